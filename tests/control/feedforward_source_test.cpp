// Friction compensation driven by the measured velocity (LoopConfig::feedforward_source): the loop
// simulation against what the describing function's compensated nonlinearity F - F_hat predicts
// (Coulomb with Fc_hat = r Fc: the PI threshold cycle at the residual level), perfect GMS
// compensation against the frictionless linear loop, and the design session's compensated DF row.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/control/design_plant.hpp"
#include "core/control/design_session.hpp"
#include "core/control/describing_function.hpp"
#include "core/control/linear_response.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/friction/model.hpp"
#include "core/sim/assembly.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
constexpr double kPi = std::numbers::pi;

// Max |x - amp y_lin| / amp over the recorded samples of the loop (record spacing = the linear
// step's sample spacing).
double max_step_error(const Scenario& s, LoopConfig cfg, const StepResponse& lin, double amp) {
  const LoopTrace tr = simulate_loop(s, cfg);
  EXPECT_EQ(tr.t.size(), lin.t.size());
  double e = 0.0;
  for (std::size_t i = 0; i < std::min(tr.t.size(), lin.t.size()); ++i)
    e = std::max(e, std::abs(tr.x[i] - amp * lin.y[i]));
  return e / amp;
}
}  // namespace

TEST(FeedforwardSource, NamesRoundTripAndOthersAreRejected) {
  for (auto f : {FeedforwardSource::Reference, FeedforwardSource::Measured})
    EXPECT_EQ(feedforward_source_from_string(to_string(f)), f);
  EXPECT_FALSE(feedforward_source_from_string("velocity"));
  EXPECT_FALSE(feedforward_source_from_string(""));
  EXPECT_EQ(LoopConfig{}.feedforward_source, FeedforwardSource::Reference);  // the default is unchanged
}

// GMS friction compensated by its own GMS model (mismatch 1) driven by the measured velocity: the
// compensator's model, stepped with the plant's v, cancels the friction force step by step, so the
// loop is the frictionless one: random plants (m, c, k) and compensators (lead, lag, PI, PID) follow
// the linear closed-loop step (core/control/linear_response) within 5e-4 of the step, to first
// order in dt; without compensation, or with the reference-driven one (0 at the set point), the
// friction is felt (errors > 20x larger).
TEST(FeedforwardSource, MeasuredPerfectGmsCompensationGivesTheFrictionlessLinearLoop) {
  std::mt19937 rng(1230);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 40 && checked < 8; ++trial) {
    Scenario s;
    const double m = 0.5 + 2.5 * u(rng);
    s.plant = {m, trial % 2 ? 100 + 900 * u(rng) : 0.0, 2 + 20 * u(rng)};
    s.friction = model_info("gms").defaults();
    const double fs = 0.5 + 2 * u(rng);
    s.friction.set_scalar("Fs", s.friction.scalar("Fs") * fs);
    s.friction.set_scalar("Fc", s.friction.scalar("Fc") * fs);
    const double wn = 15 + 30 * u(rng);
    LeadCompensator c;
    switch (trial % 4) {
      case 0: c = {m * wn * wn * (0.5 + u(rng)), wn * (0.2 + 0.5 * u(rng)), wn * (5 + 10 * u(rng))}; break;  // lead
      case 1: c = {m * wn * wn * (0.5 + u(rng)), wn * (0.05 + 0.1 * u(rng)), wn * 0.01 * u(rng)}; break;  // lag
      case 2: c = {m * wn * wn * (0.5 + u(rng)), wn * (0.05 + 0.2 * u(rng)), 0.0}; break;                 // PI
      default:                                                                                               // PID
        c = {m * wn * wn * (0.5 + u(rng)), wn * (0.2 + 0.5 * u(rng)), wn * (5 + 10 * u(rng)),
             Section{wn * (0.05 + 0.2 * u(rng)), 0.0}};
    }
    const TransferFunction T = closed_loop({Poly({1.0}), Poly({s.plant.spring, s.plant.damper, m})}, c);
    bool stable = true;
    for (const cplx& p : T.poles()) stable = stable && p.real() < -0.5;
    if (!stable) continue;
    ++checked;
    const double amp = 2e-3 * (1 + 4 * u(rng)), duration = 1.5;
    const int n = 151;
    const StepResponse lin = step_response(T, duration, n);
    LoopConfig cfg;
    cfg.reference = Signal::constant(amp);
    cfg.C = c;
    cfg.duration = duration;
    cfg.comp = Compensation::Gms;
    cfg.feedforward_source = FeedforwardSource::Measured;
    auto at = [&](double dt, LoopConfig k) {
      k.dt = dt;
      k.record_every = static_cast<int>(std::lround(duration / (n - 1) / dt));
      return max_step_error(s, k, lin, amp);
    };
    const double e1 = at(2e-5, cfg), e2 = at(1e-5, cfg);
    EXPECT_LT(e2, 5e-4) << "trial " << trial;
    EXPECT_LT(e2, 0.6 * e1) << "first order: " << e1 << " -> " << e2;
    LoopConfig plain = cfg;
    plain.comp = Compensation::None;
    EXPECT_GT(at(1e-5, plain), 20 * e2) << "trial " << trial << ": the friction must be felt without compensation";
    LoopConfig by_reference = cfg;
    by_reference.feedforward_source = FeedforwardSource::Reference;
    EXPECT_GT(at(1e-5, by_reference), 20 * e2) << "trial " << trial << ": v_ref = 0 at the set point";
  }
  EXPECT_GE(checked, 6);
}

// Coulomb friction (Fs = Fc: the law of the closed form) in a PI loop (1 kg, damper c < z, Kc, z
// random) with a Coulomb compensator Fc_hat = r Fc (r random in [0.2, 0.8]) driven by the measured
// velocity: the residual Coulomb level Fc (1 - r) sets the threshold cycle, a = 4 Fc (1 - r) /
// (pi (z - c - sigma2)) at w = sqrt(Kc) (closed form of
// LimitCycle.CompensationShrinksTheThresholdCycleToTheResidualCoulombLevel; position amplitude
// a / w). Simulated: started at 0.5x that amplitude the loop does not hunt and creeps to the set
// point; at 2x the oscillation grows. Where 2x the compensated threshold is below 0.7x the
// uncompensated one (r > 0.7), the same start with the reference-driven compensation (0 at a set
// point: the friction alone) does not grow: it is the measured-velocity compensation that moves it.
// With stiction (Fs = 1.5 Fc) the compensation, 0 at standstill, leaves the full Fs to break away
// but only Fc (1 - r) while sliding: below the threshold the loop may then hunt by stick-slip
// (outside the DF, measured e.g. at r = 0.85: 0.26-0.75 A, period 0.16-0.5 s against the DF's
// 0.12 s); it stays bounded below A, and 2x still grows.
TEST(FeedforwardSource, MeasuredCoulombCompensationThresholdFollowsTheCompensatedClosedForm) {
  std::mt19937 rng(1231);
  std::uniform_real_distribution<double> lk(2.5, 3.5), uz(3.0, 8.0), uc(0.3, 0.7), ur(0.2, 0.8);
  int contrasted = 0;
  for (int i = 0; i < 8; ++i) {
    Scenario s;
    const double Kc = std::pow(10.0, lk(rng)), z = uz(rng), r = i == 0 ? 0.75 : ur(rng);
    s.plant = {1.0, 0.0, uc(rng) * z};
    s.friction = model_info("coulomb").defaults();
    const double Fc = s.friction.scalar("Fc"), s2 = s.friction.scalar("sigma2");
    s.friction.set_scalar("Fs", Fc);
    const double w = std::sqrt(Kc), Nq = z - s.plant.damper;
    ASSERT_GT(Nq, s2);
    const double A = 4 * Fc * (1 - r) / (kPi * (Nq - s2)) / w;  // position amplitude [m]
    LoopConfig cfg;
    cfg.C = {Kc, z, 0.0};
    cfg.comp = Compensation::Coulomb;
    cfg.feedforward_source = FeedforwardSource::Measured;
    cfg.mismatch.force = r;
    cfg.dt = 2e-5;
    cfg.duration = 8.0;
    cfg.record_every = 20;
    cfg.reference = Signal::constant(0.5 * A);
    const LoopMetrics below = loop_metrics(simulate_loop(s, cfg));
    EXPECT_FALSE(below.hunting) << "r = " << r;
    EXPECT_LT(below.tail_max_error, 0.5 * A) << "r = " << r;
    auto grows = [&](const Scenario& sc, const LoopConfig& k) {
      try {
        const LoopTrace tr = simulate_loop(sc, k);
        const LoopMetrics m = loop_metrics(tr);
        return m.cycle_amplitude > 10 * A || std::abs(tr.x.back()) > 100 * A;
      } catch (const SimulationError&) {
        return true;
      }
    };
    LoopConfig above = cfg;
    above.reference = Signal::constant(2.0 * A);
    EXPECT_TRUE(grows(s, above)) << "r = " << r;
    if (r > 0.7) {
      ++contrasted;
      LoopConfig by_reference = above;
      by_reference.feedforward_source = FeedforwardSource::Reference;
      EXPECT_FALSE(grows(s, by_reference)) << "r = " << r;
    }
    Scenario stiction = s;
    stiction.friction.set_scalar("Fs", 1.5 * Fc);
    const LoopMetrics stuck = loop_metrics(simulate_loop(stiction, cfg));
    EXPECT_LT(stuck.tail_max_error, A) << "r = " << r << ": stick-slip stays below the threshold";
    EXPECT_TRUE(grows(stiction, above)) << "r = " << r;
  }
  EXPECT_GE(contrasted, 1);
}

// The design session with the measured-velocity compensation predicts the compensated loop's cycle
// on F - F_hat: a Coulomb PI loop with the Coulomb compensator at r gives the residual threshold
// (closed form, 2 %), while the reference-driven compensation repeats the uncompensated prediction.
TEST(FeedforwardSource, DesignSessionPredictsTheCompensatedLoopWithTheCompensatedNonlinearity) {
  std::mt19937 rng(1232);
  std::uniform_real_distribution<double> ur(0.2, 0.8);
  for (int i = 0; i < 3; ++i) {
    DesignInputs in;
    in.scenario.plant = {1.0, 0.0, 2.0};
    in.scenario.friction = model_info("coulomb").defaults();
    in.manual = LeadCompensator{1000.0, 5.0, 0.0};
    in.compensation = Compensation::Coulomb;
    const double r = ur(rng);
    in.mismatch.force = r;
    in.simulate = false;
    in.feedforward_source = FeedforwardSource::Measured;
    const DesignOutputs out = compute_design(in);
    ASSERT_TRUE(out.limit_cycles && out.compensated().limit_cycles) << out.error;
    const double Fc = in.scenario.friction.scalar("Fc"), s2 = in.scenario.friction.scalar("sigma2");
    const double a = 4 * Fc * (1 - r) / (kPi * (5.0 - 2.0 - s2)), a0 = a / (1 - r);
    double big = 0.0, big0 = 0.0;
    for (const auto& c : out.compensated().limit_cycles->cycles) big = std::max(big, c.velocity_amplitude);
    for (const auto& c : out.limit_cycles->cycles) big0 = std::max(big0, c.velocity_amplitude);
    EXPECT_NEAR(big, a, 0.02 * a) << "r = " << r;
    EXPECT_NEAR(big0, a0, 0.02 * a0);
    in.feedforward_source = FeedforwardSource::Reference;
    const DesignOutputs ref = compute_design(in);
    ASSERT_TRUE(ref.compensated().limit_cycles);
    ASSERT_EQ(ref.compensated().limit_cycles->cycles.size(), ref.limit_cycles->cycles.size());
    for (std::size_t k = 0; k < ref.limit_cycles->cycles.size(); ++k)
      EXPECT_EQ(ref.compensated().limit_cycles->cycles[k].amplitude, ref.limit_cycles->cycles[k].amplitude);
  }
}

// On an assembled plant the measured source drives the feedforward with the drive's body velocity:
// a one-body assembly (assembly_from_scenario) gives the one-body loop's trace with it too (GMS
// and Coulomb compensation, random plants and mismatch), and it differs from the reference-driven
// run (the source is used).
TEST(FeedforwardSource, OneBodyAssemblyWithMeasuredFeedforwardMatchesTheOneBodyLoop) {
  std::mt19937 rng(1233);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    Scenario s;
    s.name = "one body";
    s.friction = model_info("gms").defaults();
    s.plant = {0.5 + 2 * u(rng), 100 * u(rng), 2 * u(rng)};
    s.drive.kind = Drive::Kind::Force;
    s.drive.signal = Signal::constant(0.0);
    const AssemblyScenario as = assembly_from_scenario(s);
    const AssemblyPort port = assembly_port(as.plant, "", "");
    LoopConfig cfg;
    cfg.reference = Signal::constant(2e-3 * (1 + u(rng)));
    cfg.C = {200 + 2000 * u(rng), 5 + 20 * u(rng), 0.0};
    cfg.C.p = cfg.C.z * (2 + 10 * u(rng));
    cfg.comp = trial % 2 ? Compensation::Coulomb : Compensation::Gms;
    cfg.feedforward_source = FeedforwardSource::Measured;
    cfg.mismatch.force = 0.6 + 0.3 * u(rng);
    cfg.dt = 2e-5;
    cfg.duration = 0.4;
    cfg.record_every = 7;
    const LoopTrace a = simulate_loop(s, cfg);
    const LoopTrace b = simulate_loop(as, port, cfg);
    ASSERT_EQ(a.t.size(), b.t.size());
    double scale_x = 1e-12, scale_f = 1e-12;
    for (std::size_t i = 0; i < a.t.size(); ++i)
      scale_x = std::max(scale_x, std::abs(a.x[i])), scale_f = std::max(scale_f, std::abs(a.u[i]) + std::abs(a.ff[i]));
    for (std::size_t i = 0; i < a.t.size(); ++i) {
      EXPECT_NEAR(a.x[i], b.x[i], 1e-9 * scale_x) << trial << " at " << a.t[i];
      EXPECT_NEAR(a.ff[i], b.ff[i], 1e-9 * scale_f) << trial << " at " << a.t[i];
    }
    LoopConfig by_reference = cfg;
    by_reference.feedforward_source = FeedforwardSource::Reference;
    const LoopTrace c = simulate_loop(as, port, by_reference);
    double d = 0.0;
    for (std::size_t i = 0; i < c.t.size(); ++i) d = std::max(d, std::abs(c.ff[i] - b.ff[i]));
    EXPECT_GT(d, 0.1 * s.friction.scalar("Fc")) << trial;
  }
}
