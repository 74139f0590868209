// gmslab core/control: the linear plant of a scenario for the root-locus design.
//
// Force u [N] -> position x [m] of the mass:  G(s) = 1 / (m s^2 + c_eff s + k_eff)   [m/N]
//   presliding:    k_eff = k + sum k_i (+ sigma0),        c_eff = c + sum sigma_i (+ sigma1) + sigma2
//                  (all friction elements stick and act as springs with micro-damping)
//   gross sliding: k_eff = k,  c_eff = c + dF_ss/dv at the operating velocity v0
//                  (the local Stribeck slope plus sigma2; negative when the Stribeck curve falls)
// Keys read from the friction model when present: column "k", "sigma"; scalars "sigma0",
// "sigma1", "sigma2". Throws InputError for v0 <= 0 or a scenario whose plant is invalid.
#pragma once

#include <string>

#include "core/control/transfer_function.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab::control {

enum class Regime { Presliding, Sliding };
const char* to_string(Regime r);
Regime regime_from_string(const std::string& s);  // "presliding" | "sliding"; throws InputError

struct LinearPlant {
  Regime regime = Regime::Presliding;
  double mass = 1.0;       // m [kg]
  double stiffness = 0.0;  // k_eff [N/m]
  double damping = 0.0;    // c_eff [N s/m]
  double velocity = 0.0;   // v0 of the sliding regime [m/s] (0 for presliding)
  TransferFunction g;      // 1 / (m s^2 + c_eff s + k_eff)  [m/N]
};

// Default operating velocity of the sliding regime: 10 Vs when the model has Vs, else 0.01 m/s.
double default_sliding_velocity(const ModelParams& friction);
LinearPlant linear_plant(const Scenario& s, Regime r, double sliding_velocity = 0.0);

}  // namespace gmslab::control
