// The designed lead loop simulated with GMS friction: steady-state ramp errors against the force
// balance u_dc + u_ff = F_ss(v_ref), the GMS feedforward's reduction of the friction error, the
// scenario's linear plants, the linear step response against the analytic second-order response,
// and the limit-cycle metrics on a known oscillation.
#include <gtest/gtest.h>

#include <cmath>

#include "core/control/lead_design.hpp"
#include "core/control/linear_response.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/control/scenario_plant.hpp"
#include "core/error.hpp"
#include "core/io/scenario_io.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
Scenario fig4() { return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"); }

// Lead for the sliding plant of the Fig. 4 mass (m = 1 kg, sigma2 = 0.4 N s/m): zeta 0.7,
// wn 60 rad/s, Kv = 1000 1/s.
LeadCompensator sliding_design(const Scenario& s) {
  const LinearPlant lp = linear_plant(s, Regime::Sliding);
  const LeadDesign d = design_for_constant(lp.g, {0.7, 60.0}, 1000.0);
  return {d.Kc, d.z, d.p};
}

LoopMetrics run(const Scenario& s, const LeadCompensator& c, Signal ref, Compensation comp,
                Mismatch mm = {}, double T = 0.0) {
  LoopConfig cfg;
  cfg.C = c;
  cfg.reference = std::move(ref);
  cfg.comp = comp;
  cfg.mismatch = mm;
  cfg.sample_time = T;
  cfg.duration = 2.0;
  return loop_metrics(simulate_loop(s, cfg));
}
}  // namespace

TEST(ScenarioPlant, PreslidingAddsElementStiffnessAndSlidingUsesTheStribeckSlope) {
  const Scenario s = fig4();
  const LinearPlant pre = linear_plant(s, Regime::Presliding);
  EXPECT_DOUBLE_EQ(pre.stiffness, 75000 + 60000 + 45000 + 30000);
  EXPECT_NEAR(pre.damping, 65.25 + 52.2 + 39.15 + 26.1 + 0.4, 1e-9);
  // Sliding at v0 = Vs: dS/dv = -(Fs - Fc) 2 v / Vs^2 exp(-(v/Vs)^2), plus sigma2.
  const LinearPlant sl = linear_plant(s, Regime::Sliding, 1e-3);
  EXPECT_NEAR(sl.damping, -0.5 * 2.0 / 1e-3 * std::exp(-1.0) + 0.4, 1e-3);
  EXPECT_DOUBLE_EQ(sl.stiffness, 0.0);
  // Default v0 = 10 Vs: the Stribeck slope has died out, only sigma2 is left.
  EXPECT_NEAR(linear_plant(s, Regime::Sliding).damping, 0.4, 1e-9);
}

TEST(LinearStepResponse, DesignWithExactPoleZeroCancellationIsTheSecondOrderResponse) {
  // G1 with the Kv = 4 lead: the third pole -2 cancels the zero -2, so the loop is
  // 16 / (s^2 + 4 s + 16): y = 1 - e^{-2t} (cos wd t + (2/wd) sin wd t), wd = sqrt(12).
  const TransferFunction G{Poly::descending({4}), Poly::descending({1, 2, 0})};
  const LeadDesign d = design_for_constant(G, {0.5, 4.0}, 4.0);
  const StepResponse r = step_response(closed_loop(G, {d.Kc, d.z, d.p}), 4.0, 401);
  const double wd = std::sqrt(12.0);
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    const double t = r.t[i];
    const double y = 1 - std::exp(-2 * t) * (std::cos(wd * t) + 2 / wd * std::sin(wd * t));
    ASSERT_NEAR(r.y[i], y, 1e-9) << t;
  }
}

TEST(LoopWithGmsFriction, RampErrorFollowsTheForceBalanceAndGmsFeedforwardRemovesIt) {
  const Scenario s = fig4();
  const LeadCompensator c = sliding_design(s);
  const double k_dc = c.Kc * c.z / c.p;  // lead's static gain [N/m]
  const double v = 0.01;                 // ramp velocity [m/s] = 10 Vs
  const double S = 1.0 + 0.5 * std::exp(-100.0);
  const double Fss = S + 0.4 * v;
  const Signal ramp = Signal::ramp(0.0, v);
  // No compensation: the controller supplies all of F_ss: e = F_ss / k_dc = 2.51 mm.
  const LoopMetrics none = run(s, c, ramp, Compensation::None);
  EXPECT_NEAR(none.steady_state_error, Fss / k_dc, 1e-3 * Fss / k_dc);
  EXPECT_NEAR(none.steady_state_error, 2.51e-3, 1e-5);
  // Coulomb feedforward Fc sgn(v_ref): the viscous part is left, e = sigma2 v / k_dc.
  const LoopMetrics coul = run(s, c, ramp, Compensation::Coulomb);
  EXPECT_NEAR(coul.steady_state_error, 0.4 * v / k_dc, 1e-3 * 0.4 * v / k_dc);
  // GMS feedforward with the plant's own model: F_ff = F_ss, e -> 0.
  const LoopMetrics gms = run(s, c, ramp, Compensation::Gms);
  EXPECT_LT(std::abs(gms.steady_state_error), 1e-9);
  EXPECT_LT(gms.rms_error, 0.02 * none.rms_error);
  // Mismatch: the compensator's force levels 80 % of the plant's: e = 0.2 S / k_dc.
  const LoopMetrics mm = run(s, c, ramp, Compensation::Gms, {0.8, 1.0, 1.0});
  EXPECT_NEAR(mm.steady_state_error, 0.2 * S / k_dc, 1e-3 * 0.2 * S / k_dc);
}

TEST(LoopWithGmsFriction, SineTrackingErrorIsCutByTheFeedforward) {
  const Scenario s = fig4();
  const LeadCompensator c = sliding_design(s);
  const Signal sine = Signal::sine(0.0, 0.01, 1.0);  // 10 mm, 1 Hz
  const LoopMetrics none = run(s, c, sine, Compensation::None);
  const LoopMetrics gms = run(s, c, sine, Compensation::Gms);
  const LoopMetrics coul = run(s, c, sine, Compensation::Coulomb);
  // Measured: none 1.87 mm rms (the mass sticks at each reversal until e reaches Fs / k_dc),
  // GMS 0.60 mm, Coulomb 0.59 mm.
  EXPECT_NEAR(none.rms_error, 1.87e-3, 0.05e-3);
  EXPECT_LT(gms.rms_error, 0.4 * none.rms_error);
  EXPECT_LT(coul.rms_error, 0.4 * none.rms_error);
  EXPECT_TRUE(std::isnan(none.overshoot));
}

TEST(LoopWithGmsFriction, StepStopsInsideTheStictionBandOfTheLeadsStaticGain) {
  // A lead has no integrator: the mass sticks once |k_dc e| < Fs, leaving an error.
  const Scenario s = fig4();
  const LeadCompensator c = sliding_design(s);
  const LoopMetrics m = run(s, c, Signal::constant(0.01), Compensation::None);
  const double band = 1.5 / (c.Kc * c.z / c.p);
  EXPECT_GT(std::abs(m.steady_state_error), 1e-5);
  EXPECT_LT(std::abs(m.steady_state_error), band);
  EXPECT_FALSE(m.hunting);
  EXPECT_GT(m.overshoot, 0.0);
  EXPECT_GT(m.settling_time, 0.0);
}

TEST(LoopWithGmsFriction, TustinControllerConvergesToTheContinuousOne) {
  const Scenario s = fig4();
  const LeadCompensator c = sliding_design(s);
  const Signal ramp = Signal::ramp(0.0, 0.01);
  const double e_cont = run(s, c, ramp, Compensation::None).steady_state_error;
  const double e_fast = run(s, c, ramp, Compensation::None, {}, 1e-4).steady_state_error;
  // Tustin keeps the static gain exactly: the ramp error is the same force balance.
  EXPECT_NEAR(e_fast, e_cont, 1e-3 * e_cont);
  LoopConfig cfg;
  cfg.C = c;
  cfg.reference = Signal::constant(0.01);
  cfg.duration = 0.5;
  const LoopTrace a = simulate_loop(s, cfg);
  cfg.sample_time = 2e-5;
  const LoopTrace b = simulate_loop(s, cfg);
  double dmax = 0.0;
  for (std::size_t i = 0; i < a.x.size(); ++i) dmax = std::max(dmax, std::abs(a.x[i] - b.x[i]));
  EXPECT_LT(dmax, 2e-4);  // 2 % of the step
}

TEST(LoopMetricsLimitCycle, KnownOscillationGivesItsAmplitudeAndPeriod) {
  LoopTrace tr;
  for (int i = 0; i <= 20000; ++i) {
    const double t = i * 1e-4;
    tr.t.push_back(t);
    tr.r.push_back(1.0);
    tr.x.push_back(0.9 + 0.003 * std::sin(2 * M_PI * t / 0.05));  // 3 mm, 50 ms
  }
  const LoopMetrics m = loop_metrics(tr);
  EXPECT_TRUE(m.hunting);
  EXPECT_NEAR(m.cycle_amplitude, 0.003, 1e-6);
  EXPECT_NEAR(m.cycle_period, 0.05, 1e-4);
  EXPECT_NEAR(m.steady_state_error, 0.1, 1e-4);
  EXPECT_TRUE(std::isnan(m.settling_time));
}

TEST(LoopSimulationInput, BadConfigurationsAreRejected) {
  const Scenario s = fig4();
  LoopConfig cfg;
  cfg.reference = Signal::constant(0.01);
  cfg.C = {-1.0, 1.0, 2.0};
  EXPECT_THROW(simulate_loop(s, cfg), InputError);
  cfg.C = {100.0, 1.0, 2.0};
  cfg.dt = 0.01;  // far above 2 / sqrt(210000) s
  EXPECT_THROW(simulate_loop(s, cfg), InputError);
  cfg.dt = 1e-5;
  cfg.sample_time = 1e-6;  // below dt
  EXPECT_THROW(simulate_loop(s, cfg), InputError);
  EXPECT_THROW(compensation_from_string("pid"), InputError);
  EXPECT_THROW(regime_from_string("stuck"), InputError);
}

TEST(LoopWithOtherFriction, LuGrePlantWithGmsFeedforwardBuiltFromItsStribeckCurve) {
  // Any registry model drives the loop. LuGre's steady state is S(v) + sigma2 v, the same curve
  // as the GMS compensator built from its Fs, Fc, Vs, delta, sigma2, so the ramp error vanishes.
  Scenario s = fig4();
  s.friction = model_info("lugre").defaults();
  const ModelParams ff = feedforward_model(s.friction, {});
  EXPECT_EQ(ff.model, "gms");
  EXPECT_DOUBLE_EQ(ff.scalar("Fs"), s.friction.scalar("Fs"));
  EXPECT_DOUBLE_EQ(ff.scalar("sigma2"), s.friction.scalar("sigma2"));
  const LeadCompensator c = sliding_design(fig4());
  const double k_dc = c.Kc * c.z / c.p;
  const double v = 0.01;
  const double Fss = build_model(s.friction)->steady_state(v);
  const Signal ramp = Signal::ramp(0.0, v);
  const LoopMetrics none = run(s, c, ramp, Compensation::None);
  EXPECT_NEAR(none.steady_state_error, Fss / k_dc, 2e-3 * Fss / k_dc);
  const LoopMetrics gms = run(s, c, ramp, Compensation::Gms);
  EXPECT_LT(std::abs(gms.steady_state_error), 1e-3 * none.steady_state_error);
}
