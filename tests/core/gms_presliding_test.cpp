// GMS in presliding: the Fig. 2A protocol and the properties that follow from the Maxwell-slip
// structure (nonlocal memory, rate independence, reduction to Maxwell-slip, bounds, dissipation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/friction/gms.hpp"
#include "core/sim/assembly.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

using test_util::at_time;
using test_util::gms_displacement_scenario;
using test_util::preset_path;

// Time at which the turning-point signal reaches its k-th point.
double turn_time(const Signal& s, std::size_t k) { return s.pt.at(k); }

TEST(GmsPresliding, Fig2aTurningPointForcesMatchReference) {
  const Scenario sc = load_scenario(preset_path("fig2a_presliding.json"));
  const Trace tr = simulate(sc);
  const double expected[] = {1.35, -1.35, 1.14, -0.585, 1.14, 1.35, -1.35};
  for (std::size_t k = 0; k < 7; ++k) {
    const double f = at_time(tr, tr.friction, turn_time(sc.drive.signal, k + 1));
    EXPECT_NEAR(f, expected[k], 0.005 * std::abs(expected[k])) << "turning point " << k + 1;
  }
}

TEST(GmsPresliding, Fig2aVirginCurveMatchesReference) {
  const Scenario sc = load_scenario(preset_path("fig2a_presliding.json"));
  const Trace tr = simulate(sc);
  const double x_um[] = {1, 2, 5, 10};
  const double f_ref[] = {0.21, 0.42, 0.825, 1.20};
  for (int i = 0; i < 4; ++i) {
    const double t = x_um[i] * 1e-6 / 1e-5;  // 10 um/s
    EXPECT_NEAR(at_time(tr, tr.friction, t), f_ref[i], 0.005 * f_ref[i]) << x_um[i] << " um";
  }
  // 20 um is beyond the first turning point of the preset: drive the virgin curve further.
  const auto far = simulate(gms_displacement_scenario(Signal::ramp(0.0, 1e-5), 2.0));
  EXPECT_NEAR(at_time(far, far.friction, 2.0), 1.50, 0.005 * 1.50);
}

TEST(GmsPresliding, InnerLoopClosesAndCurveRejoinsOuterBranch) {
  // Nonlocal memory (Masing rules, wiping-out): after the inner loop 8 -> -3 -> 8 um, the force at
  // 8 um is the one the curve had there before, and from 8 to 15 um the curve continues the outer
  // branch as if the inner loop had never happened (compare with a run without the inner loop).
  const Scenario sc = load_scenario(preset_path("fig2a_presliding.json"));
  const Trace with_loop = simulate(sc);
  const Signal& s = sc.drive.signal;
  EXPECT_NEAR(at_time(with_loop, with_loop.friction, turn_time(s, 5)),
              at_time(with_loop, with_loop.friction, turn_time(s, 3)), 1e-9);

  const Signal outer = Signal::turning_points(0.0, 1e-5, {15e-6, -15e-6, 15e-6});
  const Trace without = simulate(gms_displacement_scenario(outer, outer.natural_end()));
  // Sample the rising branch from 8 to 15 um in both runs at the same positions.
  for (double x_um = 8.5; x_um <= 15.0; x_um += 0.5) {
    const double t_with = turn_time(s, 5) + (x_um - 8.0) * 0.1;     // after the inner loop
    const double t_without = turn_time(outer, 2) + (x_um + 15.0) * 0.1;
    EXPECT_NEAR(at_time(with_loop, with_loop.friction, t_with),
                at_time(without, without.friction, t_without), 1e-9)
        << "x = " << x_um << " um";
  }
}

TEST(GmsPresliding, HysteresisIsRateIndependent) {
  const Signal fast = Signal::turning_points(0.0, 1e-5, {15e-6, -15e-6, 8e-6, -3e-6, 8e-6});
  const Signal slow = Signal::turning_points(0.0, 1e-6, {15e-6, -15e-6, 8e-6, -3e-6, 8e-6});
  const Trace a = simulate(gms_displacement_scenario(fast, fast.natural_end(), 1e-3));
  const Trace b = simulate(gms_displacement_scenario(slow, slow.natural_end(), 1e-2));
  // Only the rate-dependent terms may differ: S(v) (at most Fs - ... over all elements) and the
  // viscous sigma2 v; both are bounded from the formulas, and far below the loop's force scale.
  const GmsParams g = GmsParams::reference(false);
  const double bound = (g.S(1e-6) - g.S(1e-5)) + g.sigma2 * (1e-5 - 1e-6);
  EXPECT_LT(bound, 1e-4);
  for (std::size_t k = 1; k <= 5; ++k) {
    const double fa = at_time(a, a.friction, turn_time(fast, k));
    const double fb = at_time(b, b.friction, turn_time(slow, k));
    EXPECT_NEAR(fa, fb, bound) << "turning point " << k;
  }
}

// An independent Maxwell-slip model: Jenkin elements, spring k_i with a slider at W_i.
struct Jenkin {
  std::vector<double> k, w, z;
  double step(double dx) {
    double f = 0.0;
    for (std::size_t i = 0; i < k.size(); ++i) {
      z[i] = std::clamp(z[i] + dx, -w[i] / k[i], w[i] / k[i]);
      f += k[i] * z[i];
    }
    return f;
  }
};

TEST(GmsPresliding, ConstantStribeckReducesToMaxwellSlip) {
  GmsParams g = GmsParams::reference(false);
  g.S.Fs = g.S.Fc = 1.2;  // S(v) = W constant
  g.sigma2 = 0.0;
  const auto model = build_model(g.to_params());
  std::vector<double> state(model->state_size());
  model->reset(state);
  Jenkin ref{g.k, {}, std::vector<double>(4, 0.0)};
  for (double a : g.alpha) ref.w.push_back(a * 1.2);

  std::mt19937 rng(42);
  std::uniform_real_distribution<double> vel(-2e-3, 2e-3);
  const double h = 1e-4;
  double max_err = 0.0;
  for (int seg = 0; seg < 200; ++seg) {
    const double v = vel(rng);
    for (int k = 0; k < 50; ++k) {
      const double f = model->step(state, {v, h});
      max_err = std::max(max_err, std::abs(f - ref.step(v * h)));
    }
  }
  EXPECT_LT(max_err, 1e-9);
}

TEST(GmsPresliding, NonViscousForceStaysWithinFs) {
  const GmsParams g = GmsParams::reference(true);
  const auto model = build_model(g.to_params());
  std::vector<double> state(model->state_size());
  model->reset(state);
  std::mt19937 rng(7);
  std::normal_distribution<double> acc(0.0, 2.0);
  double v = 0.0, worst = 0.0;
  for (int k = 0; k < 200000; ++k) {
    v = std::clamp(v + acc(rng) * 1e-4, -0.05, 0.05);
    model->step(state, {v, 1e-5});
    double elastic = 0.0;
    for (std::size_t i = 0; i < model->element_count(); ++i) elastic += model->element(state, i).force;
    worst = std::max(worst, std::abs(elastic));
  }
  EXPECT_LE(worst, g.S.Fs * (1.0 + 1e-12));
  EXPECT_GT(worst, 0.5 * g.S.Fs);  // the input did load it
}

TEST(GmsPresliding, ClosedCycleDissipatesMasingLoopEnergy) {
  // Displacement cycle +-15 um after the virgin loading. For Jenkin elements with yield
  // displacement d_i = W_i / k_i < A the loop area is 4 W_i (A - d_i) (W_i = alpha_i S(v)).
  const double A = 15e-6, v = 1e-5;
  const Signal x = Signal::turning_points(0.0, v, {A, -A, A});
  const Trace tr = simulate(gms_displacement_scenario(x, x.natural_end(), 1e-4));
  const double t0 = turn_time(x, 1);
  double work = 0.0;
  for (std::size_t k = 1; k < tr.size(); ++k)
    if (tr.t[k] > t0 + 1e-9) work += tr.friction[k] * (tr.x[k] - tr.x[k - 1]);
  const GmsParams g = GmsParams::reference(false);
  const double S = g.S(v);
  double expected = g.sigma2 * v * 4 * A;  // viscous part
  for (std::size_t i = 0; i < g.k.size(); ++i) {
    const double w = g.alpha[i] * S, d = w / g.k[i];
    if (d < A) expected += 4 * w * (A - d);
  }
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(work, expected, 0.005 * expected);
}

TEST(GmsPresliding, SameScenarioGivesSameTrace) {
  const Scenario sc = load_scenario(preset_path("fig2a_presliding.json"));
  const Trace a = simulate(sc), b = simulate(sc);
  EXPECT_EQ(a.friction, b.friction);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.element_force, b.element_force);
}

}  // namespace
}  // namespace gmslab

namespace gmslab {
namespace {

TEST(LiveEdits, ChangingElementCountKeepsTraceColumnsAligned) {
  AssemblySimulation sim =
      one_body_simulation(load_scenario(test_util::preset_path("fig4_stick_slip.json")));
  sim.advance(1000);
  GmsParams g = GmsParams::reference(true);
  g.alpha = {0.5, 0.5};
  g.k = {50000, 25000};
  g.sigma = {0, 0};
  sim.set_friction(g.to_params());
  sim.advance(1000);
  const Trace& tr = sim.one_body_trace();
  EXPECT_EQ(tr.n_elements, 2u);
  EXPECT_EQ(tr.element_force.size(), tr.size() * 2);
  EXPECT_EQ(tr.element_slip.size(), tr.size() * 2);
}

TEST(LiveEdits, SameShapeEditKeepsFrictionState) {
  // Editing a parameter while stuck must not release the elements' stored forces.
  AssemblySimulation sim =
      one_body_simulation(load_scenario(test_util::preset_path("fig4_stick_slip.json")));
  sim.advance(300000);  // 3 s: loaded at about 0.6 N, stuck
  const double before = sim.one_body_trace().friction.back();
  ModelParams p = sim.one_body()->friction;
  p.set_scalar("C", 300.0);
  sim.set_friction(p);
  sim.advance(10);
  EXPECT_NEAR(sim.one_body_trace().friction.back(), before, 0.01);
  EXPECT_GT(before, 0.5);
}

}  // namespace
}  // namespace gmslab

namespace gmslab {
namespace {

TEST(GmsStribeck, SaturatedShortcutIsBitIdenticalToTheFormula) {
  // The step skips pow/exp where S(v) rounds to Fc; the force must equal the full formula's.
  for (double delta : {0.5, 1.0, 2.0, 3.7}) {
    GmsParams g = GmsParams::reference(false);
    g.S.delta = delta;
    const auto model = build_model(g.to_params());
    for (double v = 1e-4; v < 10.0; v *= 1.05) {
      std::vector<double> state(model->state_size(), 0.0);
      // From zero state with a long step every element slips to alpha_i S: F = S + sigma2 v.
      const double f = model->step(state, {v, 10.0});
      const double s_formula = g.S.Fc + (g.S.Fs - g.S.Fc) * std::exp(-std::pow(v / g.S.Vs, delta));
      double elastic = 0.0;
      for (std::size_t i = 0; i < 4; ++i) elastic += state[i];
      EXPECT_NEAR(elastic, s_formula, 1e-12) << "delta " << delta << " v " << v;
      EXPECT_GT(f, 0.0);
    }
  }
}

}  // namespace
}  // namespace gmslab
