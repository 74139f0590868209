// Frequency responses: margins, crossovers, closed-loop bandwidth and peak against closed forms
// over random loops (fixed seeds); Nyquist stability (Z = N + P) against the closed-loop roots.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/control/design_session.hpp"
#include "core/control/frequency.hpp"
#include "core/control/root_locus.hpp"
#include "core/error.hpp"

using namespace gmslab::control;

namespace {
constexpr double kPi = std::numbers::pi;
TransferFunction tf(std::vector<double> num, std::vector<double> den) {
  return {Poly::descending(num), Poly::descending(den)};
}
double deg(double rad) { return rad * 180.0 / kPi; }
}  // namespace

// L = K / (s (s + a)): w_gc^2 = (-a^2 + sqrt(a^4 + 4 K^2)) / 2, PM = 90 - atan(w_gc / a), no GM.
TEST(Frequency, IntegratorLagMarginsMatchClosedForm) {
  std::mt19937 rng(1201);
  std::uniform_real_distribution<double> la(-2.0, 3.0);
  for (int i = 0; i < 200; ++i) {
    const double a = std::pow(10.0, la(rng)), K = std::pow(10.0, la(rng)) * a * a;
    const Margins m = margins(tf({K}, {1, a, 0}));
    const double wgc = std::sqrt(0.5 * (-a * a + std::sqrt(a * a * a * a + 4 * K * K)));
    ASSERT_EQ(m.gain_crossovers.size(), 1u) << "a=" << a << " K=" << K;
    EXPECT_NEAR(m.gain_crossover, wgc, 1e-9 * wgc);
    EXPECT_NEAR(m.phase_margin, 90.0 - deg(std::atan(wgc / a)), 1e-7);
    EXPECT_TRUE(m.phase_crossovers.empty());
    EXPECT_TRUE(std::isinf(m.gain_margin));
  }
}

// L = K / (s (s + a) (s + b)): w_pc = sqrt(a b), GM = a b (a + b) / K; the gain crossover checked
// by bisection on |L(jw)| = 1 (a second method).
TEST(Frequency, ThirdOrderTypeOneGainMarginMatchesClosedForm) {
  std::mt19937 rng(1202);
  std::uniform_real_distribution<double> la(-1.0, 2.5), lk(-1.5, 1.5);
  for (int i = 0; i < 200; ++i) {
    const double a = std::pow(10.0, la(rng)), b = std::pow(10.0, la(rng));
    const double K = a * b * (a + b) * std::pow(10.0, lk(rng));  // GM between 1/30 and 30
    const TransferFunction L{Poly({K}), Poly::from_roots({0.0, -a, -b})};
    const Margins m = margins(L);
    ASSERT_EQ(m.phase_crossovers.size(), 1u);
    EXPECT_NEAR(m.phase_crossover, std::sqrt(a * b), 1e-9 * std::sqrt(a * b));
    EXPECT_NEAR(m.gain_margin, a * b * (a + b) / K, 1e-8 * a * b * (a + b) / K);
    double lo = 1e-9, hi = 1e9;  // |L| decreasing in w
    for (int k = 0; k < 200; ++k) {
      const double mid = std::sqrt(lo * hi);
      (std::abs(L(cplx(0.0, mid))) > 1.0 ? lo : hi) = mid;
    }
    ASSERT_EQ(m.gain_crossovers.size(), 1u);
    EXPECT_NEAR(m.gain_crossover, lo, 1e-8 * lo);
    const double pm = 180.0 - 90.0 - deg(std::atan(lo / a)) - deg(std::atan(lo / b));
    EXPECT_NEAR(m.phase_margin, pm, 1e-6);
    // GM > 1 <=> PM > 0 <=> stable (this loop crosses once each).
    EXPECT_EQ(m.gain_margin > 1.0, m.phase_margin > 0.0);
  }
}

// L = wn^2 / (s (s + 2 zeta wn)): T is the standard second order.
//   PM = atan(2 zeta / sqrt(sqrt(1 + 4 zeta^4) - 2 zeta^2))
//   w_b = wn sqrt(1 - 2 zeta^2 + sqrt(4 zeta^4 - 4 zeta^2 + 2))
//   zeta < 1/sqrt 2: M_r = 1 / (2 zeta sqrt(1 - zeta^2)) at w_r = wn sqrt(1 - 2 zeta^2); else 1 at 0.
TEST(Frequency, SecondOrderClosedLoopMatchesClosedForms) {
  std::mt19937 rng(1203);
  std::uniform_real_distribution<double> uz(0.05, 0.95), lw(-1.0, 4.0);
  for (int i = 0; i < 300; ++i) {
    const double z = uz(rng), wn = std::pow(10.0, lw(rng));
    const FrequencyReport r = frequency_response(tf({wn * wn}, {1, 2 * z * wn, 0}));
    EXPECT_NEAR(r.margins.phase_margin, deg(std::atan(2 * z / std::sqrt(std::sqrt(1 + 4 * z * z * z * z) - 2 * z * z))), 1e-7);
    const double wb = wn * std::sqrt(1 - 2 * z * z + std::sqrt(4 * z * z * z * z - 4 * z * z + 2));
    EXPECT_NEAR(r.bandwidth, wb, 1e-8 * wb);
    EXPECT_NEAR(r.dc_gain, 1.0, 1e-12);
    if (z < 1 / std::sqrt(2.0) - 0.01) {
      EXPECT_NEAR(r.peak_db, 20 * std::log10(1 / (2 * z * std::sqrt(1 - z * z))), 1e-8);
      EXPECT_NEAR(r.peak_w, wn * std::sqrt(1 - 2 * z * z), 1e-6 * wn);
    } else if (z > 1 / std::sqrt(2.0) + 0.01) {
      EXPECT_NEAR(r.peak_db, 0.0, 1e-9);
      EXPECT_EQ(r.peak_w, 0.0);
    }
    EXPECT_TRUE(r.nyquist.stable);
    EXPECT_EQ(r.nyquist.axis_poles, 1);
  }
}

// The Bode data: magnitude is |L(jw)|, the phase continuous and equal to arg L mod 360.
TEST(Frequency, BodeSamplesAreTheResponse) {
  const TransferFunction L = tf({30, 60}, {1, 3, 2, 0, 0});  // type 2 with a lead zero
  const FrequencyReport r = frequency_response(L, {.points = 300});
  ASSERT_EQ(r.open.w.size(), 300u);
  for (std::size_t i = 0; i < r.open.w.size(); ++i) {
    const cplx v = L(cplx(0.0, r.open.w[i]));
    EXPECT_NEAR(r.open.mag_db[i], 20 * std::log10(std::abs(v)), 1e-9);
    const double d = std::remainder(r.open.phase_deg[i] - deg(std::arg(v)), 360.0);
    EXPECT_NEAR(d, 0.0, 1e-7);
    if (i > 0) {
      EXPECT_LT(std::abs(r.open.phase_deg[i] - r.open.phase_deg[i - 1]), 30.0);
    }
  }
  EXPECT_NEAR(r.open.phase_deg.front(), -180.0, 5.0);  // double integrator at low w
}

// Nyquist: Z = N + P equals the number of closed-loop roots with Re > 0, over random loops with
// unstable poles, poles at the origin and on the imaginary axis, equal order and negative gains.
TEST(Frequency, NyquistCountMatchesClosedLoopRoots) {
  std::mt19937 rng(1204);
  std::uniform_real_distribution<double> u(-1.0, 1.0), lk(-2.0, 3.0);
  int checked = 0, unstable = 0, with_rhp = 0;
  for (int i = 0; i < 600; ++i) {
    std::vector<cplx> poles, zeros;
    const int n = 1 + static_cast<int>(rng() % 5);
    const int origin = static_cast<int>(rng() % 3);
    for (int k = 0; k < origin && static_cast<int>(poles.size()) < n; ++k) poles.emplace_back(0.0, 0.0);
    if (rng() % 6 == 0 && static_cast<int>(poles.size()) + 2 <= n) {
      const double w = 1 + 5 * std::abs(u(rng));
      poles.emplace_back(0.0, w), poles.emplace_back(0.0, -w);  // undamped mode
    }
    while (static_cast<int>(poles.size()) < n) {
      if (rng() % 3 == 0 && static_cast<int>(poles.size()) + 2 <= n) {
        const cplx p(5 * u(rng), 1 + 5 * std::abs(u(rng)));
        poles.push_back(p), poles.push_back(std::conj(p));
      } else {
        poles.emplace_back(5 * u(rng), 0.0);
      }
    }
    const int m = static_cast<int>(rng() % static_cast<unsigned>(n + 1));
    for (int k = 0; k < m; ++k) zeros.emplace_back(5 * u(rng) + (u(rng) > 0 ? 0.3 : -0.3), 0.0);
    const double K = (rng() % 5 == 0 ? -1.0 : 1.0) * std::pow(10.0, lk(rng));
    const TransferFunction L{Poly::from_roots(zeros, K), Poly::from_roots(poles)};
    const std::vector<cplx> cl = (L.den + L.num).roots();
    if (static_cast<int>(cl.size()) != n) continue;  // equal order with a root at infinity
    bool near_axis = false;
    int Z = 0;
    for (const cplx& s : cl) {
      near_axis |= std::abs(s.real()) < 1e-4 * std::max(1.0, std::abs(s));
      Z += s.real() > 0.0;
    }
    if (near_axis) continue;
    const Nyquist ny = nyquist_count(L);
    ++checked;
    unstable += Z > 0;
    with_rhp += ny.open_rhp_poles > 0;
    EXPECT_FALSE(ny.marginal) << i;
    EXPECT_EQ(ny.closed_rhp_poles, Z) << "case " << i << " K=" << K << " n=" << n << " origin=" << origin;
    EXPECT_EQ(ny.stable, Z == 0);
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(unstable, 100);
  EXPECT_GT(with_rhp, 100);
}

// Loops whose coefficients span the double range. A second-order loop wn^2 / (s (s + wn)) is
// stable at every scale (closed loop s^2 + wn s + wn^2) and counted so from wn = 1e-100 to 1e150
// (coefficients up to 1e300). The fuzzer's case (cli_fuzz timeout:
// a lead design on 7.8e196 / (3 s^2 + 2 s) with wn = 7.8e79) makes 1 + L non-finite on the
// contour: it is marginal (not counted, not stable) and returns at once instead of refining
// every segment to the depth limit.
TEST(Frequency, NyquistOfLoopsNearTheDoubleRangeIsCountedOrMarginal) {
  for (int e : {-100, -30, 0, 30, 80, 120, 150}) {
    const double wn = std::pow(10.0, e);
    const Nyquist ny = nyquist_count(tf({wn * wn}, {1, wn, 0}));
    EXPECT_FALSE(ny.marginal) << "wn 1e" << e;
    EXPECT_TRUE(ny.stable) << "wn 1e" << e;
  }
  const double KcN = 4.4203301123331135e-36 * 7.777777777777778e196, z = 7.367216853888553e79,
               p = 1.4734433707777046e81;
  const Nyquist ny = nyquist_count(tf({KcN, KcN * z}, {3, 3 * p + 2, 2 * p, 0}));
  EXPECT_TRUE(ny.marginal);
  EXPECT_FALSE(ny.stable);
}

TEST(Frequency, BadLoopIsAnInputError) {
  EXPECT_THROW(margins(tf({1, 0, 0}, {1, 1})), gmslab::InputError);
  EXPECT_THROW(frequency_response(tf({1}, {1, 1}), {.points = 1}), gmslab::InputError);
}

// Lag cost: the error constant is lim s^n Gc G (evaluated at small s, a second method), and the
// slow pole is a closed-loop root near -z, between the lag zero and the origin's side for a
// type-0 plant (the real-axis segment (-z, -p) is on the locus there).
TEST(LagCost, ErrorConstantAndSlowPoleOverRandomLags) {
  std::mt19937 rng(1205);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const double a = 1 + 9 * u(rng), b = 1 + 9 * u(rng), K0 = 0.5 + u(rng);
    const TransferFunction g{Poly({K0 * a * b}), Poly::from_roots({-a, -b})};  // type 0, G(0) = K0
    const double z = 0.05 * std::min(a, b) * (0.2 + u(rng)), p = z / (2 + 20 * u(rng)), Kc = 1 + 10 * u(rng);
    const LeadCompensator c{Kc, z, p};
    const TransferFunction L{g.num * Poly({Kc * z, Kc}), g.den * Poly({p, 1.0})};
    const std::vector<cplx> cl = closed_loop_poles(L, 1.0);
    const LagCost lc = lag_cost(plant_type(g), c, cl);
    const double s = 1e-9;
    EXPECT_NEAR(lc.K, std::abs(L(cplx(s, 0.0))), 1e-6 * lc.K);
    EXPECT_NEAR(lc.K / lc.K_gain_only, z / p, 1e-9 * z / p);
    EXPECT_EQ(lc.slow_pole.imag(), 0.0);
    EXPECT_LT(lc.slow_pole.real(), -p);
    EXPECT_GT(lc.slow_pole.real(), -z);
    EXPECT_NEAR(std::abs((L.den + L.num)(lc.slow_pole)) / std::abs(L.den(lc.slow_pole)), 0.0, 1e-6);
  }
  EXPECT_THROW(lag_cost({0, 1.0}, {1.0, 1.0, 2.0}, {}), gmslab::InputError);
}
