// Compensators of one or two first-order sections, C(s) = Kc prod_i (s + z_i)/(s + p_i): the
// one-section case against the formulas it had before the sections, the closed-loop poles of the
// multi-section loop against the characteristic equation in factored form, the export against the
// expanded product, the loop simulation's cascade against its one-section path and (PID on a
// frictionless plant) against the linear closed-loop step, and the design types (lag, lead-lag,
// PI, PID) against what they promise (error constant bought, slow pole, the gain point's damping).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "core/control/design_json.hpp"
#include "core/control/design_plant.hpp"
#include "core/control/design_session.hpp"
#include "core/control/discrete.hpp"
#include "core/control/linear_response.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/io/scenario_io.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
Scenario fig4() { return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"); }

// A random strictly proper plant: den of degree 1..3 with roots in the left half plane or at the
// origin, num of lower degree with a positive gain.
TransferFunction random_plant(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 1 + static_cast<int>(rng() % 3);
  Poly den({1.0});
  for (int i = 0; i < n; ++i) den = den * Poly({i == 0 && u(rng) < 0.5 ? 0.0 : 0.5 + 20 * u(rng), 1.0});
  Poly num({1.0 + 50 * u(rng)});
  if (n >= 2 && u(rng) < 0.5) num = num * Poly({1.0 + 10 * u(rng), 1.0});
  return {num, den};
}

LeadCompensator random_two_sections(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  LeadCompensator c{0.5 + 50 * u(rng), 0.5 + 10 * u(rng), 2 + 60 * u(rng)};
  const double z2 = 0.1 + 5 * u(rng);
  c.second = Section{z2, u(rng) < 0.3 ? 0.0 : z2 * (0.02 + 0.9 * u(rng))};
  return c;
}
}  // namespace

// One section: the transfer function and the exported coefficients are the formulas of before.
TEST(CompensatorSections, OneSectionIsTheFormerCompensator) {
  std::mt19937 rng(1201);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double Kc = 1e-2 + 1e4 * u(rng), z = 0.1 + 100 * u(rng), p = trial % 5 == 0 ? 0.0 : 0.1 + 500 * u(rng);
    const LeadCompensator c{Kc, z, p};
    const TransferFunction t = c.tf();
    ASSERT_EQ(t.num.degree(), 1);
    EXPECT_EQ(t.num.coeff(0), Kc * z);
    EXPECT_EQ(t.num.coeff(1), Kc);
    EXPECT_EQ(t.den.coeff(0), p);
    EXPECT_EQ(t.den.coeff(1), 1.0);
    const nlohmann::json j = compensator_json(c);
    EXPECT_EQ(j["num"], nlohmann::json({Kc, Kc * z}));
    EXPECT_EQ(j["den"], nlohmann::json({1.0, p}));
    EXPECT_EQ(j["sections"].size(), 1u);
    char buf[200];
    std::snprintf(buf, sizeof buf, "C = tf([%.17g, %.17g], [%.17g, %.17g]);", Kc, Kc * z, 1.0, p);
    EXPECT_EQ(compensator_matlab(c), buf);
    // A unity second section (s + a)/(s + a) leaves the loop's sampled transfer function unchanged.
    LeadCompensator c2 = c;
    const double a = 0.5 + 30 * u(rng);
    c2.second = Section{a, a};
    const TransferFunction G = random_plant(rng);
    const TransferFunction L1 = sampled_loop(G, c, 1e-3), L2 = sampled_loop(G, c2, 1e-3);
    // (Away from z = 1: the ZOH numerator's coefficients cancel there, and the expanded products
    // of the two representations then differ by more than rounding.)
    for (double wT : {0.5, 1.5, 2.5, 3.1}) {
      const cplx zz = std::exp(cplx(0.0, wT));
      EXPECT_NEAR(std::abs(L1(zz) - L2(zz)), 0.0, 1e-8 * std::abs(L1(zz)));
    }
  }
}

// The loop simulation: the one-section path (exact first-order update) and the two-section cascade
// (exact ZOH of the 2-state realisation, or Tustin per section) give the same trace when the second
// section is a unity (s + a)/(s + a); and the order of two sections does not matter (the same
// transfer function, discretised exactly / by Tustin per factor). Random Fig. 4 loops.
TEST(CompensatorSections, LoopSimulationCascadeMatchesTheOneSectionPathToRounding) {
  std::mt19937 rng(1202);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Scenario s = fig4();
  for (int trial = 0; trial < 12; ++trial) {
    LoopConfig cfg;
    cfg.C = {2000 + 4000 * u(rng), 5 + 20 * u(rng), 60 + 200 * u(rng)};
    cfg.reference = trial % 2 ? Signal::constant(1e-3 + 1e-2 * u(rng)) : Signal::sine(0.0, 5e-3, 1 + 3 * u(rng));
    cfg.duration = 0.3;
    cfg.dt = 1e-5;
    cfg.sample_time = trial % 3 == 0 ? 2e-4 : 0.0;
    cfg.comp = trial % 2 ? Compensation::Gms : Compensation::None;
    const LoopTrace a = simulate_loop(s, cfg);
    LoopConfig c2 = cfg;
    const double w = 1 + 100 * u(rng);
    c2.C.second = Section{w, w};
    const LoopTrace b = simulate_loop(s, c2);
    ASSERT_EQ(a.x.size(), b.x.size());
    double scale = 0.0, diff = 0.0;
    for (std::size_t i = 0; i < a.x.size(); ++i)
      scale = std::max(scale, std::abs(a.x[i])), diff = std::max(diff, std::abs(a.x[i] - b.x[i]));
    EXPECT_LT(diff, 1e-8 * scale) << "trial " << trial;
    // Two real sections in either order.
    LoopConfig p = cfg, q = cfg;
    const Section s1{cfg.C.z, cfg.C.p}, s2{0.5 + 3 * u(rng), 0.05 + 0.4 * u(rng)};
    p.C = {cfg.C.Kc, s1.z, s1.p, s2};
    q.C = {cfg.C.Kc, s2.z, s2.p, s1};
    const LoopTrace tp = simulate_loop(s, p), tq = simulate_loop(s, q);
    diff = 0.0;
    for (std::size_t i = 0; i < tp.x.size(); ++i) diff = std::max(diff, std::abs(tp.x[i] - tq.x[i]));
    EXPECT_LT(diff, 1e-8 * scale) << "trial " << trial << " (order of the sections)";
  }
}

// For random plants and two-section compensators, the closed-loop poles the design reports are the
// roots of den dc + Kc num nc, evaluated in factored form (den(s) prod (s + p_i) + Kc num(s)
// prod (s + z_i)), and there are deg(den) + 2 of them.
TEST(CompensatorSections, ClosedLoopPolesAreTheRootsOfTheCharacteristicEquation) {
  std::mt19937 rng(1203);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const TransferFunction G = random_plant(rng);
    const LeadCompensator c = random_two_sections(rng);
    DesignInputs in;
    in.plant.source = PlantSource::Typed;
    std::ostringstream num, den;
    num.precision(17), den.precision(17);
    for (double x : G.num.descending_coeffs()) num << x << " ";
    for (double x : G.den.descending_coeffs()) den << x << " ";
    in.plant.num = num.str();
    in.plant.den = den.str();
    in.manual = c;
    in.simulate = false;
    const DesignOutputs out = compute_design(in);
    ASSERT_TRUE(out.compensator) << out.error;
    ASSERT_EQ(static_cast<int>(out.closed_loop_poles.size()), G.den.degree() + 2);
    for (const cplx& s : out.closed_loop_poles) {
      const cplx a = G.den(s) * (s + c.p) * (s + c.second->p);
      const cplx b = c.Kc * G.num(s) * (s + c.z) * (s + c.second->z);
      EXPECT_LT(std::abs(a + b), 1e-7 * (std::abs(a) + std::abs(b)) + 1e-9) << "trial " << trial << " s = " << s;
    }
    // The export carries the product polynomial: num = Kc [1, z1 + z2, z1 z2], den = [1, p1 + p2, p1 p2].
    const nlohmann::json j = compensator_json(c);
    const double z1 = c.z, z2 = c.second->z, p1 = c.p, p2 = c.second->p;
    const std::vector<double> en{c.Kc, c.Kc * (z1 + z2), c.Kc * z1 * z2}, ed{1.0, p1 + p2, p1 * p2};
    const auto jn = j["num"].get<std::vector<double>>(), jd = j["den"].get<std::vector<double>>();
    ASSERT_EQ(jn.size(), 3u);
    ASSERT_EQ(jd.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(jn[i], en[i], 1e-14 * std::abs(en[0] * (1 + z1) * (1 + z2)));
      EXPECT_NEAR(jd[i], ed[i], 1e-14 * (1 + p1) * (1 + p2));
    }
    // The MATLAB / python strings hold the same numbers (17 digits: exact).
    const std::string m = compensator_matlab(c);
    double a0, a1, a2, b0, b1, b2;
    ASSERT_EQ(std::sscanf(m.c_str(), "C = tf([%lf, %lf, %lf], [%lf, %lf, %lf]);", &a0, &a1, &a2, &b0, &b1, &b2), 6) << m;
    EXPECT_EQ(a0, jn[0]);
    EXPECT_EQ(a1, jn[1]);
    EXPECT_EQ(a2, jn[2]);
    EXPECT_EQ(b0, jd[0]);
    EXPECT_EQ(b1, jd[1]);
    EXPECT_EQ(b2, jd[2]);
    const std::string py = compensator_python(c);
    ASSERT_EQ(std::sscanf(py.c_str(), "import control\nC = control.tf([%lf, %lf, %lf], [%lf, %lf, %lf])", &a0, &a1, &a2,
                          &b0, &b1, &b2),
              6)
        << py;
    EXPECT_EQ(a1, jn[1]);
    EXPECT_EQ(b2, jd[2]);
    ++checked;
  }
  EXPECT_EQ(checked, 300);
}

// A PID Kc (s + z1)(s + z2)/(s (s + p_f)) on a frictionless one-body plant (an assembly without
// contacts: m x'' = u - c v - k x) follows the linear closed loop's step (ZOH-exact) to first
// order in dt, and its integral action removes the static error (also against a spring).
TEST(CompensatorSections, PidLoopWithoutFrictionMatchesTheLinearClosedLoopStep) {
  std::mt19937 rng(1204);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 60 && checked < 6; ++trial) {
    Assembly a;
    const double m = 0.2 + 2 * u(rng);
    a.bodies = {{"mass", m}};
    a.dampers = {{"d", 0, kGround, 0.5 + 10 * u(rng)}};
    if (trial % 2) a.springs = {{"k", 0, kGround, 50 + 500 * u(rng)}};
    a.drives = {{"force", DrivePart::Kind::Force, 0, Signal::constant(0.0)}};
    const DesignPlant dp =
        design_plant({PlantSource::Assembly, "1", "1 0", "force", "x.mass"}, Regime::Sliding, 0.0, nullptr, &a);
    const double wn = 10 + 30 * u(rng);
    LeadCompensator c{m * wn * wn * (0.5 + u(rng)), wn * (0.2 + 0.5 * u(rng)), wn * (5 + 10 * u(rng))};
    c.second = Section{wn * (0.05 + 0.2 * u(rng)), 0.0};  // the integral section
    const TransferFunction T = closed_loop(dp.linear.g, c);
    bool stable = true;
    for (const cplx& s : T.poles()) stable = stable && s.real() < -0.5;
    if (!stable) continue;
    ++checked;
    AssemblyScenario sc;
    sc.name = "pid";
    sc.plant = a;
    sc.run.dt = 1e-5;
    const double amp = 1e-3 * (1 + 9 * u(rng)), duration = 1.5;
    const int n = 151;
    const StepResponse lin = step_response(T, duration, n);
    EXPECT_NEAR(T.num(0.0) / T.den(0.0), 1.0, 1e-12) << "the integrator removes the static error";
    auto max_error = [&](double dt) {
      LoopConfig cfg;
      cfg.reference = Signal::constant(amp);
      cfg.C = c;
      cfg.dt = dt;
      cfg.duration = duration;
      cfg.record_every = static_cast<int>(std::lround(duration / (n - 1) / dt));
      const LoopTrace tr = simulate_loop(sc, dp.port, cfg);
      EXPECT_EQ(tr.t.size(), lin.t.size());
      double e = 0.0;
      for (std::size_t i = 0; i < std::min(tr.t.size(), lin.t.size()); ++i)
        e = std::max(e, std::abs(tr.x[i] - amp * lin.y[i]));
      return e / amp;
    };
    const double e1 = max_error(2e-5), e2 = max_error(1e-5);
    EXPECT_LT(e2, 5e-4) << "trial " << trial;
    EXPECT_LT(e2, 0.6 * e1) << "first order: " << e1 << " -> " << e2;
  }
  EXPECT_GE(checked, 4);
}

// The design types on random type-1 plants K0 b/(s (s + a)(s + b)) (b far: the locus crosses every
// zeta line): the lag's Kc puts a pole of the uncompensated loop on the zeta line (a second method:
// the closed-loop roots of den + Kc num), the lag buys exactly the requested error constant and its
// slow pole sits next to its zero; the lead-lag's lead is the usable maximum and the lag makes up
// the requested constant; the PI and the PID end with an integrator.
TEST(CompensatorSections, DesignTypesBuyTheRequestedErrorConstant) {
  std::mt19937 rng(1205);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    const double a0 = 1 + 10 * u(rng), b0 = 200 + 300 * u(rng), K0 = 5 + 50 * u(rng);
    const TransferFunction G{Poly({K0 * b0}), Poly({0.0, 1.0}) * Poly({a0, 1.0}) * Poly({b0, 1.0})};
    DesignInputs in;
    in.plant.source = PlantSource::Typed;
    std::ostringstream num, den;
    num.precision(17), den.precision(17);
    for (double x : G.num.descending_coeffs()) num << x << " ";
    for (double x : G.den.descending_coeffs()) den << x << " ";
    in.plant.num = num.str(), in.plant.den = den.str();
    in.simulate = false;
    const double zeta = 0.4 + 0.4 * u(rng);
    in.root = {zeta, 2 * a0 * (1 + u(rng))};
    // Lag.
    in.type = CompensatorType::Lag;
    const DesignOutputs plain = [&] {
      DesignInputs g = in;
      g.K = 1.0;  // below Kc's own: no lag
      return compute_design(g);
    }();
    ASSERT_TRUE(plain.gain_point) << plain.error;
    const GainPoint gp = *plain.gain_point;
    EXPECT_NEAR(-gp.s.real() / std::abs(gp.s), zeta, 1e-9);
    double nearest = 1e300;
    for (const cplx& s : (G.den + G.num * gp.k).roots()) nearest = std::min(nearest, std::abs(s - gp.s));
    EXPECT_LT(nearest, 1e-6 * std::abs(gp.s)) << "trial " << trial;
    const double K_gain = gp.k * plant_type(G).K0;  // K0 b / (a b) = K0 / a
    in.K = K_gain * (3 + 20 * u(rng));
    DesignOutputs out = compute_design(in);
    ASSERT_TRUE(out.compensator && out.lag) << out.error;
    EXPECT_EQ(out.compensator_kind, "lag");
    EXPECT_NEAR(out.lag->K, *in.K, 1e-9 * *in.K);
    EXPECT_NEAR(out.lag->K_gain_only, K_gain, 1e-9 * K_gain);
    EXPECT_LT(std::abs(out.lag->slow_pole + out.compensator->z), out.compensator->z) << "slow pole next to -z";
    EXPECT_NEAR(out.lag->time_constant, 1.0 / std::abs(out.lag->slow_pole.real()), 1e-12);
    // PI: same gain point, an integrator.
    in.type = CompensatorType::PI;
    out = compute_design(in);
    ASSERT_TRUE(out.compensator) << out.error;
    EXPECT_EQ(out.compensator->p, 0.0);
    EXPECT_NEAR(out.compensator->Kc, gp.k, 1e-9 * gp.k);
    ASSERT_TRUE(out.lag);
    EXPECT_TRUE(std::isinf(out.lag->K));
    // Lead-lag: the usable maximum lead, the lag for the rest (target above the lead's reach).
    in.type = CompensatorType::LeadLag;
    in.K.reset();
    const DesignOutputs lead = compute_design(in);  // lead-lag without K: usable lead x lag_factor
    ASSERT_TRUE(lead.compensator && lead.compensator->second && lead.report && lead.report->usable_design) << lead.error;
    const LeadDesign& ud = *lead.report->usable_design;
    EXPECT_EQ(lead.compensator->Kc, ud.Kc);
    EXPECT_EQ(lead.compensator->z, ud.z);
    EXPECT_EQ(lead.compensator->p, ud.p);
    ASSERT_TRUE(lead.lag);
    EXPECT_NEAR(lead.lag->K, in.lag_factor * ud.K, 1e-6 * ud.K * in.lag_factor);
    EXPECT_NEAR(lead.lag->K_gain_only, ud.K, 1e-9 * ud.K);
    in.K = ud.K * (2 + 30 * u(rng));
    out = compute_design(in);
    ASSERT_TRUE(out.compensator && out.compensator->second && out.lag) << out.error;
    EXPECT_NEAR(out.lag->K, *in.K, 1e-6 * *in.K);
    const Section lag = *out.compensator->second;
    EXPECT_LT(std::abs(out.lag->slow_pole + lag.z), lag.z);
    // PID: the lead's zero and pole, then an integral section.
    in.type = CompensatorType::PID;
    in.K.reset();
    out = compute_design(in);
    ASSERT_TRUE(out.compensator && out.compensator->second) << out.error;
    EXPECT_EQ(out.compensator->second->p, 0.0);
    EXPECT_EQ(out.compensator->z, ud.z);
    EXPECT_EQ(out.compensator->p, ud.p);
  }
}

// The lag on the worked G1 = 4/(s(s+2)) at zeta 0.5 (random targets K): the gain point is the closed
// form -1 + j sqrt(3) with Kc = |s||s + 2|/4 = 1 (Kv 2 by the gain alone), the lag buys Kv = K exactly.
TEST(CompensatorSections, LagOnTheWorkedG1IsTheClosedForm) {
  std::mt19937 rng(1206);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const double K = 5 + 50 * u(rng);
    DesignInputs in;
    in.plant.source = PlantSource::Typed;
    in.plant.num = "4";
    in.plant.den = "1 2 0";
    in.root = {0.5, 2.0};
    in.K = K;
    in.type = CompensatorType::Lag;
    in.simulate = false;
    const DesignOutputs out = compute_design(in);
    ASSERT_TRUE(out.gain_point && out.compensator && out.lag) << out.error;
    EXPECT_NEAR(out.gain_point->s.real(), -1.0, 1e-9);
    EXPECT_NEAR(out.gain_point->s.imag(), std::sqrt(3.0), 1e-9);
    EXPECT_NEAR(out.compensator->Kc, 1.0, 1e-9);
    EXPECT_NEAR(out.lag->K, K, 1e-9 * K);
    EXPECT_NEAR(out.lag->K_gain_only, 2.0, 1e-9);
  }
}
