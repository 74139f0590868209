// Periodic orbits of the closed loop with friction (core/control/limit_cycles.hpp) against the long
// simulation of the same loop (core/control/loop_simulation.hpp), whose settled cycle is measured
// independently (tests/control/random_loops.hpp: half peak-to-peak and the spacing of upward
// mid-level crossings over the last 40 % of a 60-200 s run).
#include "core/control/limit_cycles.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/cli/cli.hpp"
#include "core/control/design_report.hpp"
#include "core/io/atomic_file.hpp"
#include "tests/control/random_loops.hpp"
#include "tests/core/run_cli.hpp"

using namespace gmslab;
using namespace gmslab::control;
using namespace gmslab::cycles_study;

namespace {
// The issue's loop: mass 1 kg, damper 3 N s/m, PI 1000 (s + 5)/s, the model at its defaults, at the
// step the design job takes (5 % of the stability limit with the presliding stiffness and Kc).
ClosedLoop issue_loop(const char* model, double gain_scale = 1.0) {
  ClosedLoop L;
  L.scenario.plant = {1.0, 0.0, 3.0};
  L.scenario.friction = model_info(model).defaults();
  L.config.C = LeadCompensator{1000.0 * gain_scale, 5.0, 0.0};
  L.config.reference = Signal::constant(0.01);
  L.config.dt =
      std::clamp(0.05 * 2.0 / std::sqrt(stuck_stiffness(L.scenario.friction) + 1000.0), 1e-5, 5e-4);
  return L;
}

SimCycle long_simulation(const ClosedLoop& L, double duration) {
  LoopConfig cfg = L.config;
  cfg.duration = duration;
  cfg.record_every = std::max(1, static_cast<int>(std::llround(1e-3 / cfg.dt)));
  return measure_cycle(simulate_loop(L.scenario, cfg));
}
}  // namespace

// The issue's four loops (GMS, LuGre, Stribeck, Coulomb): a stable orbit within 5 % of the
// simulated cycle in amplitude and period, every multiplier inside the unit circle.
TEST(LimitCycles, IssueLoopsHaveTheSimulatedCycleAsAStableOrbit) {
  for (const char* model : {"gms", "lugre", "stribeck", "coulomb"}) {
    const ClosedLoop L = issue_loop(model);
    const OrbitReport r = find_orbits(L);
    const SimCycle sim = long_simulation(L, 60.0);
    ASSERT_EQ(sim.state, SimState::Hunting) << model;
    const PeriodicOrbit* o = r.stable();
    ASSERT_NE(o, nullptr) << model << ": " << r.not_found;
    std::printf(
        "%-9s orbit %.4f mm %.4f s stick %.2f |mu|max %.3f (%zu multipliers, %d map runs) | "
        "simulated %.4f mm %.4f s\n",
        model, o->amplitude * 1e3, o->period, o->stick_fraction, std::abs(o->multipliers.front()),
        o->multipliers.size(), r.map_evaluations, sim.amplitude * 1e3, sim.period);
    EXPECT_NEAR(o->amplitude, sim.amplitude, 0.05 * sim.amplitude) << model;
    EXPECT_NEAR(o->period, sim.period, 0.05 * sim.period) << model;
    for (const auto& mu : o->multipliers) EXPECT_LT(std::abs(mu), 1.0) << model;
    EXPECT_GT(o->stick_fraction, 0.0) << model;
    EXPECT_LT(o->stick_fraction, 1.0) << model;
  }
}

// Random loops (tests/control/random_loops.hpp; every registry model, PI / PID / lead, one- and
// two-body plants, continuous and sampled) from seeds disjoint from the tuning range 1-240 and from
// the study's 5000-5239: where the long simulation hunts, a stable orbit within 5 % in amplitude
// and period; where it comes to rest, no stable orbit (above the rest resolution). Every case is
// counted; GMSLAB_CYCLES_SEED / GMSLAB_CYCLES_N draw others.
TEST(LimitCycles, RandomLoopsAgreeWithTheirLongSimulation) {
  const char* seed_env = std::getenv("GMSLAB_CYCLES_SEED");
  const char* n_env = std::getenv("GMSLAB_CYCLES_N");
  const unsigned seed0 =
      seed_env ? static_cast<unsigned>(std::strtoul(seed_env, nullptr, 10)) : 100000u;
  const int n = n_env ? std::atoi(n_env) : 48;
  int hunts = 0, rest = 0, excluded = 0, fn = 0, fp = 0, agree = 0;
  print_header();
  for (int i = 0; i < n; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    const CaseResult c = run_case(seed);
    print_case(seed, c);
    hunts += c.sim.state == SimState::Hunting;
    rest += c.sim.state == SimState::Rest;
    excluded += c.sim.state == SimState::Unsettled || c.sim.state == SimState::Diverged;
    fn += c.false_negative, fp += c.false_positive, agree += c.agree;
    EXPECT_FALSE(c.false_negative) << "seed " << seed << ": " << c.orbits.not_found;
    EXPECT_FALSE(c.false_positive) << "seed " << seed;
  }
  std::printf(
      "loops %d: hunting %d, at rest %d, excluded %d; agree %d, false negatives %d, false "
      "positives %d\n",
      n, hunts, rest, excluded, agree, fn, fp);
  EXPECT_EQ(hunts + rest + excluded, n);
  if (!seed_env) {
    EXPECT_GE(hunts, n / 4);  // the draw exercises hunting loops
    EXPECT_GE(rest, n / 4);   // and loops at rest
  }
}

// A loop that comes to rest (a lead without integrator): no orbit, and the report says which method
// searched what and why nothing was found.
TEST(LimitCycles, NotFoundSaysWhichMethodSearchedWhat) {
  ClosedLoop L = issue_loop("stribeck");
  L.config.C = LeadCompensator{1000.0, 5.0, 200.0};
  const OrbitReport r = find_orbits(L);
  EXPECT_TRUE(r.orbits.empty());
  EXPECT_EQ(r.stable(), nullptr);
  EXPECT_NE(r.method.find("shooting"), std::string::npos) << r.method;
  EXPECT_NE(r.method.find("simulation from rest"), std::string::npos) << r.method;
  EXPECT_NE(r.not_found.find("settles"), std::string::npos) << r.not_found;
  EXPECT_EQ(long_simulation(L, 30.0).state, SimState::Rest);
  // A ramp reference has no orbit around a set point: an error naming it.
  L.config.reference = Signal::ramp(0.0, 0.01);
  EXPECT_THROW(find_orbits(L), InputError);
}

// The hunting map: at each gain scale where continuation found an orbit, the long simulation of the
// loop with that gain hunts with it (5 %).
TEST(LimitCycles, HuntingMapOrbitsAreTheSimulatedCyclesAtTheirGain) {
  const ClosedLoop L = issue_loop("coulomb");
  const OrbitReport r = find_orbits(L);
  ASSERT_NE(r.stable(), nullptr);
  const HuntingMap m = hunting_map(L, *r.stable(), 0.5, 2.0, 5);
  ASSERT_EQ(m.points.size(), 5u);
  int checked = 0;
  for (const HuntingMapPoint& p : m.points) {
    if (!p.orbit) continue;
    const SimCycle sim = long_simulation(issue_loop("coulomb", p.gain_scale), 60.0);
    std::printf("gain x%.3f: orbit %.4f mm %.4f s %s | simulated %s %.4f mm %.4f s\n", p.gain_scale,
                p.orbit->amplitude * 1e3, p.orbit->period, p.orbit->stable ? "stable" : "unstable",
                to_string(sim.state), sim.amplitude * 1e3, sim.period);
    ASSERT_EQ(sim.state, SimState::Hunting);
    EXPECT_NEAR(p.orbit->amplitude, sim.amplitude, 0.05 * sim.amplitude);
    EXPECT_NEAR(p.orbit->period, sim.period, 0.05 * sim.period);
    ++checked;
  }
  EXPECT_GE(checked, 4) << m.note;
  EXPECT_THROW(hunting_map(L, *r.stable(), 2.0, 1.0, 5), InputError);
}

// gmslab cycles on the issue's GMS loop: the JSON's keys, the orbit against the simulation it
// reports, and bad controller input as exit code 2.
TEST(LimitCycles, CyclesCommandWritesOrbitsSimulationAndMap) {
  const auto tmp = std::filesystem::temp_directory_path();
  const std::string out = (tmp / "gmslab_cycles_test.json").string(),
                    preset = (tmp / "gmslab_cycles_loop.json").string();
  std::filesystem::remove(out);
  // The Fig. 4 preset's mass and GMS friction with the issue's damper (3 N s/m), no spring.
  auto p = nlohmann::json::parse(
      gmslab::read_file(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"));
  p["plant"] = {{"mass", 1.0}, {"spring", 0.0}, {"damper", 3.0}};
  gmslab::write_file_atomic(preset, p.dump());
  ASSERT_EQ(gmslab::test_util::run_cli({"cycles", preset, "--controller-num", "1000 5000",
                                        "--controller-den", "1 0", "--gain-scale", "0.5:2:4",
                                        "--json", out}),
            0);
  const auto j = nlohmann::json::parse(gmslab::read_file(out));
  for (const char* key :
       {"orbits", "simulation", "map", "method", "not_found", "describing_function"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["map"].size(), 4u);
  for (const char* key : {"hunting", "amplitude_m", "period_s"})
    EXPECT_TRUE(j["simulation"].contains(key)) << key;
  if (j["simulation"]["hunting"].get<bool>()) {
    ASSERT_FALSE(j["orbits"].empty());
    const auto& o = j["orbits"][0];
    for (const char* key : {"amplitude_m", "period_s", "stable", "stick_fraction", "multipliers"})
      EXPECT_TRUE(o.contains(key)) << key;
    EXPECT_NEAR(o["amplitude_m"].get<double>(), j["simulation"]["amplitude_m"].get<double>(),
                0.05 * j["simulation"]["amplitude_m"].get<double>());
    EXPECT_NEAR(o["period_s"].get<double>(), j["simulation"]["period_s"].get<double>(),
                0.05 * j["simulation"]["period_s"].get<double>());
  }
  // A numerator of another degree than the denominator, complex zeros, a bad gain grid: exit 2.
  for (const auto& [num, den, grid] :
       std::vector<std::array<std::string, 3>>{{"1 2 3", "1 0", "0.5:2:4"},
                                               {"1 2 5", "1 3 0", "0.5:2:4"},
                                               {"1000 5000", "1 0", "2:1:3"}})
    EXPECT_EQ(
        gmslab::test_util::run_cli({"cycles", preset, "--controller-num", num, "--controller-den",
                                    den, "--gain-scale", grid, "--json", out}),
        2)
        << num << " / " << den << " " << grid;
}
