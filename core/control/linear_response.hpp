// gmslab core/control: lead compensator as a transfer function, the unity-feedback closed loop
// and its step response (exact zero-order-hold discretisation of a state-space realisation).
//
//   Gc(s) = Kc (s + z) / (s + p)                         [N/m for a force-to-position plant]
//   T(s)  = Gc G / (1 + Gc G) = Kc (s + z) num / ((s + p) den + Kc (s + z) num)
// Step response: controllable canonical realisation of T, x[k+1] = Ad x[k] + Bd u,
// [Ad Bd; 0 1] = exp([A B; 0 0] h) (Eigen's matrix exponential), y = C x + D u.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/control/transfer_function.hpp"

namespace gmslab::control {

// One first-order section (s + z) / (s + p) of a compensator [rad/s]; p = 0: an integrator.
struct Section {
  double z = 1.0;
  double p = 1.0;
};

// The compensator C(s) = Kc prod_i (s + z_i) / (s + p_i), at most two sections: the first is
// (z, p), the optional second (s + second->z) / (s + second->p) in series. One section: lead
// (z < p), lag (z > p > 0), PI (p = 0); two: lead-lag (lead, then a unity-DC lag), PID
// Kc (s + z1)(s + z2) / (s (s + p_f)) = sections (z1, 0) and (z2, p_f) (p_f: derivative filter).
struct LeadCompensator {
  LeadCompensator() = default;
  LeadCompensator(double Kc_, double z_, double p_, std::optional<Section> second_ = std::nullopt)
      : Kc(Kc_), z(z_), p(p_), second(second_) {}
  double Kc = 1.0;  // gain [N/m for a force-to-position plant]
  double z = 1.0;   // zero at -z [rad/s], > 0
  double p = 1.0;   // pole at -p [rad/s], > 0 (p = z: a pure gain; p = 0: PI, in the loop simulation)
  std::optional<Section> second;  // none: the one-section compensator
  int sections() const { return second ? 2 : 1; }
  Section section(int i) const { return i == 0 ? Section{z, p} : *second; }
  Poly num_poly() const;  // prod (s + z_i), without Kc
  Poly den_poly() const;  // prod (s + p_i)
  TransferFunction tf() const;  // Kc num_poly / den_poly
  std::vector<double> zeros() const;  // z_i (the zeros sit at -z_i) [rad/s]
  std::vector<double> poles() const;  // p_i [rad/s]
  // Kc prod z_i / p_i: the compensator's static gain (the error constant is it times K0); +inf
  // with an integrator (the type rises by one).
  double static_gain() const;
  // "Kc (s + z1)(s + z2) / ((s + p1) s)" with the numbers (%.4g), for labels.
  std::string text() const;
};
// Throws InputError (naming `who`) unless Kc > 0 and every z_i > 0, p_i >= 0, all finite.
void check_compensator(const LeadCompensator& c, const std::string& who);

TransferFunction closed_loop(const TransferFunction& g, const LeadCompensator& c);

struct StepResponse {
  std::vector<double> t;  // [s]
  std::vector<double> y;  // output for a unit step input (units of the plant output per input)
};
// Throws InputError when T is improper, t_end <= 0 or n < 2.
StepResponse step_response(const TransferFunction& T, double t_end, int n = 400);

}  // namespace gmslab::control
