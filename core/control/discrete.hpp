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

}  // namespace gmslab::control
