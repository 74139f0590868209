// The hunting (stick-slip limit cycle) of PI / PID loops with friction predicted by the describing
// function of the mass with its friction and the controller's fast part (core/control/hunting.hpp),
// checked against the loop simulated with friction (core/control/loop_simulation.hpp): the
// simulated cycle is measured independently (half peak-to-peak of x and the mean spacing of upward
// mean crossings over the steady tail).
#include <gtest/gtest.h>

#include <cstdlib>

#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/control/hunting.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/friction/model.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
constexpr double kPi = std::numbers::pi;

struct Measured {
  bool hunting = false;
  double amplitude = 0, period = 0;
};
// The steady cycle over the last `frac` of the run: half peak-to-peak and the mean spacing of the
// upward crossings of the mid level (hysteresis of a quarter amplitude); at least 4 cycles, and the
// second half of the window with the same amplitude within 5 % (steady).
Measured measure(const LoopTrace& tr, double frac) {
  Measured m;
  const std::size_t n = tr.t.size(), i0 = static_cast<std::size_t>((1 - frac) * (n - 1));
  const std::size_t im = (i0 + n) / 2;
  double lo = 1e300, hi = -1e300, lo2 = 1e300, hi2 = -1e300;
  for (std::size_t i = i0; i < n; ++i) {
    lo = std::min(lo, tr.x[i]), hi = std::max(hi, tr.x[i]);
    if (i >= im) lo2 = std::min(lo2, tr.x[i]), hi2 = std::max(hi2, tr.x[i]);
  }
  const double amp = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
  std::vector<std::size_t> ups;
  bool below = tr.x[i0] < mid;
  for (std::size_t i = i0 + 1; i < n; ++i) {
    if (below && tr.x[i] > mid + 0.25 * amp) ups.push_back(i), below = false;
    else if (!below && tr.x[i] < mid - 0.25 * amp) below = true;
  }
  if (ups.size() < 5 || amp < 1e-8 || std::abs(0.5 * (hi2 - lo2) - amp) > 0.05 * amp) return m;
  m.hunting = true;
  m.amplitude = amp;
  m.period = (tr.t[ups.back()] - tr.t[ups.front()]) / static_cast<double>(ups.size() - 1);
  return m;
}

Measured simulate(const Scenario& s, const LeadCompensator& C, double period_hint) {
  LoopConfig cfg;
  cfg.C = C;
  cfg.reference = Signal::constant(0.01);
  cfg.dt = 1e-5;
  cfg.duration = std::clamp(25.0 * period_hint, 20.0, 80.0);
  cfg.record_every = 10;
  return measure(simulate_loop(s, cfg), 0.4);
}
}  // namespace

// The integral split C = R/s + C_f: C_f(s) + R/s equals C(s) at random points (PI and PID).
TEST(HuntingDf, IntegralSplitRecomposesTheCompensator) {
  std::mt19937 rng(1240);
  std::uniform_real_distribution<double> lk(1.0, 4.0), lz(-1.0, 2.0);
  for (int i = 0; i < 100; ++i) {
    const double Kc = std::pow(10.0, lk(rng)), z = std::pow(10.0, lz(rng)), zi = std::pow(10.0, lz(rng)) * 0.1;
    const double p = z * (2.0 + 10.0 * (i % 7));
    for (const LeadCompensator& C : {LeadCompensator{Kc, z, 0.0}, LeadCompensator{Kc, z, p, Section{zi, 0.0}},
                                     LeadCompensator{Kc, zi, 0.0, Section{z, p}}}) {
      const auto sp = integral_split(C);
      ASSERT_TRUE(sp.has_value());
      for (double w : {0.1, 1.0, 10.0, 100.0}) {
        const cplx s(0.0, w);
        const cplx Cf = sp->fast.d + (sp->fast.a > 0.0 ? sp->fast.cst / (s + sp->fast.a) : cplx(0.0));
        const cplx expect = C.tf()(s);
        EXPECT_LT(std::abs(Cf + sp->R / s - expect), 1e-9 * std::abs(expect));
      }
    }
  }
  EXPECT_FALSE(integral_split(LeadCompensator{100.0, 5.0, 50.0}).has_value());                     // lead
  EXPECT_FALSE(integral_split(LeadCompensator{100.0, 5.0, 0.0, Section{1.0, 0.0}}).has_value());  // double
}

// Ideal stick-slip (Coulomb Fs > Fc, no damping, fast slips against a slow integrator): x is a
// square wave of level X = (Fs - Fc)/Kc and u_I a triangle, so the triangle describing function is
// exact in that limit: the block's P at the cycle is (4/pi) X / ((8/pi^2) A) and w = R |P|.
TEST(HuntingDf, BlockOfIdealStickSlipIsASquareWave) {
  std::mt19937 rng(1241);
  std::uniform_real_distribution<double> uf(1.2, 2.5), um(0.5, 3.0);
  for (int i = 0; i < 10; ++i) {
    ModelParams fr = model_info("coulomb").defaults();
    const double Fc = 1.0, Fs = uf(rng) * Fc;
    fr.set_scalar("Fc", Fc), fr.set_scalar("Fs", Fs), fr.set_scalar("sigma2", 0.0);
    const auto m = build_model(fr);
    const Plant pl{um(rng), 0.0, 0.0};
    const double Kc = 2000.0, X = (Fs - Fc) / Kc;
    const double A = Fc * 1.02, w = 0.05;  // slips of ~pi sqrt(m/Kc) << 2 pi / w
    HuntingOptions o;
    o.max_step = 0.02 * std::sqrt(pl.mass / Kc);
    o.max_steps = 1000000;
    const PlantHarmonics ph = plant_harmonics(pl, *m, FastPart{Kc, 0.0, 0.0}, A, w, o);
    EXPECT_NEAR(ph.half_pp, X, 0.03 * X) << "Fs=" << Fs << " m=" << pl.mass;
    EXPECT_NEAR(std::abs(ph.X1), 4.0 / kPi * X, 0.04 * X);
    EXPECT_NEAR(std::arg(ph.P) * 180 / kPi, -90.0, 8.0);
  }
}

// The predictions against simulation over random loops, counted case by case: periodic orbits
// (tests/control/limit_cycles_test.cpp), which replace the describing function's agreement checks.

// A lead loop (no integrator) has no predicted hunting, and its simulation comes to rest.
TEST(HuntingDf, LeadLoopHasNoPredictedHuntingAndDoesNotHunt) {
  Scenario s;
  s.plant = {1.0, 0.0, 3.0};
  s.friction = model_info("stribeck").defaults();
  const LeadCompensator lead{1000.0, 5.0, 200.0};
  const HuntingReport r = predict_hunting(s.plant, s.friction, lead);
  EXPECT_TRUE(r.cycles.empty());
  EXPECT_EQ(r.hunting(), nullptr);
  EXPECT_FALSE(r.note.empty());
  EXPECT_FALSE(simulate(s, lead, 1.0).hunting);
}

// The sine drive (the classical describing function) of the same block is biased on stick-slip:
// the integral force is a triangle, whose peak (which the break-away sees) is pi^2/8 x its first
// harmonic, so with a sine of the same first harmonic the block breaks away later; measured on the
// Coulomb PI case of the Design view the sine's period is longer than the triangle's and than the
// simulated one.
TEST(HuntingDf, SineDriveIsBiasedOnStickSlip) {
  Scenario s;
  s.plant = {1.0, 0.0, 3.0};
  s.friction = model_info("coulomb").defaults();
  const LeadCompensator C{1000.0, 5.0, 0.0};
  HuntingOptions o;
  const HuntingReport tri = predict_hunting(s.plant, s.friction, C, o);
  o.wave = DriveWave::Sine;
  const HuntingReport sine = predict_hunting(s.plant, s.friction, C, o);
  ASSERT_NE(tri.hunting(), nullptr);
  const Measured sim = simulate(s, C, 2.0);
  ASSERT_TRUE(sim.hunting);
  std::printf("triangle %.4g s, sine %s%.4g s, simulated %.4g s\n", tri.hunting()->period,
              sine.hunting() ? "" : "(none) ", sine.hunting() ? sine.hunting()->period : NAN, sim.period);
  if (sine.hunting()) {
    EXPECT_GT(sine.hunting()->period, 1.15 * sim.period);
    EXPECT_GT(sine.hunting()->period, tri.hunting()->period);
  }
}
