// Random closed loops with friction for the periodic-orbit checks
// (tests/control/limit_cycles_test.cpp) and the study (`gmslab_study cycles`,
// bench/study/ident_study.cpp): each registry model at its defaults in turn, PI / PID / lead (no
// integrator) compensators, one-body and two-body plants, continuous and sampled controllers. The
// long simulation's settled cycle is measured independently of the orbit solver (half peak-to-peak
// and mean spacing of upward mid-level crossings over the last 40 % of the run, steady when the
// last fifth has the same amplitude within 2 % as the whole window).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/control/limit_cycles.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/friction/model.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab::cycles_study {

using namespace gmslab::control;

struct RandomLoop {
  ClosedLoop loop;
  std::string model, controller, plant;  // labels
  bool sampled = false;
};

enum class SimState { Hunting, Rest, Unsettled, Diverged };
struct SimCycle {
  SimState state = SimState::Rest;
  double amplitude = 0.0, period = 0.0;
};

inline const char* to_string(SimState s) {
  switch (s) {
    case SimState::Hunting:
      return "hunts";
    case SimState::Rest:
      return "rest";
    case SimState::Unsettled:
      return "unsettled";
    case SimState::Diverged:
      return "diverged";
  }
  return "?";
}

// The settled cycle over the last 40 % of the trace.
inline SimCycle measure_cycle(const LoopTrace& tr) {
  SimCycle m;
  const std::size_t n = tr.t.size(),
                    i0 = static_cast<std::size_t>(0.6 * static_cast<double>(n - 1));
  const std::size_t i4 = static_cast<std::size_t>(0.92 * static_cast<double>(n - 1));
  double lo = 1e300, hi = -1e300, lo4 = 1e300, hi4 = -1e300;
  for (std::size_t i = i0; i < n; ++i) {
    lo = std::min(lo, tr.x[i]), hi = std::max(hi, tr.x[i]);
    if (i >= i4) lo4 = std::min(lo4, tr.x[i]), hi4 = std::max(hi4, tr.x[i]);
  }
  const double amp = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
  if (!(amp < 1.0)) {  // beyond a metre: growing without bound
    m.state = SimState::Diverged;
    return m;
  }
  std::vector<double> ups;
  bool below = tr.x[i0] < mid;
  for (std::size_t i = i0 + 1; i < n; ++i) {
    if (below && tr.x[i] > mid + 0.25 * amp)
      ups.push_back(tr.t[i]), below = false;
    else if (!below && tr.x[i] < mid - 0.25 * amp)
      below = true;
  }
  // At rest: no motion beyond 1e-4 of the set point (1e-6 m) over the window.
  if (amp < 1e-4 * std::abs(tr.r.back()) || ups.size() < 4) {
    m.state = amp < 1e-4 * std::abs(tr.r.back()) ? SimState::Rest : SimState::Unsettled;
    return m;
  }
  // Steady: the last fifth and the first fifth of the window with the window's amplitude within 2
  // %.
  double lo1 = 1e300, hi1 = -1e300;
  for (std::size_t i = i0; i < i0 + (n - i4); ++i)
    lo1 = std::min(lo1, tr.x[i]), hi1 = std::max(hi1, tr.x[i]);
  const bool steady = std::abs(0.5 * (hi4 - lo4) - amp) <= 0.02 * amp &&
                      std::abs(0.5 * (hi1 - lo1) - amp) <= 0.02 * amp;
  m.state = steady ? SimState::Hunting : SimState::Unsettled;
  m.amplitude = amp;
  m.period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
  return m;
}

// Loop number `seed`: model = registry[seed % models], controller = (seed / models) % 3 (PI, PID,
// lead), two-body plant for every third draw (by seed / (3 models)), sampled for odd draws of the
// rng; m in [0.5, 5] kg, c = [0.5, 2] m z, Kc in [300, 3000] m, z in [2, 8] rad/s.
inline RandomLoop draw_loop(unsigned seed) {
  const auto& reg = model_registry();
  const std::size_t nm = reg.size();
  std::mt19937 rng(seed * 7919u + 17u);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const auto between = [&](double a, double b) { return a + (b - a) * u01(rng); };
  RandomLoop r;
  r.model = std::string(reg[seed % nm].tag);
  const int type = static_cast<int>((seed / nm) % 3);
  const bool two_body = (seed / (3 * nm)) % 3 == 2;
  r.sampled = u01(rng) < 0.5;
  const double m = std::exp(between(std::log(0.5), std::log(5.0)));
  const double z = between(2.0, 8.0), Kc = between(300.0, 3000.0) * m;
  const double c = between(0.5, 2.0) * m * z;
  LoopConfig& cfg = r.loop.config;
  cfg.reference = Signal::constant(0.01);
  if (type == 0)
    cfg.C = LeadCompensator{Kc, z, 0.0}, r.controller = "PI";
  else if (type == 1)
    cfg.C = LeadCompensator{Kc, 4.0 * z, 40.0 * z, Section{z, 0.0}}, r.controller = "PID";
  else
    cfg.C = LeadCompensator{Kc, z, 10.0 * z}, r.controller = "lead";
  ModelParams fr = model_info(r.model).defaults();
  Scenario& s = r.loop.scenario;
  s.plant = {m, 0.0, c};
  s.friction = fr;
  double limit = 0.0;
  if (two_body) {
    // Motor (m, its friction and damper to ground, the drive) and a load of 0.2-1 m on a shaft.
    const double ml = between(0.2, 1.0) * m, ks = between(2e4, 2e5) * m;
    AssemblyScenario a;
    a.plant.bodies = {{"motor", m}, {"load", ml}};
    a.plant.springs = {{"shaft", 0, 1, ks}};
    a.plant.dampers = {{"damper", 0, kGround, c},
                       {"shaft_loss", 0, 1, 0.05 * 2.0 * std::sqrt(ks * ml)}};
    a.plant.contacts = {{"friction", 0, kGround, fr}};
    DrivePart d;
    d.name = "motor_drive";
    d.kind = DrivePart::Kind::Force;
    d.body = 0;
    a.plant.drives = {d};
    a.run.dt = 1e-5;
    r.loop.assembly = a;
    r.loop.port.drive = 0, r.loop.port.body = 0, r.loop.port.drive_name = "motor_drive",
    r.loop.port.output = "x.motor";
    limit = assembly_loop_dt_limit(a.plant, 0, Kc);
    r.plant = "two-body";
  } else {
    limit = 2.0 / std::sqrt((stuck_stiffness(fr) + Kc) / m);
    r.plant = "one-body";
  }
  cfg.dt = std::clamp(0.05 * limit, 1e-5, 5e-4);
  cfg.sample_time = r.sampled ? cfg.dt * std::round(between(0.5e-3, 2e-3) / cfg.dt) : 0.0;
  return r;
}

struct CaseResult {
  RandomLoop loop;
  SimCycle sim;
  OrbitReport orbits;
  const PeriodicOrbit* orbit = nullptr;  // the stable one (into orbits)
  bool agree = false;  // hunting: a stable orbit within the tolerances; rest: no stable orbit
  bool false_negative = false, false_positive = false;
  bool micro = false;  // at rest, with a stable orbit below the resolution of "at rest"
  double sim_seconds = 0.0;
};

// The long simulation (60 s, or 40 orbit periods up to 200 s; 300 s when that did not settle)
// against find_orbits.
inline CaseResult run_case(unsigned seed, double amp_tol = 0.05, double period_tol = 0.05) {
  CaseResult c;
  c.loop = draw_loop(seed);
  const ClosedLoop& L = c.loop.loop;
  try {
    c.orbits = find_orbits(L);
  } catch (const Error& e) {
    c.orbits.not_found = e.what();
  }
  c.orbit = c.orbits.stable();
  LoopConfig cfg = L.config;
  cfg.duration = c.orbit ? std::clamp(40.0 * c.orbit->period, 60.0, 200.0) : 60.0;
  cfg.record_every = std::max(1, static_cast<int>(std::llround(1e-3 / cfg.dt)));
  try {
    c.sim = measure_cycle(L.assembly ? simulate_loop(*L.assembly, L.port, cfg)
                                     : simulate_loop(L.scenario, cfg));
    if (c.sim.state == SimState::Unsettled && cfg.duration < 300.0) {  // a slow transient: 300 s
      cfg.duration = 300.0;
      c.sim = measure_cycle(L.assembly ? simulate_loop(*L.assembly, L.port, cfg)
                                       : simulate_loop(L.scenario, cfg));
    }
  } catch (const SimulationError&) {
    c.sim.state = SimState::Diverged;
  }
  if (c.sim.state == SimState::Hunting) {
    c.agree = c.orbit &&
              std::abs(c.orbit->amplitude - c.sim.amplitude) <= amp_tol * c.sim.amplitude &&
              std::abs(c.orbit->period - c.sim.period) <= period_tol * c.sim.period;
    c.false_negative = !c.agree;
  } else if (c.sim.state == SimState::Rest) {
    // At rest within the measurement's resolution (1e-4 of the set point): a stable orbit smaller
    // than that (a micro-cycle) is no hunting either.
    c.micro = c.orbit && c.orbit->amplitude < 1e-4 * std::abs(L.config.reference(0.0));
    c.agree = c.orbit == nullptr || c.micro;
    c.false_positive = !c.agree;
  }
  return c;
}

inline void print_header() {
  std::printf("%-6s %-16s %-5s %-8s %-3s | %-9s %9s %8s | %9s %8s %6s %5s %s\n", "seed", "model",
              "ctrl", "plant", "T", "sim", "sim mm", "sim s", "orbit mm", "orbit s", "|mu|",
              "evals", "verdict");
}
inline void print_case(unsigned seed, const CaseResult& c) {
  const PeriodicOrbit* o = c.orbit;
  const char* verdict = c.false_negative   ? "FALSE NEGATIVE"
                        : c.false_positive ? "FALSE POSITIVE"
                        : c.micro          ? "ok (micro-cycle)"
                        : c.agree          ? "ok"
                                           : "excluded";
  std::printf("%-6u %-16s %-5s %-8s %-3s | %-9s %9.4f %8.4f | %9.4f %8.4f %6.3f %5d %s\n", seed,
              c.loop.model.c_str(), c.loop.controller.c_str(), c.loop.plant.c_str(),
              c.loop.sampled ? "yes" : "no", to_string(c.sim.state), c.sim.amplitude * 1e3,
              c.sim.period, o ? o->amplitude * 1e3 : NAN, o ? o->period : NAN,
              o && !o->multipliers.empty() ? std::abs(o->multipliers.front()) : NAN,
              c.orbits.map_evaluations, verdict);
}

}  // namespace gmslab::cycles_study
