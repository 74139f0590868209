// gmslab core/control: the loop in discrete time (controller sampled at T, plant held by a
// zero-order hold), and its frequency response up to the Nyquist frequency pi / T.
//
//   zoh(G, T):    G(z) = (1 - z^-1) Z{G(s)/s}: the plant in controllable canonical form,
//                 Ad = e^{A T}, Bd = int_0^T e^{A t} dt B; den(z) = prod (z - e^{p_i T}),
//                 num(z) = det(zI - Ad + Bd C) - det(zI - Ad) + D det(zI - Ad)
//   tustin(C, T): s = (2/T)(z - 1)/(z + 1) (the loop simulation's controller)
//   w plane:      z = (1 + w T/2)/(1 - w T/2) maps the unit circle onto the imaginary axis
//                 (z = e^{j omega T} <-> w = j (2/T) tan(omega T / 2)) and its inside onto the left
//                 half plane, so the continuous machinery (frequency.hpp: margins as polynomial
//                 roots, the Nyquist count Z = N + P) applies exactly; frequencies map back by
//                 omega = (2/T) atan(nu T / 2).
// Units: T in s; omega in rad/s, up to pi / T.
#pragma once

#include "core/control/frequency.hpp"
#include "core/control/linear_response.hpp"
#include "core/control/root_locus.hpp"

namespace gmslab::control {

// Polynomials in z (ascending powers). Throw InputError for T <= 0 or an improper G / C.
TransferFunction zoh(const TransferFunction& G, double T);
TransferFunction tustin(const TransferFunction& C, double T);
TransferFunction to_w_plane(const TransferFunction& Lz, double T);

struct DiscreteFrequencyReport {
  double T = 0.0;                 // [s]
  double nyquist_frequency = 0.0;  // pi / T [rad/s]
  Bode open;                       // L(e^{j omega T}) for omega up to pi / T
  Margins margins;                 // crossovers in omega [rad/s]
  Nyquist nyquist;                 // of the w-plane image: P = poles outside the unit circle,
                                   // Z = closed-loop poles outside it
  std::vector<cplx> closed_loop_poles;  // roots of den + num in z (drawn with the unit circle)
};
DiscreteFrequencyReport discrete_frequency_response(const TransferFunction& Lz, double T, int points = 400);

// The root locus in z of den(z) + k num(z) = 0 (Lz = num/den, k >= 0), e.g. the sampled loop
// Tustin(Gc / Kc) ZOH(G) in the controller gain k = Kc. Stable: every root inside the unit circle.
//   unit-circle crossings: the imaginary-axis crossings of the w-plane image (z = e^{j omega T} <->
//     w = j (2/T) tan(omega T/2), same gain) and z = -1 where k = -den(-1)/num(-1) >= 0 (w = inf);
//     each z = e^{j omega T} with omega in [0, pi/T] (its conjugate is a crossing too); an
//     open-loop pole on the circle (z = 1 for a pole at s = 0) is the locus's start, not a crossing;
//   stable_gains: the gain intervals between successive crossing gains (and 0, +inf) whose
//     midpoint (geometric; 10 x the last for the unbounded one) has every closed-loop root inside;
//   view (unless given): the unit circle, the open-loop poles and the zeros within |z| < 10, with a
//     30 % margin, widened to 1.6 x its height (a 16:10 canvas); the crossing gains and
//     `extra_gains` are sampled exactly.
struct UnitCircleCrossing {
  cplx z;              // on |z| = 1 (Im z >= 0)
  double omega = 0.0;  // arg z / T [rad/s]
  double k = 0.0;      // gain
};
struct ZLocus {
  double T = 0.0;  // [s]
  RootLocus locus;  // in z (its asymptotes and imaginary-axis crossings are those of the z polynomial)
  std::vector<UnitCircleCrossing> crossings;  // sorted by gain
  std::vector<std::pair<double, double>> stable_gains;  // [k_lo, k_hi] (k_hi may be +inf)
};
// Throws InputError for T <= 0 or an improper / zero Lz.
ZLocus z_root_locus(const TransferFunction& Lz, double T, const LocusOptions& opt = {});
// The sampled loop per unit controller gain, Tustin((s + z)/(s + p)) ZOH(G) (the compensator
// Kc (s + z)/(s + p); p = 0: the PI). The loop is Kc times it; its z-plane locus is in Kc.
TransferFunction sampled_loop(const TransferFunction& G, double z, double p, double T);
// The same for any compensator: Tustin(prod (s + z_i)/(s + p_i)) ZOH(G) (one section: as above).
TransferFunction sampled_loop(const TransferFunction& G, const LeadCompensator& c, double T);
// Every root of den + k num strictly inside the unit circle (|z| < 1 - 1e-12).
bool roots_inside_unit_circle(const TransferFunction& Lz, double k);

}  // namespace gmslab::control
