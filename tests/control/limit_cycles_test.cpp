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
  // The branch from end to end of the range (no fold on this loop), one point per step of at
  // most ln(2 / 0.5) / 4 in ln s at least.
  ASSERT_GE(m.points.size(), 5u) << m.note;
  EXPECT_NEAR(m.points.front().gain_scale, 0.5, 1e-9) << m.note;
  EXPECT_NEAR(m.points.back().gain_scale, 2.0, 1e-9) << m.note;
  EXPECT_FALSE(m.fold) << m.note;
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
  EXPECT_EQ(checked, static_cast<int>(m.points.size())) << m.note;
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
  // The map: the branch's orbits (at least one per step of ln(2 / 0.5) / 3 in ln s, both ends of
  // the range reached on this loop), each saying stable or not; the fold (none here) as null.
  EXPECT_GE(j["map"].size(), 4u);
  for (const auto& pt : j["map"]) {
    EXPECT_TRUE(pt.contains("stable"));
    EXPECT_GE(pt["gain_scale"].get<double>(), 0.5 - 1e-9);
    EXPECT_LE(pt["gain_scale"].get<double>(), 2.0 + 1e-9);
  }
  EXPECT_TRUE(j.contains("fold_gain_scale"));
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

namespace {
// The loop simulated from the state z0 for `duration` (the loop's own stepper, as simulate_loop),
// its settled cycle measured as the random-loop study measures it (measure_cycle).
SimCycle simulate_from(const ClosedLoop& L, const std::vector<double>& z0, double duration) {
  LoopConfig c = L.config;
  c.duration = duration;
  LoopStepper st = L.assembly ? loop_stepper(*L.assembly, L.port, c, duration + 1.0)
                              : loop_stepper(L.scenario, c, duration + 1.0);
  st.set_state(z0, 0);
  LoopTrace tr;
  const long long steps = std::llround(duration / c.dt),
                  every = std::max(1LL, std::llround(1e-3 / c.dt));
  try {
    for (long long k = 0; k < steps; ++k) {
      st.step();
      if (k % every == 0)
        tr.t.push_back(st.time()), tr.x.push_back(st.output()), tr.r.push_back(st.reference());
    }
  } catch (const SimulationError&) {
    return SimCycle{SimState::Diverged, 0.0, 0.0};
  }
  return measure_cycle(tr);
}
// At rest at x0 (every other state entry zero: controller, friction elements).
std::vector<double> rest_at(const ClosedLoop& L, double x0) {
  LoopConfig c = L.config;
  LoopStepper st =
      L.assembly ? loop_stepper(*L.assembly, L.port, c, 1.0) : loop_stepper(L.scenario, c, 1.0);
  std::vector<double> z(st.state().size(), 0.0);
  z[st.output_index()] = x0;
  return z;
}
ClosedLoop scaled_loop(ClosedLoop L, double g) {
  L.config.C.Kc *= g;
  return L;
}
// How many of the starts make the loop at gain scale g hunt: at rest 1, 3 and 10 mm below the set
// point, and the section states `extra` (cycles' states). Hunting: steady over the last 40 % of
// 60 s (200 s when unsettled).
int starts_that_hunt(const ClosedLoop& L0, double g, const std::vector<std::vector<double>>& extra,
                     int* unsettled) {
  const ClosedLoop L = scaled_loop(L0, g);
  const double r = L.config.reference(0.0);
  std::vector<std::vector<double>> starts = {rest_at(L, r - 1e-3), rest_at(L, r - 3e-3),
                                             rest_at(L, r - 1e-2)};
  starts.insert(starts.end(), extra.begin(), extra.end());
  int hunts = 0;
  for (const auto& z0 : starts) {
    SimCycle s = simulate_from(L, z0, 60.0);
    if (s.state == SimState::Unsettled) s = simulate_from(L, z0, 200.0);
    hunts += s.state == SimState::Hunting;
    *unsettled += s.state == SimState::Unsettled;
  }
  return hunts;
}
}  // namespace

// Folds of the hunting map against brute force. Random one-body continuous PI / PID loops
// (tests/control/random_loops.hpp, models with stiction) whose stable orbit at gain scale 0.3 (or
// else 1) is continued over 0.1-10 x that gain. At each fold: on the side of the stable branch, at
// the fold x (1 -+ 5 %) and x (1 -+ 15 %), a start hunts (a long simulation from rest 1, 3 or 10 mm
// off, or from the branch's stable orbits within a factor 1.3 of that gain, as they are and
// continued to it); on the other side none does (from rest,
// or from the states of the two orbits of the branch nearest the fold). Each unstable orbit of the
// map past a fold is genuine: displaced 10 % of the way towards the stable orbit at its gain the
// simulation settles on that cycle (5 %), displaced 10 % away it comes to rest (60 s, 200 s when
// unsettled; orbits within 1 % of the stable one's amplitude are counted, not checked). Seeds from
// 300000 (the tolerances were chosen on seeds 1-519); GMSLAB_FOLD_SEED / GMSLAB_FOLD_N draw others.
TEST(LimitCycles, FoldsAgreeWithBruteForceSimulation) {
  const char* seed_env = std::getenv("GMSLAB_FOLD_SEED");
  const char* n_env = std::getenv("GMSLAB_FOLD_N");
  const unsigned seed0 =
      seed_env ? static_cast<unsigned>(std::strtoul(seed_env, nullptr, 10)) : 300000u;
  const int n = n_env ? std::atoi(n_env) : 240;
  constexpr double kFoldTol = 0.05;
  int drawn = 0, skipped = 0, no_orbit = 0, no_fold = 0, folds = 0, fold_ok = 0, unstable = 0,
      separates = 0, no_partner = 0, no_turn = 0, at_fold = 0;
  for (int i = 0; i < n; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    const RandomLoop r = draw_loop(seed);
    ++drawn;
    if (r.controller == "lead" || r.plant == "two-body" || r.sampled || r.model == "dahl" ||
        r.model == "maxwell_slip") {
      ++skipped;  // never hunt in the study (lead, Dahl, Maxwell-slip) or slow (sampled, two-body)
      continue;
    }
    const PeriodicOrbit* start = nullptr;
    OrbitReport rep;
    double g0 = 0.0;
    for (double g : {0.3, 1.0}) {
      rep = find_orbits(scaled_loop(r.loop, g));
      if ((start = rep.stable())) {
        g0 = g;
        break;
      }
    }
    if (!start) {
      ++no_orbit;
      continue;
    }
    const ClosedLoop L = scaled_loop(r.loop, g0);
    const HuntingMap m = hunting_map(L, *start, 0.1, 10.0, 11);
    if (m.folds.empty()) {
      ++no_fold;
      continue;
    }
    for (std::size_t j = 1; j < m.points.size(); ++j) {
      const PeriodicOrbit& a = *m.points[j - 1].orbit;
      const PeriodicOrbit& b = *m.points[j].orbit;
      if (a.stable == b.stable) continue;
      const PeriodicOrbit& st = a.stable ? a : b;
      // The fold between a and b; the cycle exists on the stable point's side.
      const auto f = std::find_if(m.folds.begin(), m.folds.end(), [&](double x) {
        return x >= 0.98 * std::min(a.gain_scale, b.gain_scale) &&
               x <= 1.02 * std::max(a.gain_scale, b.gain_scale);
      });
      if (f == m.folds.end()) {  // a multiplier leaving the unit circle elsewhere than at +1
        ++no_turn;
        continue;
      }
      ++folds;
      const double side = st.gain_scale < *f ? -1.0 : 1.0;
      int unsettled = 0;
      bool ok = true;
      std::printf("seed %u %s %s (gain x %.2f): fold at %.4f, cycle %s it;", seed, r.model.c_str(),
                  r.controller.c_str(), g0, *f, side < 0 ? "below" : "above");
      // Beyond the fold even the states of the branch's orbits nearest to it come to rest.
      std::vector<std::vector<double>> ghosts = {a.section_state, b.section_state};
      for (double d : {kFoldTol, 3.0 * kFoldTol}) {
        const double g_in = *f * (1.0 + side * d), g_out = *f * (1.0 - side * d);
        // On the cycle's side: from rest, and from the branch's stable orbits within a factor
        // 1.3 of g_in, as they are and continued to g_in (Newton at a fixed gain is
        // ill-conditioned next to the fold, so several).
        std::vector<std::vector<double>> cycle;
        for (const HuntingMapPoint& q : m.points) {
          if (!q.orbit->stable || std::abs(std::log(q.gain_scale / g_in)) > std::log(1.3)) continue;
          cycle.push_back(q.orbit->section_state);
          if (const auto c = continue_orbit(L, *q.orbit, g_in)) cycle.push_back(c->section_state);
        }
        const int in = starts_that_hunt(L, g_in, cycle, &unsettled);
        const int out = starts_that_hunt(L, g_out, ghosts, &unsettled);
        std::printf(" +-%.0f %%: %d / %d starts hunt", d * 100, in, out);
        EXPECT_GE(in, 1) << "seed " << seed << ": no start hunts on the cycle's side of the fold";
        EXPECT_EQ(out, 0) << "seed " << seed << ": a start hunts beyond the fold";
        ok = ok && in >= 1 && out == 0;
      }
      std::printf(" (%d unsettled)\n", unsettled);
      fold_ok += ok;
    }
    // The unstable orbits past a fold (the run of unstable points next to it): between the basin
    // of rest and that of the stable cycle at their gain.
    std::vector<bool> past_fold(m.points.size(), false);
    for (std::size_t j = 1; j < m.points.size(); ++j) {
      const double lo = std::min(m.points[j - 1].gain_scale, m.points[j].gain_scale),
                   hi = std::max(m.points[j - 1].gain_scale, m.points[j].gain_scale);
      if (m.points[j - 1].orbit->stable == m.points[j].orbit->stable ||
          std::none_of(m.folds.begin(), m.folds.end(),
                       [&](double x) { return x >= 0.98 * lo && x <= 1.02 * hi; }))
        continue;
      const int dir = m.points[j].orbit->stable ? -1 : 1;  // towards the unstable side
      for (auto k = static_cast<std::ptrdiff_t>(dir > 0 ? j : j - 1);
           k >= 0 && k < static_cast<std::ptrdiff_t>(m.points.size()) &&
           !m.points[static_cast<std::size_t>(k)].orbit->stable;
           k += dir)
        past_fold[static_cast<std::size_t>(k)] = true;
    }
    for (std::size_t j = 0; j < m.points.size(); ++j) {
      const HuntingMapPoint& p = m.points[j];
      if (!past_fold[j]) continue;
      ++unstable;
      const PeriodicOrbit* near = nullptr;
      for (const HuntingMapPoint& q : m.points)
        if (q.orbit->stable && (!near || std::abs(std::log(q.gain_scale / p.gain_scale)) <
                                             std::abs(std::log(near->gain_scale / p.gain_scale))))
          near = &*q.orbit;
      const std::optional<PeriodicOrbit> partner =
          near ? continue_orbit(L, *near, p.gain_scale) : std::nullopt;
      if (!partner || !partner->stable || partner->amplitude <= p.orbit->amplitude) {
        ++no_partner;
        continue;
      }
      // Within 1 % of the stable cycle's amplitude (right at the fold) the two cannot be told
      // apart by a 10 % displacement: counted, not checked.
      if (partner->amplitude < 1.01 * p.orbit->amplitude) {
        ++at_fold;
        continue;
      }
      const ClosedLoop Lp = scaled_loop(L, p.gain_scale);
      std::vector<double> toward = p.orbit->section_state, away = toward;
      for (std::size_t k : p.orbit->unknowns) {
        const double d = partner->section_state[k] - p.orbit->section_state[k];
        toward[k] += 0.1 * d, away[k] -= 0.1 * d;
      }
      SimCycle up = simulate_from(Lp, toward, 60.0), down = simulate_from(Lp, away, 60.0);
      if (up.state == SimState::Unsettled) up = simulate_from(Lp, toward, 200.0);
      if (down.state == SimState::Unsettled) down = simulate_from(Lp, away, 200.0);
      std::printf(
          "  unstable orbit at gain %.4f: %.4f mm (stable %.4f mm); displaced towards: %s %.4f "
          "mm, away: %s\n",
          p.gain_scale, p.orbit->amplitude * 1e3, partner->amplitude * 1e3, to_string(up.state),
          up.amplitude * 1e3, to_string(down.state));
      const bool ok = up.state == SimState::Hunting &&
                      std::abs(up.amplitude - partner->amplitude) <= 0.05 * partner->amplitude &&
                      down.state == SimState::Rest;
      EXPECT_TRUE(ok) << "seed " << seed << " gain " << p.gain_scale;
      separates += ok;
    }
  }
  std::printf(
      "loops %d: skipped %d, no stable orbit %d, no fold %d; folds %d (%d agree with brute "
      "force), stability changes without a turn %d; unstable orbits past a fold %d (%d separate "
      "rest from the cycle, %d without a stable partner, %d within 1 %% of it)\n",
      drawn, skipped, no_orbit, no_fold, folds, fold_ok, no_turn, unstable, separates, no_partner,
      at_fold);
  EXPECT_EQ(fold_ok, folds);
  EXPECT_EQ(separates + no_partner + at_fold, unstable);
  if (!seed_env) {
    EXPECT_GE(folds, 2);  // the draw has folds to check
    EXPECT_GE(separates, 2);
  }
}
