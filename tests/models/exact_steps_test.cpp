// Each model's frozen-velocity step against an independent fine integration of its raw equations
// (classical RK4 / explicit Euler at a thousandth of the step), and the stick band of the static
// laws against the closed-form motion of a mass.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "core/friction/stribeck.hpp"
#include "tests/models/model_protocols.hpp"

namespace gmslab {
namespace {

// A velocity history that visits presliding, reversals and sliding: v_k for k = 0..n-1.
std::vector<double> test_velocities(int n, double vmax) {
  std::vector<double> v;
  for (int k = 0; k < n; ++k) {
    const double t = k / double(n);
    v.push_back(vmax * (std::sin(2 * std::numbers::pi * 3 * t) + 0.3 * std::sin(2 * std::numbers::pi * 17 * t)));
  }
  v[n / 3] = 0.0;  // a rest step
  return v;
}

double rk4(const std::function<double(double)>& f, double z, double h, int n) {
  const double hs = h / n;
  for (int i = 0; i < n; ++i) {
    const double k1 = f(z), k2 = f(z + 0.5 * hs * k1), k3 = f(z + 0.5 * hs * k2), k4 = f(z + hs * k3);
    z += hs * (k1 + 2 * k2 + 2 * k3 + k4) / 6;
  }
  return z;
}

// Single-state models: F = sigma0 z + sigma1 (z1 - z0)/h + sigma2 v with dz/dt = g(z, v).
void expect_matches_fine_integration(const ModelParams& p,
                                     const std::function<double(double, double)>& dzdt,
                                     double sigma0, double sigma1, double sigma2, double tol) {
  const auto m = build_model(p);
  std::vector<double> s(m->state_size(), 0.0);
  double z = 0.0;
  const double h = 1e-3;
  for (double v : test_velocities(600, 2e-3)) {
    const double z1 = rk4([&](double zz) { return dzdt(zz, v); }, z, h, 1000);
    const double f_ref = sigma0 * z1 + sigma1 * (z1 - z) / h + sigma2 * v;
    ASSERT_NEAR(m->step(s, {v, h}), f_ref, tol) << p.model << " v = " << v;
    z = z1;
  }
}

TEST(ExactStep, LuGreMatchesFineRk4) {
  const ModelParams p = model_info("lugre").defaults();
  const Stribeck S{1.5, 1.0, 1e-3, 2.0};
  expect_matches_fine_integration(
      p, [&](double z, double v) { return v - 1e5 * std::abs(v) * z / S(v); }, 1e5,
      std::sqrt(1e5), 0.4, 1e-9);
}

TEST(ExactStep, DahlMatchesFineRk4ForEveryShapeExponent) {
  for (double a : {1.0, 2.0, 0.6}) {
    ModelParams p = model_info("dahl").defaults();
    p.set_scalar("a", a);
    // F_d = sigma0 z form is only for a = 1; integrate F_d itself: dF/dt = s0 v |1 - F sgn v / Fc|^a
    auto dFdt = [&](double F, double v) {
      const double u = 1.0 - F * sgn(v) / 1.0;
      return 1e5 * v * std::copysign(std::pow(std::abs(u), a), u);
    };
    expect_matches_fine_integration(p, dFdt, 1.0, 0.0, 0.4, 1e-8);
  }
}

TEST(ExactStep, ElastoPlasticMatchesFineRk4) {
  const ModelParams p = model_info("elastoplastic").defaults();
  const Stribeck S{1.5, 1.0, 1e-3, 2.0};
  const double s0 = 1e5, zba = 9e-6;
  auto dzdt = [&](double z, double v) {
    if (v == 0.0) return 0.0;
    const double zmax = S(v) / s0, az = std::abs(z);
    double alpha = 0.0;
    if (sgn(z) == sgn(v)) {
      if (az >= zmax) alpha = 1.0;
      else if (az > zba)
        alpha = 0.5 * std::sin(std::numbers::pi * (az - 0.5 * (zmax + zba)) / (zmax - zba)) + 0.5;
    }
    return v * (1.0 - alpha * z * sgn(v) / zmax);
  };
  expect_matches_fine_integration(p, dzdt, s0, std::sqrt(1e5), 0.4, 2e-6);
}

// Leuven: explicit Euler on dz with the Jenkin elements moved every micro-step.
TEST(ExactStep, LeuvenMatchesFineEulerWithElementsMovedEveryMicroStep) {
  ModelParams p = model_info("leuven").defaults();
  p.set_scalar("sigma1", 50.0);
  const auto m = build_model(p);
  const auto k = p.column("k"), W = p.column("W");
  const Stribeck S{1.5, 1.0, 1e-3, 2.0};
  std::vector<double> s(m->state_size(), 0.0), F(k.size(), 0.0);
  const double h = 1e-3;
  const int micro = 20000;
  for (double v : test_velocities(300, 2e-3)) {
    double dz_total = 0.0;
    for (int i = 0; i < micro && v != 0.0; ++i) {
      double fh = 0.0;
      for (double f : F) fh += f;
      const double r = fh / (sgn(v) * S(v));
      const double dz = v * (1.0 - std::copysign(std::pow(std::abs(r), 8.0), r)) * h / micro;
      for (std::size_t j = 0; j < F.size(); ++j) F[j] = std::clamp(F[j] + k[j] * dz, -W[j], W[j]);
      dz_total += dz;
    }
    double fh = 0.0;
    for (double f : F) fh += f;
    ASSERT_NEAR(m->step(s, {v, h}), fh + 50.0 * dz_total / h + 0.4 * v, 2e-4) << "v = " << v;
  }
}

// ---- the Karnopp stick band ---------------------------------------------------------------------
struct Body {
  double x = 0.0, v = 0.0;
};
// Symplectic Euler, as core/sim: friction step with the current v, then v, then x.
void advance(const FrictionModel& m, std::vector<double>& s, Body& b, double f_other, double h) {
  const double ff = m.step(s, {b.v, h, f_other, 1.0});
  b.v += h * (f_other - ff);
  b.x += h * b.v;
}

// A 1 kg body launched at v0 with no force decelerates by m dv/dt = -Fc - sigma2 v and stops at
// t = (m / sigma2) ln(1 + sigma2 v0 / Fc); it then stays exactly at rest (v = 0, x unchanged).
TEST(StickBand, CoulombMassComesToRestAtTheClosedFormTimeAndStays) {
  const auto m = build_model(model_info("coulomb").defaults());
  std::vector<double> s;
  Body b;
  b.v = 0.01;
  const double h = 1e-6, t_stop = (1.0 / 0.4) * std::log(1.0 + 0.4 * 0.01 / 1.0);
  double t = 0.0;
  while (b.v > 0.0) {
    advance(*m, s, b, 0.0, h);
    t += h;
  }
  EXPECT_NEAR(t, t_stop, 1e-5);  // the band (1e-5 m/s) stops it up to v_stick / (Fc/m) early
  EXPECT_EQ(b.v, 0.0);
  const double x_rest = b.x;
  for (int k = 0; k < 100000; ++k) advance(*m, s, b, 1.45, h);  // below Fs = 1.5 N: stuck
  EXPECT_EQ(b.v, 0.0);
  EXPECT_EQ(b.x, x_rest);
  for (int k = 0; k < 1000; ++k) advance(*m, s, b, 1.55, h);  // above Fs: breaks away
  EXPECT_GT(b.v, 0.0);
}

// The Stribeck law with the stick band: an oscillating force below break-away never moves a
// resting body, and the friction balances it exactly.
TEST(StickBand, StribeckBodyAtRestBalancesSubBreakAwayForce) {
  const auto m = build_model(model_info("stribeck").defaults());
  std::vector<double> s;
  Body b;
  const double h = 1e-4;
  for (int k = 0; k < 20000; ++k) {
    const double f = 1.4 * std::sin(2 * std::numbers::pi * k * h);
    const double ff = m->step(s, {b.v, h, f, 1.0});
    EXPECT_DOUBLE_EQ(ff, f);
    b.v += h * (f - ff);
    b.x += h * b.v;
  }
  EXPECT_EQ(b.x, 0.0);
}

// With prescribed motion (mass 0) the set-valued law is regularised by a straight line inside the
// band, meeting the sliding curve at v_stick.
TEST(StickBand, PrescribedMotionUsesTheRegularisedLineInsideTheBand) {
  const auto m = build_model(model_info("stribeck").defaults());
  std::vector<double> s;
  const double vb = 1e-5, edge = m->steady_state(vb);
  EXPECT_DOUBLE_EQ(m->step(s, {0.5 * vb, 1e-3}), 0.5 * edge);
  EXPECT_DOUBLE_EQ(m->step(s, {-0.25 * vb, 1e-3}), -0.25 * edge);
  EXPECT_DOUBLE_EQ(m->step(s, {2 * vb, 1e-3}), m->steady_state(2 * vb));
}

}  // namespace
}  // namespace gmslab
