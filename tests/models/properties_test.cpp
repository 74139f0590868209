// The properties that tell the friction models apart (the property table of docs/references.md),
// each measured on the protocols of the seed's figures and run over the models it concerns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "core/sim/assembly.hpp"
#include "tests/models/model_protocols.hpp"

namespace gmslab {
namespace {

using testing::at_time;
using testing::preset_with;
using testing::value_at_crossing;

// ---- nonlocal memory (Fig. 2A protocol) ---------------------------------------------------------
struct InnerLoop {
  double f8_before, f8_after;    // F at 8 um before and after the inner loop 8 -> -3 -> 8 um [N]
  double f15_after, f15_plain;   // F at 15 um after the inner loop / on the same branch without it
};

InnerLoop inner_loop(const std::string& tag) {
  const Scenario s = preset_with("fig2a_presliding.json", tag);
  const Trace tr = simulate(s);  // turning points at 1.5, 4.5, 6.8, 7.9, 9.0, 9.7, 12.7 s
  Scenario plain = s;           // 0 -> 15 -> -15 -> 15 um: the outer branch, no inner loop
  plain.drive.signal = Signal::turning_points(0.0, 1e-5, {15e-6, -15e-6, 15e-6});
  plain.run.duration = 7.5;
  const Trace tp = simulate(plain);
  return {at_time(tr, tr.friction, 6.8), at_time(tr, tr.friction, 9.0),
          at_time(tr, tr.friction, 9.7), tp.friction.back()};
}

TEST(NonlocalMemory, InnerLoopClosesExactlyForMaxwellSlipAndGms) {
  for (const char* tag : {"gms", "maxwell_slip"}) {
    const auto r = inner_loop(tag);
    EXPECT_NEAR(r.f8_after, r.f8_before, 1e-9) << tag;
    EXPECT_NEAR(r.f15_after, r.f15_plain, 1e-9) << tag << ": curve must rejoin the outer branch";
  }
}

// Leuven: F_h has exact memory in z, but z follows x only as dz/dx = 1 - |F_h/s|^n; with the
// default n = 8 the loop closes to 0.02 N (LuGre and Dahl miss by 0.3 N).
TEST(NonlocalMemory, InnerLoopClosesApproximatelyForLeuven) {
  const auto r = inner_loop("leuven");
  EXPECT_NEAR(r.f8_after, r.f8_before, 0.03);
  EXPECT_NEAR(r.f15_after, r.f15_plain, 0.03);
}

TEST(NonlocalMemory, InnerLoopDoesNotCloseForDahlAndLuGre) {
  for (const char* tag : {"dahl", "lugre"}) {
    const auto r = inner_loop(tag);
    EXPECT_GT(std::abs(r.f8_after - r.f8_before), 0.2) << tag << ": local memory only";
  }
}

// Maxwell-slip is exactly Masing: the virgin curve is sum min(k_i x, W_i), and the Fig. 2A turning
// point forces of docs/references.md follow (GMS at 10 um/s has S = Fs to 1e-4 N).
TEST(NonlocalMemory, MaxwellSlipTurningPointsAreTheReferenceNumbers) {
  const Scenario s = preset_with("fig2a_presliding.json", "maxwell_slip");
  const Trace tr = simulate(s);
  const double ref[] = {1.35, -1.35, 1.14, -0.585, 1.14, 1.35, -1.35};
  const double times[] = {1.5, 4.5, 6.8, 7.9, 9.0, 9.7, 12.7};
  const double sigma2_v = 0.4 * 1e-5;  // viscous part at 10 um/s
  const double sign_of_v[] = {1, -1, 1, -1, 1, 1, -1};  // direction of travel into each point
  for (int i = 0; i < 7; ++i) {
    const double sign = sign_of_v[i];
    EXPECT_NEAR(at_time(tr, tr.friction, times[i]), ref[i] + sign * sigma2_v, 1e-9) << times[i];
  }
  const double k[] = {75000, 60000, 45000, 30000}, W[] = {0.15, 0.3, 0.45, 0.6};
  for (double x_um : {1.0, 2.0, 5.0, 10.0}) {
    double virgin = 0.0;
    for (int i = 0; i < 4; ++i) virgin += std::min(k[i] * x_um * 1e-6, W[i]);
    EXPECT_NEAR(value_at_crossing(tr.t, tr.x, tr.friction, x_um * 1e-6, +1) - sigma2_v, virgin,
                1e-9);
  }
}

// (GMS with a constant Stribeck level reducing to Maxwell-slip is tests/core's.)

// ---- drift under a sub-break-away oscillating force (Fig. 2D protocol) --------------------------
double drift_6_to_12s(const std::string& tag) {
  const Trace tr = simulate(preset_with("fig2d_nondrifting.json", tag));
  return tr.x.back() - at_time(tr, tr.x, 6.0);
}

TEST(Drift, LuGreDriftsAbout81umIn6s) {
  EXPECT_NEAR(drift_6_to_12s("lugre") * 1e6, 81.0, 1.5);
  // The preset that shows it in the window gives the same.
  const Trace tr = simulate(load_scenario(testing::preset_path("compare_fig2d_lugre.json")));
  EXPECT_NEAR((tr.x.back() - at_time(tr, tr.x, 6.0)) * 1e6, 81.0, 1.5);
}

TEST(Drift, DahlDriftsToo) { EXPECT_GT(drift_6_to_12s("dahl") * 1e6, 50.0); }

TEST(Drift, GmsElastoPlasticAndMaxwellSlipStayWithinATenthMicrometre) {
  for (const char* tag : {"gms", "elastoplastic", "maxwell_slip", "stribeck", "coulomb"})
    EXPECT_LT(std::abs(drift_6_to_12s(tag)) * 1e6, 0.1) << tag;
}

// Leuven creeps slowly (dz/dx != 1 in presliding), far less than LuGre.
TEST(Drift, LeuvenCreepsFarLessThanLuGre) {
  EXPECT_LT(std::abs(drift_6_to_12s("leuven")) * 1e6, 1.0);
}

// ---- frictional lag (Fig. 2B protocol) ----------------------------------------------------------
struct LagBranches {
  double up, down;  // F at v = 1 mm/s, accelerating / decelerating branch of the last cycle [N]
};

LagBranches lag(const std::string& tag, const std::string& factor) {
  const Scenario s = preset_with("fig2b_lag_" + factor + ".json", tag);
  const Trace tr = simulate(s);
  const double t_last = s.run.duration * 2.0 / 3.0;
  return {value_at_crossing(tr.t, tr.v, tr.friction, 1e-3, +1, t_last),
          value_at_crossing(tr.t, tr.v, tr.friction, 1e-3, -1, t_last)};
}

TEST(FrictionalLag, GmsMatchesTheFig2BReferenceNumbers) {
  const struct {
    const char* factor;
    double up, down;
  } ref[] = {{"x1", 1.186, 1.182}, {"x16", 1.222, 1.154}, {"x100", 1.320, 1.079}};
  for (const auto& r : ref) {
    const auto b = lag("gms", r.factor);
    EXPECT_NEAR(b.up, r.up, 2e-3) << r.factor;
    EXPECT_NEAR(b.down, r.down, 2e-3) << r.factor;
  }
}

TEST(FrictionalLag, LoopOpensWithAccelerationForRateStateModels) {
  for (const char* tag : {"gms", "lugre", "elastoplastic", "leuven"}) {
    double prev = -1.0;
    for (const char* f : {"x1", "x16", "x100"}) {
      const auto b = lag(tag, f);
      const double width = b.up - b.down;
      EXPECT_GT(width, prev) << tag << " " << f << ": the loop must widen with acceleration";
      EXPECT_GT(width, 0.0) << tag << " " << f << ": the accelerating branch lies above";
      prev = width;
    }
    EXPECT_GT(prev, 0.04) << tag;
  }
}

TEST(FrictionalLag, NoLagForStaticMaxwellSlipAndDahl) {
  for (const char* tag : {"maxwell_slip", "dahl", "stribeck", "coulomb"}) {
    const auto b = lag(tag, "x100");
    EXPECT_NEAR(b.up - b.down, 0.0, 2e-4) << tag;
  }
}

// ---- break-away force vs force rate -------------------------------------------------------------
// Unit mass, applied force ramp F = r t. Break-away force: the largest non-viscous friction force
// (F_f - sigma2 v) before gross sliding (v = 10 mm/s).
struct BreakAwayRun {
  double friction_peak;  // largest non-viscous friction before gross sliding [N]
  double applied;        // applied force r t when the body reaches gross sliding [N]
};

BreakAwayRun break_away_run(const std::string& tag, double rate) {
  Scenario s;
  s.friction = model_info(tag).defaults();
  s.plant.mass = 1.0;
  s.drive.kind = Drive::Kind::Force;
  s.drive.signal = Signal::ramp(0.0, rate);
  s.run.dt = 1e-5;
  s.run.duration = 3.0 / rate + 1.0;
  AssemblySimulation sim = one_body_simulation(s);
  const double sigma2 = s.friction.scalar("sigma2");
  double peak = 0.0;
  while (!sim.finished() && sim.velocities()[0] < 1e-2) {
    sim.advance(1);
    peak = std::max(peak, sim.one_body_trace().friction.back() - sigma2 * sim.velocities()[0]);
  }
  return {peak, sim.one_body_trace().applied.back()};
}

double break_away_force(const std::string& tag, double rate) {
  return break_away_run(tag, rate).friction_peak;
}

// In these models the break-away force depends on the force rate: the faster the ramp, the
// sooner the body reaches velocities where S(v) has dropped, before the friction state catches up
// (it falls, as the LuGre paper reports for its Table I set).
TEST(BreakAway, DependsOnForceRateForRateStateModels) {
  for (const char* tag : {"gms", "lugre", "elastoplastic", "leuven"}) {
    const double slow = break_away_force(tag, 1.0), fast = break_away_force(tag, 50.0);
    EXPECT_GT(std::abs(slow - fast), 0.15) << tag << ": " << slow << " vs " << fast << " N";
    EXPECT_LE(slow, 1.5 + 1e-3) << tag;
  }
}

// The literature (docs/references.md) says the break-away force "rises with force rate" for LuGre and GMS. The
// applied force at which the body reaches gross sliding does rise, but for every model with
// stiction, rate-state or not, because it includes the inertial force m a of the mass accelerating
// away. For the Coulomb law with its Karnopp band (m = 1 kg, ramp r): held at Fs until
// |v| = v_stick, reached after t_s = sqrt(2 v_stick / r); then Fc, so
// v_stick + (Fs - Fc + r t_s) tau + r tau^2 / 2 = v_slide, applied force r (Fs / r + t_s + tau)
// (sigma2 v is a 0.3 % correction). So that reading cannot tell the models apart; the friction
// peak (above) can.
TEST(BreakAway, AppliedForceAtGrossSlidingRisesWithRateForEveryModelByInertia) {
  const ModelParams c = model_info("coulomb").defaults();
  const double Fs = c.scalar("Fs"), Fc = c.scalar("Fc"), v_stick = c.scalar("v_stick");
  const double v_slide = 1e-2;
  for (double r : {1.0, 50.0}) {
    const double ts = std::sqrt(2.0 * v_stick / r), b = Fs - Fc + r * ts;
    const double tau = (-b + std::sqrt(b * b + 2.0 * r * (v_slide - v_stick))) / r;
    const double expected = Fs + r * (ts + tau);
    EXPECT_NEAR(break_away_run("coulomb", r).applied, expected, 0.02 * (expected - Fs)) << r;
  }
  for (const char* tag : {"gms", "lugre", "elastoplastic", "leuven", "maxwell_slip", "stribeck"}) {
    const double slow = break_away_run(tag, 1.0).applied, fast = break_away_run(tag, 50.0).applied;
    EXPECT_GT(fast - slow, 0.3) << tag << ": " << slow << " vs " << fast << " N";
    std::cout << "[ info ] " << tag << ": applied force at gross sliding " << slow << " N at 1 N/s, "
              << fast << " N at 50 N/s\n";
  }
}

TEST(BreakAway, IndependentOfForceRateForMaxwellSlipAndStaticLaws) {
  for (const char* tag : {"maxwell_slip", "stribeck", "coulomb"}) {
    EXPECT_NEAR(break_away_force(tag, 1.0), 1.5, 1e-6) << tag;
    EXPECT_NEAR(break_away_force(tag, 50.0), 1.5, 1e-6) << tag;
  }
}

// ---- stick-slip (Figs. 3/4 protocol) ------------------------------------------------------------
std::vector<double> slip_onsets(const std::string& tag) {
  const Trace tr = simulate(preset_with("fig4_stick_slip.json", tag));
  std::vector<double> on;
  bool moving = false;
  for (std::size_t k = 0; k < tr.size(); ++k) {
    const bool m = tr.v[k] > 1e-3;
    if (m && !moving) on.push_back(tr.t[k]);
    moving = m;
  }
  return on;
}

TEST(StickSlip, LuGrePeriodIsAbout636s) {
  const auto on = slip_onsets("lugre");
  ASSERT_GE(on.size(), 3u);
  EXPECT_NEAR(on[2] - on[1], 6.36, 0.03);
}

TEST(StickSlip, GmsPeriodIsLongerThanLuGre) {
  const auto g = slip_onsets("gms"), l = slip_onsets("lugre");
  ASSERT_GE(g.size(), 3u);
  ASSERT_GE(l.size(), 3u);
  EXPECT_GT((g[2] - g[1]) - (l[2] - l[1]), 0.1);
}

TEST(StickSlip, VelocityWeakeningModelsStickSlipPeriodically) {
  for (const char* tag : {"elastoplastic", "leuven", "stribeck", "coulomb"}) {
    const auto on = slip_onsets(tag);
    ASSERT_GE(on.size(), 3u) << tag;
    EXPECT_GT(on[2] - on[1], 6.0) << tag;
    EXPECT_LT(on[2] - on[1], 6.8) << tag;
    EXPECT_NEAR(on[2] - on[1], on[1] - on[0], 0.05) << tag << ": a limit cycle";
  }
}

// Without a drop from static to sliding friction there is nothing to release: after the first
// slip the mass keeps sliding.
TEST(StickSlip, NoStickSlipWithoutVelocityWeakening) {
  for (const char* tag : {"maxwell_slip", "dahl"}) EXPECT_EQ(slip_onsets(tag).size(), 1u) << tag;
}

}  // namespace
}  // namespace gmslab
