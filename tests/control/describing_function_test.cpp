// Describing functions computed from a nonlinearity's own step against their closed forms
// (Coulomb 4 Fc / (pi a) + sigma2, saturation, relay with hysteresis) over random parameters, and
// predicted limit cycles against the loop simulated with friction.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/control/describing_function.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/friction/model.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
constexpr double kPi = std::numbers::pi;
}

TEST(DescribingFunction, CoulombMatchesFourFcOverPiA) {
  std::mt19937 rng(1210);
  std::uniform_real_distribution<double> la(-3.0, 0.0), lw(-1.0, 3.0), fc(0.1, 5.0), s2(0.0, 2.0);
  for (int i = 0; i < 40; ++i) {
    ModelParams p = model_info("coulomb").defaults();
    const double Fc = fc(rng), sigma2 = s2(rng);
    p.set_scalar("Fc", Fc), p.set_scalar("Fs", Fc * 1.2), p.set_scalar("sigma2", sigma2);
    const auto m = build_model(p);
    const double a = std::pow(10.0, la(rng)), w = std::pow(10.0, lw(rng));
    const cplx N = describing_function(stepped(*m), a, w);
    const double expect = 4 * Fc / (kPi * a) + sigma2;
    EXPECT_NEAR(N.real(), expect, 2e-3 * expect) << "a=" << a << " w=" << w;
    EXPECT_NEAR(N.imag(), 0.0, 5e-3 * expect);
  }
}

// Saturation of slope k and limit M = k d: N = (2k/pi)(asin(d/a) + (d/a) sqrt(1 - (d/a)^2)), a > d.
TEST(DescribingFunction, SaturationMatchesClosedForm) {
  std::mt19937 rng(1211);
  std::uniform_real_distribution<double> lk(-1.0, 2.0), r(0.05, 0.95);
  for (int i = 0; i < 40; ++i) {
    const double k = std::pow(10.0, lk(rng)), d = r(rng), a = 1.0;
    SteppedNonlinearity sat{[] {}, [&](double v, double) { return k * std::clamp(v, -d, d); }};
    const cplx N = describing_function(sat, a, 3.0);
    const double q = d / a;
    const double expect = 2 * k / kPi * (std::asin(q) + q * std::sqrt(1 - q * q));
    EXPECT_NEAR(N.real(), expect, 1e-4 * k);
    EXPECT_NEAR(N.imag(), 0.0, 1e-4 * k);
  }
}

// Relay +-M switching at +-d (hysteresis): N = (4M / (pi a)) (sqrt(1 - (d/a)^2) - j d/a), a > d.
TEST(DescribingFunction, RelayWithHysteresisMatchesClosedForm) {
  std::mt19937 rng(1212);
  std::uniform_real_distribution<double> lm(-1.0, 1.0), r(0.0, 0.9), lw(-1.0, 2.0);
  for (int i = 0; i < 40; ++i) {
    const double M = std::pow(10.0, lm(rng)), a = 0.5, d = r(rng) * a, w = std::pow(10.0, lw(rng));
    double out = -M;
    SteppedNonlinearity relay{[&] { out = -M; }, [&](double v, double) {
                                if (v >= d) out = M;
                                else if (v <= -d) out = -M;
                                return out;
                              }};
    const cplx N = describing_function(relay, a, w);
    const double q = d / a, g = 4 * M / (kPi * a);
    EXPECT_NEAR(N.real(), g * std::sqrt(1 - q * q), 5e-3 * g) << "q=" << q;
    EXPECT_NEAR(N.imag(), -g * q, 5e-3 * g) << "q=" << q;
  }
}

TEST(DescribingFunction, BadAmplitudeIsAnInputError) {
  SteppedNonlinearity lin{[] {}, [](double v, double) { return v; }};
  EXPECT_THROW(describing_function(lin, 0.0, 1.0), InputError);
  EXPECT_THROW(describing_function(lin, 1.0, -1.0), InputError);
}

// Where the describing function does not apply: stick-slip hunting. A PI loop with Stribeck
// friction (stiction Fs > Fc) on a 1 kg mass with c = 3 N s/m hunts in simulation (the mass sticks
// while the integrator winds up to Fs, slips, sticks again: a sub-millimetre cycle of ~1.6 s),
// while the DF, whose sinusoidal motion never sticks, only predicts the unstable threshold cycle
// (tens of mm at ~0.2 s). The lead loop (p = 200 rad/s) neither hunts nor has a predicted cycle.
TEST(LimitCycle, StickSlipHuntingIsOutsideTheDescribingFunction) {
  Scenario s;
  s.plant = {1.0, 0.0, 3.0};
  s.friction = model_info("stribeck").defaults();
  const auto m = build_model(s.friction);
  const LeadCompensator pi{1000.0, 5.0, 0.0};
  const LimitCycleReport r = predict_limit_cycles(stepped(*m), s.plant, pi);
  LoopConfig cfg;
  cfg.C = pi;
  cfg.reference = Signal::constant(0.01);
  cfg.dt = 1e-5;
  cfg.duration = 20.0;
  cfg.record_every = 20;
  const LoopMetrics lm = loop_metrics(simulate_loop(s, cfg));
  std::printf("stick-slip: simulated %.4g mm, %.4g s; DF:", lm.cycle_amplitude * 1e3, lm.cycle_period);
  for (const auto& c : r.cycles) std::printf(" %.4g mm %.4g s %s", c.amplitude * 1e3, c.period, c.stable ? "stable" : "unstable");
  std::printf("\n");
  ASSERT_TRUE(lm.hunting);
  ASSERT_EQ(r.cycles.size(), 1u);
  EXPECT_FALSE(r.cycles.front().stable);
  EXPECT_GT(r.cycles.front().amplitude, 10 * lm.cycle_amplitude);
  EXPECT_GT(lm.cycle_period, 3 * r.cycles.front().period);
  // The lead loop: no hunting, no prediction.
  Scenario s0 = s;
  s0.plant.damper = 0.0;
  const LeadCompensator lead{1000.0, 5.0, 200.0};
  EXPECT_TRUE(predict_limit_cycles(stepped(*m), s0.plant, lead).cycles.empty());
  cfg.C = lead;
  EXPECT_FALSE(loop_metrics(simulate_loop(s0, cfg)).hunting);
}

// PI loop around a damped mass with Coulomb friction: the describing function predicts an
// unstable cycle (an amplitude threshold: N = 4 Fc / (pi a) + sigma2 acts as damping that fades
// with amplitude). Closed form for this loop: H real negative at w^2 = (k + Kc) / m, where
// N = m Kc z / (k + Kc) - c, so a = 4 Fc / (pi (N - sigma2)). Simulation agrees on both sides: a
// step well below the threshold does not hunt and its error does not grow, one well above it
// diverges.
TEST(LimitCycle, CoulombPiThresholdMatchesClosedFormAndSimulation) {
  std::mt19937 rng(1213);
  std::uniform_real_distribution<double> lk(2.5, 3.5), uz(3.0, 8.0), uc(0.3, 0.8);
  for (int i = 0; i < 4; ++i) {
    Scenario s;
    const double Kc = std::pow(10.0, lk(rng)), z = uz(rng);
    s.plant = {1.0, 0.0, uc(rng) * z};  // c < m z: the friction-free loop is unstable
    s.friction = model_info("coulomb").defaults();
    const double Fc = s.friction.scalar("Fc"), s2 = s.friction.scalar("sigma2");
    const auto m = build_model(s.friction);
    const LeadCompensator C{Kc, z, 0.0};
    const LimitCycleReport r = predict_limit_cycles(stepped(*m), s.plant, C);
    ASSERT_EQ(r.cycles.size(), 1u);
    const LimitCycle& c = r.cycles.front();
    const double w = std::sqrt(Kc), Nq = z - s.plant.damper;  // m = 1, k = 0
    ASSERT_GT(Nq, s2);
    const double a = 4 * Fc / (kPi * (Nq - s2));
    EXPECT_NEAR(c.frequency, w, 2e-3 * w);
    EXPECT_NEAR(c.velocity_amplitude, a, 0.01 * a);
    EXPECT_FALSE(c.stable);
    LoopConfig cfg;
    cfg.C = C;
    cfg.dt = 2e-5;
    cfg.duration = 10.0;
    cfg.record_every = 20;
    cfg.reference = Signal::constant(0.2 * c.amplitude);
    const LoopMetrics below = loop_metrics(simulate_loop(s, cfg));
    EXPECT_FALSE(below.hunting);
    EXPECT_LT(below.tail_max_error, 0.2 * c.amplitude);  // crept towards the set point, did not grow
    cfg.reference = Signal::constant(5.0 * c.amplitude);
    bool diverged = false;
    try {
      const LoopTrace tr = simulate_loop(s, cfg);
      diverged = std::abs(tr.x.back()) > 100 * c.amplitude;
    } catch (const SimulationError&) {
      diverged = true;
    }
    EXPECT_TRUE(diverged);
  }
}

// The same threshold cycle for every friction family (Coulomb, Stribeck, LuGre, GMS; the
// presliding and rate-state models through their numerically computed DF), PI loops on a 1 kg
// mass with two dampings: started at half the predicted amplitude the loop does not hunt; started
// at twice it the oscillation grows, at the predicted period within 10 %.
TEST(LimitCycle, ThresholdCycleOfEachFrictionFamilyMatchesSimulation) {
  for (const char* model : {"coulomb", "stribeck", "lugre", "gms"})
    for (double c : {0.0, 2.0}) {
      Scenario s;
      s.plant = {1.0, 0.0, c};
      s.friction = model_info(model).defaults();
      const auto m = build_model(s.friction);
      const LeadCompensator C{1000.0, 5.0, 0.0};
      const LimitCycleReport r = predict_limit_cycles(stepped(*m), s.plant, C);
      ASSERT_EQ(r.cycles.size(), 1u) << model;
      const LimitCycle& lc = r.cycles.front();
      EXPECT_FALSE(lc.stable) << model;
      LoopConfig cfg;
      cfg.C = C;
      cfg.dt = 2e-5;
      cfg.duration = 6.0;
      cfg.record_every = 10;
      cfg.reference = Signal::constant(0.5 * lc.amplitude);
      const LoopMetrics below = loop_metrics(simulate_loop(s, cfg));
      EXPECT_FALSE(below.hunting) << model << " c=" << c;
      EXPECT_LT(below.tail_max_error, 0.5 * lc.amplitude) << model << " c=" << c;
      cfg.reference = Signal::constant(2.0 * lc.amplitude);
      const LoopTrace tr = simulate_loop(s, cfg);
      const LoopMetrics above = loop_metrics(tr);
      EXPECT_GT(above.cycle_amplitude, 10 * lc.amplitude) << model << " c=" << c;
      EXPECT_NEAR(above.cycle_period, lc.period, 0.1 * lc.period) << model << " c=" << c;
    }
}

// Friction compensation driven by the measured velocity (compensated_friction): with a Coulomb law
// and a Coulomb compensator Fc_hat = r Fc, the loop's nonlinearity is Coulomb with Fc - Fc_hat:
// N = 4 Fc (1 - r) / (pi a) + sigma2 (over random Fc, sigma2, r in [0.2, 2] incl. over-
// compensation, a, w); perfect compensation (r = 1) of a GMS law by its own model leaves nothing.
TEST(DescribingFunction, CompensatedCoulombIsCoulombWithTheResidualLevel) {
  std::mt19937 rng(1226);
  std::uniform_real_distribution<double> la(-3.0, 0.0), lw(-1.0, 3.0), fc(0.1, 5.0), s2(0.0, 2.0), ur(0.2, 2.0);
  for (int i = 0; i < 40; ++i) {
    ModelParams p = model_info("coulomb").defaults();
    const double Fc = fc(rng), sigma2 = s2(rng), r = ur(rng);
    p.set_scalar("Fc", Fc), p.set_scalar("Fs", Fc * 1.2), p.set_scalar("sigma2", sigma2);
    Mismatch mm;
    mm.force = r;
    const double a = std::pow(10.0, la(rng)), w = std::pow(10.0, lw(rng));
    const cplx N = describing_function(compensated_friction(p, Compensation::Coulomb, mm), a, w);
    const double expect = 4 * Fc * (1 - r) / (kPi * a) + sigma2;
    EXPECT_NEAR(N.real(), expect, 2e-3 * (4 * Fc / (kPi * a) + sigma2)) << "a=" << a << " w=" << w << " r=" << r;
    EXPECT_NEAR(N.imag(), 0.0, 5e-3 * (4 * Fc / (kPi * a) + sigma2));
    const cplx N0 = describing_function(compensated_friction(p, Compensation::None, mm), a, w);
    EXPECT_NEAR(N0.real(), 4 * Fc / (kPi * a) + sigma2, 2e-3 * (4 * Fc / (kPi * a) + sigma2));
  }
  const ModelParams g = model_info("gms").defaults();
  const cplx Ng = describing_function(compensated_friction(g, Compensation::Gms, Mismatch{}), 0.01, 20.0);
  EXPECT_LT(std::abs(Ng), 1e-12);
  const cplx Ng0 = describing_function(compensated_friction(g, Compensation::None, Mismatch{}), 0.01, 20.0);
  EXPECT_GT(std::abs(Ng0), 10.0);
}

// The Coulomb PI loop of CoulombPiThresholdMatchesClosedFormAndSimulation with the compensation
// on: its threshold cycle shrinks with the residual level, a = 4 Fc (1 - r) / (pi (N - sigma2)),
// and vanishes with perfect model-based compensation: the compensated nonlinearity is then 0 and
// no cycle is predicted, while the loop without compensation has one.
TEST(LimitCycle, CompensationShrinksTheThresholdCycleToTheResidualCoulombLevel) {
  std::mt19937 rng(1227);
  std::uniform_real_distribution<double> lk(2.5, 3.5), uz(3.0, 8.0), uc(0.3, 0.8), ur(0.2, 0.9);
  for (int i = 0; i < 6; ++i) {
    Plant pl{1.0, 0.0, 0.0};
    const double Kc = std::pow(10.0, lk(rng)), z = uz(rng);
    pl.damper = uc(rng) * z;
    ModelParams f = model_info("coulomb").defaults();
    const double Fc = f.scalar("Fc"), s2 = f.scalar("sigma2"), r = ur(rng);
    const LeadCompensator C{Kc, z, 0.0};
    Mismatch mm;
    mm.force = r;
    const LimitCycleReport rc = predict_limit_cycles(compensated_friction(f, Compensation::Coulomb, mm), pl, C);
    // The threshold cycle (the largest; the sign law also leaves a cycle at the scale of the
    // model's stick band v_stick, where the law ramps and the compensator does not).
    ASSERT_GE(rc.cycles.size(), 1u);
    const LimitCycle* big = &rc.cycles[0];
    for (const LimitCycle& c : rc.cycles)
      if (c.velocity_amplitude > big->velocity_amplitude) big = &c;
    for (const LimitCycle& c : rc.cycles)
      if (&c != big) { EXPECT_LT(c.velocity_amplitude, 100 * f.scalar("v_stick")); }
    const double Nq = z - pl.damper, w = std::sqrt(Kc);
    const double a = 4 * Fc * (1 - r) / (kPi * (Nq - s2));
    EXPECT_NEAR(big->velocity_amplitude, a, 0.01 * a) << "r = " << r;
    EXPECT_NEAR(big->frequency, w, 2e-3 * w);
    // Perfect model-based compensation (the compensator is the plant's own law, Karnopp stick band
    // included): nothing is left, no cycle; the loop without it has one.
    EXPECT_EQ(predict_limit_cycles(compensated_friction(f, Compensation::None, mm), pl, C).cycles.size(), 1u);
    const auto m1 = build_model(f), m2 = build_model(f);
    const LimitCycleReport rp = predict_limit_cycles(compensated(stepped(*m1), stepped(*m2)), pl, C);
    EXPECT_TRUE(rp.cycles.empty());
    EXPECT_FALSE(rp.note.empty());
    // The sign law Fc sgn(v) at the right level (r = 1, sigma2 = 0) compensates all but the
    // model's stick band |v| < vs, where the law ramps (F = Fc v / vs): the residual
    // -Fc (1 - |v|/vs) sgn v has N = -2 Fc vs^2 / (3 pi a^3) for a >> vs, negative, so it cannot
    // balance H's negative real crossing: no cycle either.
    mm.force = 1.0;
    f.set_scalar("sigma2", 0.0);
    const double vs = f.scalar("v_stick"), as = 20.0 * vs;
    const cplx Ns = describing_function(compensated_friction(f, Compensation::Coulomb, mm), as, w, {20000, 2});
    const double expect_s = -2 * Fc * vs * vs / (3 * kPi * as * as * as);
    EXPECT_NEAR(Ns.real(), expect_s, 0.05 * std::abs(expect_s));
    EXPECT_TRUE(predict_limit_cycles(compensated_friction(f, Compensation::Coulomb, mm), pl, C).cycles.empty());
  }
}
