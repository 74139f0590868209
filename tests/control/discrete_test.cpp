// Discrete time: zero-order hold against closed forms, Tustin, margins on the unit circle checked
// by evaluating L(e^{j omega T}), and stability from the w-plane Nyquist count against the
// closed-loop roots' moduli, over random loops (fixed seeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "core/control/discrete.hpp"
#include "core/error.hpp"

using namespace gmslab::control;

namespace {
cplx eval(const TransferFunction& H, cplx z) { return H.num(z) / H.den(z); }
}  // namespace

// 1/(s + a): G(z) = (1 - e^{-aT}) / (a (z - e^{-aT})); 1/s^2: T^2 (z + 1) / (2 (z - 1)^2).
TEST(Discrete, ZeroOrderHoldMatchesClosedForms) {
  std::mt19937 rng(1220);
  std::uniform_real_distribution<double> la(-1.0, 2.0), lt(-4.0, -1.0), ang(0.1, 3.0);
  for (int i = 0; i < 100; ++i) {
    const double a = std::pow(10.0, la(rng)), T = std::pow(10.0, lt(rng));
    const cplx z = std::polar(1.3, ang(rng));
    const TransferFunction g1 = zoh({Poly({1.0}), Poly({a, 1.0})}, T);
    const double e = std::exp(-a * T);
    const cplx expect1 = (1 - e) / (a * (z - e));
    EXPECT_NEAR(std::abs(eval(g1, z) - expect1), 0.0, 1e-9 * std::abs(expect1));
    const TransferFunction g2 = zoh({Poly({1.0}), Poly({0.0, 0.0, 1.0})}, T);
    const cplx expect2 = T * T * (z + 1.0) / (2.0 * (z - 1.0) * (z - 1.0));
    EXPECT_NEAR(std::abs(eval(g2, z) - expect2), 0.0, 1e-6 * std::abs(expect2));
  }
  EXPECT_THROW(zoh({Poly({1.0}), Poly({1.0, 1.0})}, 0.0), gmslab::InputError);
}

TEST(Discrete, TustinIsTheBilinearSubstitution) {
  const TransferFunction C{Poly({30.0, 4.0}), Poly({50.0, 1.0})};  // 4 (s + 7.5) / (s + 50)
  const double T = 2e-3;
  const TransferFunction Cz = tustin(C, T);
  for (double th : {0.1, 0.7, 2.0}) {
    const cplx z = std::polar(0.9, th);
    const cplx s = 2.0 / T * (z - 1.0) / (z + 1.0);
    EXPECT_NEAR(std::abs(eval(Cz, z) - eval(C, s)), 0.0, 1e-9 * std::abs(eval(C, s)));
  }
}

// Random sampled loops Kc Gc(z) G_zoh(z): margins from the w plane are crossovers of
// L(e^{j omega T}) on the unit circle, and Z = N + P equals the closed-loop roots outside |z| = 1.
TEST(Discrete, MarginsOnTheUnitCircleAndStabilityMatchRoots) {
  std::mt19937 rng(1221);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0, unstable = 0;
  for (int i = 0; i < 300; ++i) {
    const double a = 0.5 + 10 * u(rng), T = std::pow(10.0, -3 + 2 * u(rng)), K = std::pow(10.0, -1 + 6 * u(rng));
    const bool integrator = u(rng) < 0.5;
    const TransferFunction G{Poly({1.0}), integrator ? Poly::from_roots({0.0, -a}) : Poly::from_roots({-a, -2 * a})};
    const double zc = a * (0.2 + u(rng)), pc = zc * (1 + 10 * u(rng));
    const TransferFunction Cz = tustin({Poly({K * zc, K}), Poly({pc, 1.0})}, T);
    const TransferFunction Gz = zoh(G, T);
    const TransferFunction Lz{Cz.num * Gz.num, Cz.den * Gz.den};
    const std::vector<cplx> cl = (Lz.den + Lz.num).roots();
    bool near = false;
    int outside = 0;
    for (const cplx& z : cl) near |= std::abs(std::abs(z) - 1.0) < 1e-6, outside += std::abs(z) > 1.0;
    if (near) continue;
    const DiscreteFrequencyReport r = discrete_frequency_response(Lz, T);
    ++checked;
    unstable += outside > 0;
    EXPECT_EQ(r.nyquist.closed_rhp_poles, outside) << i;
    for (double w : r.margins.gain_crossovers) {
      EXPECT_LT(w, std::numbers::pi / T);
      EXPECT_NEAR(std::abs(eval(Lz, std::exp(cplx(0.0, w * T)))), 1.0, 1e-6);
    }
    for (double w : r.margins.phase_crossovers) {
      const cplx L = eval(Lz, std::exp(cplx(0.0, w * T)));
      EXPECT_NEAR(L.imag(), 0.0, 1e-6 * std::abs(L));
      EXPECT_LT(L.real(), 0.0);
    }
    if (std::isfinite(r.margins.gain_crossover)) {
      const cplx L = eval(Lz, std::exp(cplx(0.0, r.margins.gain_crossover * T)));
      EXPECT_NEAR(std::remainder(r.margins.phase_margin - 180.0 - std::arg(L) * 180.0 / std::numbers::pi, 360.0), 0.0, 1e-4);  // deg
    }
  }
  EXPECT_GT(checked, 250);
  EXPECT_GT(unstable, 30);
}

// ZOH of 1/(s (s + a)) (x = aT, e = e^{-x}):
//   G(z) = (b1 z + b0) / (a^2 (z - 1)(z - e)),  b1 = x - 1 + e,  b0 = 1 - e - x e.
// K G in unity feedback: z^2 + (K b1/a^2 - 1 - e) z + (e + K b0/a^2) = 0; by Jury's test it is
// stable for 0 < K < min(a^2 (1 - e)/b0 [complex pair leaves through |z| = 1],
// 2 (1 + e) a^2/(b1 - b0) [a root leaves through z = -1]). Over random a, T: the closed form of the
// ZOH, the z-plane locus's first unit-circle crossing at that gain (its point on |z| = 1 and a
// root there), and the stable gain interval [0, K_crit].
TEST(Discrete, ZPlaneLocusLeavesTheUnitCircleAtTheJuryGain) {
  std::mt19937 rng(1212);
  std::uniform_real_distribution<double> la(-0.5, 1.5), lt(-3.0, -0.3);
  for (int i = 0; i < 120; ++i) {
    const double a = std::pow(10.0, la(rng)), T = std::pow(10.0, lt(rng));
    const double x = a * T, e = std::exp(-x), b1 = x - 1 + e, b0 = 1 - e - x * e;
    const TransferFunction Gz = zoh({Poly({1.0}), Poly({0.0, a, 1.0})}, T);
    for (double ang : {0.4, 1.7, 2.9}) {
      const cplx z = std::polar(0.8, ang);
      const cplx expect = (b1 * z + b0) / (a * a * (z - 1.0) * (z - e));
      ASSERT_NEAR(std::abs(eval(Gz, z) - expect), 0.0, 1e-7 * std::abs(expect)) << "a " << a << " T " << T;
    }
    const double k_circle = a * a * (1 - e) / b0, k_minus1 = 2 * (1 + e) * a * a / (b1 - b0);
    const double k_crit = std::min(k_circle, k_minus1);
    const ZLocus zl = z_root_locus(Gz, T);
    ASSERT_FALSE(zl.crossings.empty());
    const UnitCircleCrossing& c = zl.crossings.front();
    EXPECT_NEAR(c.k, k_crit, 1e-6 * k_crit) << "a " << a << " T " << T;
    EXPECT_NEAR(std::abs(c.z), 1.0, 1e-9);
    EXPECT_NEAR(std::abs(Gz.den(c.z) + c.k * Gz.num(c.z)), 0.0, 1e-7 * std::abs(Gz.den(c.z)) + 1e-12);
    EXPECT_NEAR(c.omega, std::arg(c.z) / T, 1e-9 / T);
    if (k_minus1 < k_circle) { EXPECT_NEAR(c.z.real(), -1.0, 1e-6); }
    ASSERT_EQ(zl.stable_gains.size(), 1u);
    EXPECT_EQ(zl.stable_gains[0].first, 0.0);
    EXPECT_NEAR(zl.stable_gains[0].second, k_crit, 1e-6 * k_crit);
    // The sampled locus passes through the crossing gain with a root on the unit circle, and is
    // inside the circle below it.
    const auto it = std::find(zl.locus.gains.begin(), zl.locus.gains.end(), c.k);
    ASSERT_NE(it, zl.locus.gains.end());
    const std::size_t j = static_cast<std::size_t>(it - zl.locus.gains.begin());
    double best = 1e9;
    for (const auto& br : zl.locus.branches) best = std::min(best, std::abs(std::abs(br[j]) - 1.0));
    EXPECT_LT(best, 1e-7);
    for (std::size_t g = 0; g < zl.locus.gains.size(); ++g) {
      if (zl.locus.gains[g] >= 0.999 * k_crit) break;
      for (const auto& br : zl.locus.branches) ASSERT_LT(std::abs(br[g]), 1.0 + 1e-9);
    }
  }
}

// A loop that is stable only in a gain window (conditionally stable) and one stable for no gain:
// the stable intervals agree with the closed-loop roots' moduli at random gains.
TEST(Discrete, StableGainIntervalsAgreeWithRootModuli) {
  std::mt19937 rng(4321);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int i = 0; i < 60; ++i) {
    // Random 2..4th order z loops with poles and zeros inside |z| < 1.3.
    const int n = 2 + i % 3, m = static_cast<int>(u(rng) * n);
    auto roots = [&](int k) {
      std::vector<cplx> r;
      while (static_cast<int>(r.size()) < k) {
        if (k - static_cast<int>(r.size()) >= 2 && u(rng) < 0.5) {
          const cplx p = std::polar(1.3 * u(rng), 3.0 * u(rng));
          r.push_back(p);
          r.push_back(std::conj(p));
        } else {
          r.emplace_back(-1.3 + 2.6 * u(rng), 0.0);
        }
      }
      return r;
    };
    const TransferFunction Lz{Poly::from_roots(roots(m)), Poly::from_roots(roots(n))};
    const ZLocus zl = z_root_locus(Lz, 0.01);
    for (int t = 0; t < 40; ++t) {
      const double k = std::pow(10.0, -3.0 + 6.0 * u(rng));
      bool in = false;
      for (const auto& [lo, hi] : zl.stable_gains) in |= k > lo && k < hi;
      bool near_edge = false;
      for (const auto& c : zl.crossings) near_edge |= std::abs(k - c.k) < 1e-6 * c.k;
      if (near_edge) continue;
      EXPECT_EQ(in, roots_inside_unit_circle(Lz, k)) << "loop " << i << " k " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 2000);
}
