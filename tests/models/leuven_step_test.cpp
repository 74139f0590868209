// The Leuven model's frozen-velocity step where its state equation is stiff: after a velocity jump
// |F_h| can exceed S(v) (F_h sits near Fs after slow sliding, S drops towards Fc at speed), and
// dz/dt = v (1 - sgn(u)|u|^n), u = F_h/s, relaxes at the rate (sum k) |v| n |u|^(n-1) / S - up to
// n |u|^(n-1) times faster than at u = 1. Expectations come from the model's equations: with v
// frozen, z moves monotonically to the fixed point F_h = s = sgn(v) S(v) (so a leg much longer than
// the presliding distance ends at steady_state(v)); the model is passive for sigma1 = 0 (the
// dissipation F_h (v - dz/dt) = |F_h| |v| |u|^n >= 0 plus the Maxwell-slip elements' own), so no
// closed displacement cycle may give out energy; and the result must not depend on the step size
// beyond the discretisation error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <utility>
#include <vector>

#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {
namespace {

struct Leg {
  double target;  // position at the end of the leg [m]
  double speed;   // |v| along the leg [m/s]
};

struct LegRun {
  double work = 0.0;        // sum F dx over all legs [J]
  double scale = 0.0;       // sum |F dx| [J]
  std::vector<double> end;  // force at the end of each leg [N]
};

// Drives the model from the virgin state through the legs at constant speed each, `steps` equal
// steps per leg, and sums the work of the force that acts over each step.
LegRun run_legs(const ModelParams& p, const std::vector<Leg>& legs, int steps, int cycles = 1) {
  const auto m = build_model(p);
  std::vector<double> state(m->state_size());
  m->reset(state);
  LegRun out;
  double x = 0.0;
  for (int c = 0; c < cycles; ++c) {
    for (const Leg& leg : legs) {
      const double x0 = x, dist = std::abs(leg.target - x0), h = dist / leg.speed / steps;
      double f = 0.0;
      for (int s = 1; s <= steps; ++s) {
        const double x1 = x0 + (leg.target - x0) * s / steps;
        f = m->step(state, {(x1 - x) / h, h, 0.0, 0.0});
        out.work += f * (x1 - x);
        out.scale += std::abs(f * (x1 - x));
        x = x1;
      }
      out.end.push_back(f);
    }
  }
  return out;
}

// Defaults with Fc = Fs / 3: after slow sliding (S = Fs) a fast leg starts at |u| = 3, where the
// relaxation is 8 * 3^7 / 8 = 2187 times faster than at |u| = 1.
ModelParams strong_stribeck() {
  ModelParams p = model_info("leuven").defaults();
  p.set_scalar("Fc", 0.5);
  return p;
}

// Slow sliding to -100 um at 5 um/s (F_h = -S(5 um/s) = -1.5 N), then reversal into fast sliding at
// 5 mm/s (S = 0.5 N). The elements reverse within 2 W_i / k_i <= 40 um, so the leg ends in steady
// sliding at steady_state(5 mm/s) = 0.5 + 0.4 * 5e-3 N.
TEST(LeuvenStep, ReversalFromSlowIntoFastSlidingEndsAtTheFastSteadyForce) {
  const ModelParams p = strong_stribeck();
  const auto m = build_model(p);
  for (int steps : {200, 2000}) {
    const LegRun r = run_legs(p, {{-100e-6, 5e-6}, {100e-6, 5e-3}}, steps);
    EXPECT_NEAR(r.end[0], m->steady_state(-5e-6), 1e-6) << steps << " steps per leg";
    EXPECT_NEAR(r.end[1], m->steady_state(5e-3), 1e-9) << steps << " steps per leg";
  }
}

// An independent integration of the raw equations: explicit Euler on z with every Jenkin element
// moved every micro-step, F = sum F_i + sigma2 v (sigma1 = 0 here); returns the work over the legs.
double fine_euler_work(const ModelParams& p, const std::vector<Leg>& legs, int micro_per_leg) {
  const auto k = p.column("k"), W = p.column("W");
  const Stribeck S{p.scalar("Fs"), p.scalar("Fc"), p.scalar("Vs"), p.scalar("delta")};
  const double n = p.scalar("n"), sigma2 = p.scalar("sigma2");
  std::vector<double> F(k.size(), 0.0);
  double x = 0.0, work = 0.0;
  for (const Leg& leg : legs) {
    const double v = (leg.target > x ? 1.0 : -1.0) * leg.speed;
    const double h = std::abs(leg.target - x) / leg.speed / micro_per_leg;
    const double s = sgn(v) * S(v);
    for (int i = 0; i < micro_per_leg; ++i) {
      double fh = 0.0;
      for (double f : F) fh += f;
      const double u = fh / s, dz = v * (1.0 - std::copysign(std::pow(std::abs(u), n), u)) * h;
      fh = 0.0;
      for (std::size_t j = 0; j < F.size(); ++j)
        fh += F[j] = std::clamp(F[j] + k[j] * dz, -W[j], W[j]);
      work += (fh + sigma2 * v) * v * h;
    }
    x = leg.target;
  }
  return work;
}

// The same speed jump inside a closed cycle 0 -> -100 um (slow) -> 0 (fast): the friction takes
// energy, as much as the fine independent integration says (the fast leg's micro-step of 10 ns is
// below 1 / the largest relaxation rate, 27 ns), and the work converges with the step count.
TEST(LeuvenStep, ClosedCycleThroughASpeedJumpTakesTheEnergyOfAFineIntegration) {
  const ModelParams p = strong_stribeck();
  const std::vector<Leg> legs{{-100e-6, 5e-6}, {0.0, 5e-3}};
  const double reference = fine_euler_work(p, legs, 2000000);
  EXPECT_GT(reference, 0.0);
  for (int steps : {200, 2000, 20000})
    EXPECT_NEAR(run_legs(p, legs, steps).work, reference, 1e-2 * reference) << steps << " steps";
}

// One step much longer than the relaxation time S / ((sum k) |v| n) = 0.6 us lands on the fixed
// point F_h = sgn(v) S(v): from the virgin state, and after slow sliding the other way (|u| = 1.5
// at the start of the step, relaxation 8 * 1.5^7 / 8 = 17 times faster still).
TEST(LeuvenStep, OneLongStepLandsOnTheSlidingFixedPoint) {
  const ModelParams p = model_info("leuven").defaults();
  const auto m = build_model(p);
  for (const double h : {1e-4, 1e-3, 1e-2, 1.0}) {
    std::vector<double> state(m->state_size());
    m->reset(state);
    EXPECT_NEAR(m->step(state, {1.0, h}), m->steady_state(1.0), 1e-9) << "virgin, h = " << h;
    for (int i = 0; i < 100; ++i) m->step(state, {-1e-6, 1e-1});  // slow sliding backwards
    EXPECT_NEAR(m->step(state, {1.0, h}), m->steady_state(1.0), 1e-9) << "reversal, h = " << h;
  }
}

// An element loaded to 500 N that must unload to the fixed point F_h = -0.004 N: F_i + k_i dz can
// only resolve F_h to ulp(500 N) = 1.1e-13 N, far coarser than the level 0.004 N itself. The step
// must settle there (an earlier stop rule asked for F_h within 4 eps |s| and ran into its 1e6
// sub-step guard).
TEST(LeuvenStep, SettlesOnTheFixedPointToTheRoundingOfItsElementForces) {
  const ModelParams p{"leuven", {0.004, 0.004, 1e-3, 2.0, 8.0, 0.0, 0.0}, {{1e6, 1000.0}}};
  ASSERT_TRUE(validate(p).empty());
  const auto m = build_model(p);
  std::vector<double> state{500.0, 0.0};
  EXPECT_NEAR(m->step(state, {-0.8, 1e-2}), m->steady_state(-0.8), 1e-12);
}

double log_uniform(std::mt19937& rng, double lo, double hi) {
  return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
}

// Random parameters (defaults scaled by [1/3, 3], 1-8 elements; every other set with a sigma1 up
// to Fc / 0.1 m/s, inside the model's passivity bound sigma1 |v| <= Fc) and closed cycles through
// random turning points with a random speed per leg (1 um/s .. 0.1 m/s, so the speed jumps at
// every turning point): the friction never gives out energy.
TEST(LeuvenStep, ClosedCyclesWithRandomSpeedJumpsNeverCreateEnergy) {
  const ModelInfo& info = model_info("leuven");
  std::mt19937 rng(19);
  for (int set = 0; set < 150; ++set) {
    ModelParams p;
    do {
      p = info.defaults();
      auto scale = [&](double& x, const ParamSpec& s) {
        const double y = x * log_uniform(rng, 1.0 / 3.0, 3.0);
        if (s.allowed(y)) x = y;
      };
      for (std::size_t i = 0; i < p.scalars.size(); ++i) scale(p.scalars[i], info.scalars[i]);
      const auto proto = p.elements;
      p.elements.clear();
      for (std::size_t r = 0, n = 1 + rng() % 8; r < n; ++r) {
        auto row = proto[r % proto.size()];
        for (std::size_t c = 0; c < row.size(); ++c) scale(row[c], info.columns[c]);
        p.elements.push_back(row);
      }
    } while (!validate(p).empty());
    if (set % 2 == 1)
      p.set_scalar("sigma1",
                   std::uniform_real_distribution<double>(0.0, 10.0)(rng) * p.scalar("Fc"));
    const double amp = log_uniform(rng, 1e-7, 1e-3);
    std::vector<Leg> legs;
    for (int k = 0, n = 2 + static_cast<int>(rng() % 6); k <= n; ++k)
      legs.push_back({k == n ? 0.0 : std::uniform_real_distribution<double>(-amp, amp)(rng),
                      log_uniform(rng, 1e-6, 1e-1)});
    const LegRun r = run_legs(p, legs, 300, 3);
    std::ostringstream o;
    o.precision(17);
    for (double x : p.scalars) o << ' ' << x;
    o << " |";
    for (const auto& row : p.elements) o << " [" << row[0] << ' ' << row[1] << ']';
    o << " | legs";
    for (const Leg& l : legs) o << ' ' << l.target << '@' << l.speed;
    ASSERT_GE(r.work, -1e-9 * r.scale)
        << "set " << set << ": the friction gave out " << -r.work << " J;" << o.str();
  }
}

// The step goes straight to the fixed point only when the relaxation certainly gets there within
// the step (it is what makes long steps of fast sliding cheap). Steps of 1 to 400 times
// tau = 0.6 us from the virgin state at 1 m/s (the elements first load from u = 0, then relax; 16
// tau still ends 1.6 % short of the fixed point, 100 tau on it): each must agree with a fine
// independent integration of the same step. A jump taken too early fails the short ones.
TEST(LeuvenStep, StepsAroundTheRelaxationTimeAgreeWithAFineIntegration) {
  const ModelParams p = model_info("leuven").defaults();
  const auto m = build_model(p);
  const double v = 1.0, tau = 0.6e-6;
  const double fixed = m->steady_state(v);
  bool saw_short = false, saw_settled = false;
  for (const double steps_tau : {1.0, 4.0, 16.0, 40.0, 100.0, 400.0}) {
    const double h = steps_tau * tau;
    std::vector<double> state(m->state_size());
    m->reset(state);
    const double f = m->step(state, {v, h});
    const auto k = p.column("k"), W = p.column("W");
    const Stribeck S{p.scalar("Fs"), p.scalar("Fc"), p.scalar("Vs"), p.scalar("delta")};
    const double n = p.scalar("n"), s = S(v);
    std::vector<double> F(k.size(), 0.0);
    const int micro = 400000;
    for (int i = 0; i < micro; ++i) {
      double fh = 0.0;
      for (double fi : F) fh += fi;
      const double dz = v * (1.0 - std::copysign(std::pow(std::abs(fh / s), n), fh / s)) * (h / micro);
      for (std::size_t j = 0; j < F.size(); ++j) F[j] = std::clamp(F[j] + k[j] * dz, -W[j], W[j]);
    }
    double end = p.scalar("sigma2") * v;
    for (double fi : F) end += fi;
    EXPECT_NEAR(f, end, 2e-5 * s) << h / tau << " relaxation times";
    saw_short |= std::abs(end - fixed) > 1e-3 * s;
    saw_settled |= std::abs(end - fixed) < 1e-9 * s;
  }
  EXPECT_TRUE(saw_short);    // the range covers steps that must not jump ...
  EXPECT_TRUE(saw_settled);  // ... and steps that settle
}

}  // namespace
}  // namespace gmslab
