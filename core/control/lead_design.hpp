// gmslab core/control: phase-lead design with the largest reachable error constant
// (method and worked examples: docs/references.md).
//
// Plant G(s) = K0 N(s) / (s^n D(s)), N(0) = D(0) = 1, K0 > 0; unity feedback; compensator
// Gc(s) = Kc (s + z) / (s + p), 0 < z < p. Error constant K = Kc (z / p) K0 (Kp, Kv, Ka: n = 0, 1, 2).
// Desired dominant root s_d = -zeta wn + j wn sqrt(1 - zeta^2), beta = arccos(zeta).
// Required lead phi = -pi - arg G(s_d), reduced to (-pi, pi]. Angles from -z, -p to s_d:
// theta_z - theta_p = phi, 0 < theta_p < theta_z <= pi - beta.
//   applicable iff 0 < phi < pi - beta
//   z = wn sin(theta_z + beta) / sin(theta_z),  p = wn sin(theta_p + beta) / sin(theta_p)
//   Kc = sin(theta_z) / (sin(theta_p) |G(s_d)|)
//   K(theta_z) = M sin(theta_z + beta) / sin(theta_z - phi + beta),  M = K0 / |G(s_d)|
//   K_max = M sin(phi + beta) / sin(beta)  (supremum, p -> inf: PD Kd (s + z_PD),
//           z_PD = wn sin(phi + beta) / sin(phi))
//   design for K < K_max: u = arg(K e^{j phi} - M), theta_z = u - beta, theta_p = theta_z - phi
// Relocation when K >= K_max: bisection on K_max(s_d) = K (1 + margin) along keep zeta (raise wn),
// keep zeta wn (raise the damped frequency wd), keep wn (lower zeta).
// Units: s, wn, z, p in rad/s; zeta and angles dimensionless / rad; Kc in the plant's inverse
// gain units; K in the units of lim s^n Gc G (1/s^n).
// Throws InputError for zeta outside (0, 1), wn <= 0, K <= 0, max_ratio <= 1, an improper plant,
// a zero at the origin, or K0 <= 0.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/control/linear_response.hpp"
#include "core/control/transfer_function.hpp"

namespace gmslab::control {

struct DominantRoot {
  double zeta = 0.5;  // damping ratio [-], in (0, 1)
  double wn = 1.0;    // natural frequency [rad/s], > 0
  cplx s() const;     // -zeta wn + j wn sqrt(1 - zeta^2)
  double beta() const;  // arccos(zeta) [rad]
};

// What a single lead can do at s_d.
struct LeadLimits {
  cplx s_d;
  double beta = 0.0;       // [rad]
  double phi = 0.0;        // required lead [rad]
  bool applicable = false;  // 0 < phi < pi - beta
  std::string reason;       // why not, when not applicable
  double G_abs = 0.0;       // |G(s_d)|
  double M = 0.0;           // K0 / |G(s_d)|
  double K_max = 0.0;       // supremum of the error constant (NaN when not applicable)
  double pd_z = 0.0, pd_Kd = 0.0;  // the PD limit Kd (s + z_PD)
};

struct Dominance {
  bool dominant = false;  // every other pole is fast (>= 5x) or nearly cancelled (residue <= 10%)
  struct Other {
    cplx pole;
    double speed_ratio = 0.0;  // Re(pole) / Re(s_d)
    double residue = 0.0;      // |step-response residue| / final value (x2 for a complex pair)
  };
  std::vector<Other> others;
  std::vector<std::string> notes;  // human-readable warnings (slow poles, a zero near s_d that
                                   // adds overshoot, p > 50 wn, instability)
};

struct LeadDesign {
  double z = 0.0, p = 0.0, Kc = 0.0;   // Gc = Kc (s + z) / (s + p)
  double K = 0.0;                      // error constant reached
  double theta_z = 0.0, theta_p = 0.0;  // [rad]
  std::vector<cplx> closed_loop_poles;  // roots of (s + p) den + Kc (s + z) num
  Dominance dominance;
};

struct Relocation {
  std::string path;    // "keep_zeta", "keep_zeta_wn", "keep_wn"
  bool found = false;
  DominantRoot root;   // new dominant root (found)
  double K_max = 0.0;  // K_max at the new root
  LeadDesign design;   // the design for K at the new root (found)
  std::string reason;  // why no point of the path reaches the target (not found)
  double peak_K = 0.0;  // largest K_max seen along the path
  DominantRoot peak_root;
};

struct LeadOptions {
  double max_ratio = 20.0;  // bound on p / z for the usable maximum [-], > 1
  double margin = 0.1;      // relocation target K (1 + margin) [-], > 0
};

struct LeadReport {
  PlantType type;
  DominantRoot root;
  LeadLimits limits;
  double K_max_usable = 0.0;            // largest K with p/z <= max_ratio (NaN: none)
  std::optional<LeadDesign> usable_design;
  std::optional<double> K_des;
  std::optional<LeadDesign> design;     // when K_des < K_max
  bool within_max_ratio = true;         // design's p/z <= max_ratio
  std::vector<Relocation> relocations;  // when K_des is given and not reachable
};

// The dominant roots' natural frequency [rad/s]: far beyond any mechanism, and inside it the
// design's polynomials (wn^2 times the plant's coefficients) stay well within doubles.
inline constexpr double kMinWn = 1e-12, kMaxWn = 1e12;
void check_root(const DominantRoot& d);  // throws InputError for zeta in (0, 1), wn in [kMinWn, kMaxWn]
LeadLimits lead_limits(const TransferFunction& g, const DominantRoot& d);
// The design whose zero is seen from s_d under theta_z (phi < theta_z < pi - beta).
LeadDesign design_at_zero_angle(const TransferFunction& g, const DominantRoot& d, double theta_z);
// Closed form for K_des < K_max (throws InputError if not reachable or not applicable).
LeadDesign design_for_constant(const TransferFunction& g, const DominantRoot& d, double K_des);
// Independent check: the characteristic equation at s_d solved as a 2x2 real linear system in
// (Kc, Kc z), with p = Kc z K0 / K_des. Returns z, p, Kc (closed_loop_poles filled).
LeadDesign design_by_linear_system(const TransferFunction& g, const DominantRoot& d, double K_des);
// Largest K with p / z <= max_ratio (NaN when no lead at s_d satisfies the bound).
double usable_max(const TransferFunction& g, const DominantRoot& d, double max_ratio,
                  std::optional<LeadDesign>* at = nullptr);
std::vector<Relocation> relocate(const TransferFunction& g, const DominantRoot& d, double K_des,
                                 double margin);
Dominance check_dominance(const TransferFunction& g, const DominantRoot& d, double Kc, double z,
                          double p, const std::vector<cplx>& poles);
// The same for a compensator of one or two sections (one: identical to the above; two: the notes
// on the zero / pole are about the first section, the residues use the whole product).
Dominance check_dominance(const TransferFunction& g, const DominantRoot& d, const LeadCompensator& c,
                          const std::vector<cplx>& poles);
// The relocation to use: the first found whose s_d dominates, else the first found with a stable
// closed loop, else the first found; nullptr when no path reaches K.
const Relocation* best_relocation(const LeadReport& r);
// Everything at once (the CLI and the design view call this).
LeadReport lead_design(const TransferFunction& g, const DominantRoot& d,
                       std::optional<double> K_des, const LeadOptions& opt = {});

}  // namespace gmslab::control
