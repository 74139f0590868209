// gmslab core/control: lead compensator as a transfer function, the unity-feedback closed loop
// and its step response (exact zero-order-hold discretisation of a state-space realisation).
//
//   Gc(s) = Kc (s + z) / (s + p)                         [N/m for a force-to-position plant]
//   T(s)  = Gc G / (1 + Gc G) = Kc (s + z) num / ((s + p) den + Kc (s + z) num)
// Step response: controllable canonical realisation of T, x[k+1] = Ad x[k] + Bd u,
// [Ad Bd; 0 1] = exp([A B; 0 0] h) (Eigen's matrix exponential), y = C x + D u.
#pragma once

#include <vector>

#include "core/control/transfer_function.hpp"

namespace gmslab::control {

struct LeadCompensator {
  double Kc = 1.0;  // gain [N/m for a force-to-position plant]
  double z = 1.0;   // zero at -z [rad/s], > 0
  double p = 1.0;   // pole at -p [rad/s], > 0 (p = z: a pure gain; p = 0: PI, in the loop simulation)
  TransferFunction tf() const { return {Poly({Kc * z, Kc}), Poly({p, 1.0})}; }
};

TransferFunction closed_loop(const TransferFunction& g, const LeadCompensator& c);

struct StepResponse {
  std::vector<double> t;  // [s]
  std::vector<double> y;  // output for a unit step input (units of the plant output per input)
};
// Throws InputError when T is improper, t_end <= 0 or n < 2.
StepResponse step_response(const TransferFunction& T, double t_end, int n = 400);

}  // namespace gmslab::control
