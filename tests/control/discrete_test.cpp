// Discrete time: zero-order hold against closed forms, Tustin, margins on the unit circle checked
// by evaluating L(e^{j omega T}), and stability from the w-plane Nyquist count against the
// closed-loop roots' moduli, over random loops (fixed seeds).
#include <gtest/gtest.h>

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
