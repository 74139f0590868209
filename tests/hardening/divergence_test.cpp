// Divergence detection: a run that goes unstable stops with a SimulationError naming the likely
// cause (with the numbers) instead of filling the trace with NaN; stable runs near the limit and
// the shipped presets never trip it.
#include <gtest/gtest.h>

#include <cmath>

#include "core/friction/gms.hpp"
#include "core/sim/assembly.hpp"
#include "hardening_util.hpp"

namespace gmslab::hardening {
namespace {

#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << "message: " << (msg)

// A 1 kg mass on the GMS reference set (no micro-damping), pushed by a 10 N, 2 Hz force that
// makes it slide back and forth.
Scenario sliding_mass(double dt, double damper) {
  Scenario s;
  s.name = "sliding mass";
  s.friction = GmsParams::reference(false).to_params();
  s.plant = {1.0, 0.0, damper};
  s.drive.kind = Drive::Kind::Force;
  s.drive.signal = Signal::sine(0.0, 10.0, 2.0);
  s.run = {dt, 10.0, 1};
  return s;
}

bool all_finite(const Trace& tr) {
  for (std::size_t i = 0; i < tr.size(); ++i)
    if (!std::isfinite(tr.x[i] + tr.v[i] + tr.friction[i] + tr.applied[i])) return false;
  return true;
}

TEST(Divergence, EnergyGrowthFromAStepTooLargeForTheDampingStopsTheRun) {
  // Explicit damping is stable for dt < 2 m / c. c = 2040 + sigma2 0.4 N s/m, dt = 1 ms:
  // v is multiplied by about -1.04 per step, so the energy grows by 1e34 in 1024 steps while
  // nothing is yet non-finite: the energy watch, not the NaN check, must catch it.
  const Scenario s = sliding_mass(1e-3, 2040.0);
  AssemblySimulation sim =
      one_body_simulation(s);  // passes the stiffness check: 2 / sqrt(210000) = 4.4 ms > 1 ms
  try {
    sim.run_to_end();
    FAIL() << "unstable damping not detected";
  } catch (const SimulationError& e) {
    const std::string msg = e.what();
    EXPECT_HAS(msg, "simulation diverged at t = 1.024 s: the energy of the mass and springs grew");
    EXPECT_HAS(msg, "run.dt = 0.001 s is too large for the damping: sum c = 2040.4 N s/m");
    EXPECT_HAS(msg, "on m = 1 kg needs dt < 2 m / sum c = 0.0009802 s");
  }
  EXPECT_LE(sim.time(), 1.024 + 1e-12);
  EXPECT_TRUE(all_finite(sim.one_body_trace()));  // the plot shows what happened before, no NaN
  // The same plant with a step inside the limit runs to the end.
  AssemblySimulation ok = one_body_simulation(sliding_mass(0.5e-3, 2040.0));
  EXPECT_NO_THROW(ok.run_to_end());
  EXPECT_TRUE(all_finite(ok.one_body_trace()));
}

TEST(Divergence, NonFiniteStateAfterALiveEditStopsTheRunAndNamesTheStep) {
  // A live edit raises the viscous coefficient to 1e7 N s/m (dt = 1e-5 s, m = 1 kg: c h / m =
  // 100, v multiplied by -99 per step): the state overflows to inf within ~160 steps, before the
  // next energy check (every 1024 steps), so the non-finite check must stop it.
  const Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  AssemblySimulation sim = one_body_simulation(s);
  sim.advance(1025);
  ModelParams p = s.friction;
  p.set_scalar("sigma2", 1e7);
  sim.set_friction(p);
  try {
    sim.advance(1000);
    FAIL() << "overflow not detected";
  } catch (const SimulationError& e) {
    const std::string msg = e.what();
    EXPECT_HAS(msg, "(non-finite");
    EXPECT_HAS(msg, "run.dt = 1e-05 s is too large for the damping: sum c = 1.00002e+07 N s/m");
    EXPECT_HAS(msg, "needs dt < 2 m / sum c = 1.99996e-07 s");
  }
  EXPECT_LT(sim.time(), 2048 * 1e-5);
  EXPECT_TRUE(all_finite(sim.one_body_trace()));
  // The window stays usable: undo the edit, reset, run again.
  sim.set_friction(s.friction);
  sim.reset();
  EXPECT_EQ(sim.advance(5000), 5000u);
  EXPECT_TRUE(all_finite(sim.one_body_trace()));
}

TEST(Divergence, NoFalseAlarmForEveryModelNearTheStabilityLimit) {
  // Every model, pulled through a spring (Fig. 3 set-up) with a ground spring and damper, at 60 %
  // of the stiffness limit (the most the check allows with margin): stable, so it must run
  // through. Symplectic Euler's energy wobble is largest there.
  for (const auto& info : model_registry()) {
    Scenario s;
    s.name = std::string(info.tag);
    s.friction = info.defaults();
    s.plant = {1.0, 50.0, 0.1};
    s.drive.kind = Drive::Kind::Pull;
    s.drive.signal = Signal::ramp(0.0, 0.1);
    s.drive.pull_spring = 2.0;
    s.run = {1.0, 3.0, 100};
    s.run.dt = std::min(0.6 * stability_limit_dt(s), 1e-4);
    SCOPED_TRACE(s.name + ", dt = " + std::to_string(s.run.dt));
    AssemblySimulation sim = one_body_simulation(s);
    EXPECT_NO_THROW(sim.run_to_end());
    EXPECT_TRUE(all_finite(sim.one_body_trace()));
  }
}

TEST(Divergence, ShippedPresetsRunThroughWithoutAlarm) {
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    if (read_file(e.path().string()).find("\"schema_version\": 2") != std::string::npos) continue;  // assembly_test
    SCOPED_TRACE(e.path().string());
    Scenario s = load_scenario(e.path().string());
    s.run.duration = std::min(s.run.duration, 30.0);
    s.run.record_every = std::max(s.run.record_every, 100);
    EXPECT_NO_THROW(simulate(s));
  }
}

}  // namespace
}  // namespace gmslab::hardening
