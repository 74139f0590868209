// gmslab core: a scenario = friction model + plant + drive + run settings. One preset file each.
//
// Plant: a mass m on a frictional surface, tied to ground by a spring k and a damper c:
//   m x'' = F_drive(t, x, v) - k x - c v - F_f
// Drives:
//   displacement  the body's position x(t) is prescribed (friction alone; hysteresis curves)
//   velocity      the body's velocity v(t) is prescribed, x integrated (frictional lag)
//   force         an external force F(t) acts on the mass
//   pull          a point at position x_p(t) pulls the mass through a spring k_p and damper c_p
//                 (the seed's Fig. 3: x_p = v_p t), F_drive = k_p (x_p - x) + c_p (x_p' - v)
#pragma once

#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/sim/signal.hpp"

namespace gmslab {

struct Plant {
  double mass = 1.0;    // m [kg], > 0
  double spring = 0.0;  // k to ground [N/m], >= 0
  double damper = 0.0;  // c to ground [N s/m], >= 0
  bool operator==(const Plant&) const = default;
};

struct Drive {
  enum class Kind { Displacement, Velocity, Force, Pull };
  Kind kind = Kind::Force;
  Signal signal;             // x(t) [m], v(t) [m/s], F(t) [N] or x_p(t) [m], by kind
  double pull_spring = 0.0;  // k_p [N/m] (pull only)
  double pull_damper = 0.0;  // c_p [N s/m] (pull only)
  bool operator==(const Drive&) const = default;
};

struct RunSettings {
  double dt = 1e-5;        // integration step [s]
  double duration = 1.0;   // simulated time [s]
  int record_every = 1;    // keep every n-th step in the trace
  bool operator==(const RunSettings&) const = default;
};

struct Scenario {
  std::string name;         // short title
  std::string description;  // what it shows
  ModelParams friction;
  Plant plant;
  Drive drive;
  RunSettings run;
  bool operator==(const Scenario&) const = default;
};

const char* to_string(Drive::Kind k);
// Appends the problems of the run settings, each naming its key ("run.dt: must be in (0, 1] s"):
// dt in (0, 1] s, duration in (0, 1e6] s, record_every >= 1, and - when `bad` is still empty - at
// most 1e10 steps. The engine's validation (check_scenario, AssemblySimulation) ends with it.
void append_run_problems(const RunSettings& r, std::vector<std::string>& bad);
// Throws InputError "invalid scenario 'NAME':" listing `bad` one per line; nothing when empty.
void throw_if_invalid(const std::string& name, const std::vector<std::string>& bad);
// Largest step that resolves the stiffest mode of the plant with the friction elements stuck:
// 2 / sqrt((k + k_p + sum k_i) / m) for mass-driven kinds, +inf for prescribed motion.
double stability_limit_dt(const Scenario& s);

}  // namespace gmslab
