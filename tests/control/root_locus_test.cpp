// Root locus: branches agree with the roots of den + k num at sampled gains, continuity between
// samples, the analytic key points (breakaway, asymptotes, axis crossings), the 0-degree and
// equal-order loci, and the locus through a lead design's closed-loop poles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/control/assignment.hpp"
#include "core/control/lead_design.hpp"
#include "core/control/root_locus.hpp"
#include "core/error.hpp"

using namespace gmslab::control;

namespace {
TransferFunction tf(std::vector<double> num, std::vector<double> den) {
  return {Poly::descending(num), Poly::descending(den)};
}
double nearest(const std::vector<cplx>& set, cplx s) {
  double best = 1e300;
  for (const cplx& x : set)
    if (!std::isnan(x.real())) best = std::min(best, std::abs(x - s));
  return best;
}
// Every branch sample is a root of den + k num at its gain (by residual).
void expect_on_locus(const TransferFunction& L, const RootLocus& rl) {
  for (std::size_t i = 0; i < rl.gains.size(); i += 7) {
    const Poly c = L.den + L.num * rl.gains[i];
    for (const auto& br : rl.branches) {
      const cplx s = br[i];
      if (std::isnan(s.real())) continue;
      // Residual relative to the size of the terms: backward-stable root finding gives ~1e-14.
      double terms = 0.0;
      for (int j = 0; j <= c.degree(); ++j) terms += std::abs(c.coeff(j)) * std::pow(std::abs(s), j);
      ASSERT_LE(std::abs(c(s)), 1e-9 * terms) << "k = " << rl.gains[i];
    }
  }
}
// Inside the view no branch moves more than max_jump x width between successive gains, except
// through a double root (breakaway), where the locus itself turns a corner.
int count_big_jumps(const RootLocus& rl, double frac) {
  int n = 0;
  for (const auto& br : rl.branches)
    for (std::size_t i = 1; i < br.size(); ++i)
      if (rl.view.contains(br[i]) && rl.view.contains(br[i - 1]) &&
          std::abs(br[i] - br[i - 1]) > frac * rl.view.width())
        ++n;
  return n;
}
}  // namespace

TEST(Assignment, HungarianFindsTheOptimumThatGreedyMisses) {
  // Greedy (row by row, cheapest free column) gives 1 + 100 = 101; the optimum is 2 + 3 = 5.
  const std::vector<double> cost = {1, 2, 3, 100};
  const auto col = solve_assignment(cost, 2);
  EXPECT_EQ(col[0], 1);
  EXPECT_EQ(col[1], 0);
  // 5x5 check against brute force over all permutations.
  const std::vector<double> c5 = {7, 53, 183, 439, 863, 497, 383, 563, 79,  973, 287, 63, 343,
                                  169, 583, 627, 343, 773, 959, 943, 767, 473, 103, 699, 303};
  const auto a = solve_assignment(c5, 5);
  double got = 0;
  for (int i = 0; i < 5; ++i) got += c5[i * 5 + a[i]];
  std::vector<int> perm = {0, 1, 2, 3, 4};
  double best = 1e300;
  do {
    double s = 0;
    for (int i = 0; i < 5; ++i) s += c5[i * 5 + perm[i]];
    best = std::min(best, s);
  } while (std::next_permutation(perm.begin(), perm.end()));
  EXPECT_DOUBLE_EQ(got, best);
}

TEST(Assignment, NonFiniteCostsStillGiveAPermutation) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> cost = {nan, inf, 1.0, inf, nan, inf, 2.0, inf, nan};
  auto col = solve_assignment(cost, 3);
  EXPECT_EQ(col[0], 2);
  EXPECT_EQ(col[2], 0);
  EXPECT_EQ(col[1], 1);
}

TEST(Polynomial, RootsOfKnownFactorsAndConjugatePairs) {
  const std::vector<cplx> want = {{-1, 0}, {-2, 3}, {-2, -3}, {0, 0}, {0, 0}, {5, 0}};
  const Poly p = Poly::from_roots(want, 2.0);
  const auto got = p.roots();
  ASSERT_EQ(got.size(), want.size());
  for (const cplx& w : want) EXPECT_LT(nearest(got, w), 1e-10);
  for (const cplx& g : got) {
    if (g.imag() != 0.0) {
      EXPECT_LT(nearest(got, std::conj(g)), 1e-15);
    }
  }
  EXPECT_EQ(p.zeros_at_origin(), 2);
  EXPECT_NEAR(p(cplx(1.0, 1.0)).real(), (2.0 * (cplx(2, 1) * cplx(3, -2) * cplx(3, 4) *
                                                 cplx(1, 1) * cplx(1, 1) * cplx(-4, 1)))
                                            .real(),
              1e-9);
}

// Coefficients whose ratios overflow (a companion matrix with inf entries): the balancing
// loop skipped such rows before it could spin forever (inf >= 2 inf); roots() returns its n
// values. A polynomial with a huge but finite spread still gets its roots: s^2 + 1e150 s + 1 has
// roots near -1e150 and -1e-150 (product 1, sum -1e150).
TEST(Polynomial, RootsReturnForCoefficientsThatOverflow) {
  const Poly over({1e300, 0.0, 1e-300});  // -c0 / c2 = -inf
  EXPECT_EQ(over.roots().size(), 2u);
  const auto r = Poly({1.0, 1e150, 1.0}).roots();
  ASSERT_EQ(r.size(), 2u);
  const double big = std::min(r[0].real(), r[1].real()), small = std::max(r[0].real(), r[1].real());
  EXPECT_NEAR(big, -1e150, 1e138);
  EXPECT_NEAR(small, -1e-150, 1e-162);
}

TEST(Polynomial, ParseRejectsMalformedCoefficientLists) {
  EXPECT_EQ(parse_polynomial("1 2 0", "--den").degree(), 2);
  EXPECT_EQ(parse_polynomial("1, 2, 0", "--den").coeff(1), 2.0);
  EXPECT_THROW(parse_polynomial("1 x 0", "--den"), gmslab::InputError);
  EXPECT_THROW(parse_polynomial("", "--den"), gmslab::InputError);
  EXPECT_THROW(parse_polynomial("0 0", "--den"), gmslab::InputError);
  EXPECT_THROW(parse_polynomial("1 nan", "--den"), gmslab::InputError);
  EXPECT_THROW(parse_polynomial("1 2e", "--den"), gmslab::InputError);
}

TEST(RootLocus, SecondOrderTypeOneBreaksAwayAtTheCentroid) {
  // 1/(s(s+2)): roots -1 +- sqrt(1 - k); breakaway at s = -1, k = 1; asymptotes at -1, +-90 deg.
  const TransferFunction L = tf({1}, {1, 2, 0});
  const RootLocus rl = root_locus(L);
  ASSERT_EQ(rl.breakaways.size(), 1u);
  EXPECT_NEAR(rl.breakaways[0].s.real(), -1.0, 1e-12);
  EXPECT_NEAR(rl.breakaways[0].k, 1.0, 1e-12);
  EXPECT_NEAR(rl.centroid, -1.0, 1e-12);
  ASSERT_EQ(rl.asymptote_angles.size(), 2u);
  EXPECT_NEAR(rl.asymptote_angles[0], std::numbers::pi / 2, 1e-12);
  EXPECT_TRUE(rl.crossings.empty());
  expect_on_locus(L, rl);
  for (std::size_t i = 0; i < rl.gains.size(); ++i) {
    const double k = rl.gains[i];
    for (const auto& br : rl.branches) {
      const cplx s = br[i];
      const cplx a = cplx(-1, 0) + std::sqrt(cplx(1 - k, 0)), b = cplx(-1, 0) - std::sqrt(cplx(1 - k, 0));
      EXPECT_LT(std::min(std::abs(s - a), std::abs(s - b)), 1e-6) << k;
    }
  }
}

TEST(RootLocus, ThirdOrderCrossesTheImaginaryAxisAtTheRouthGain) {
  // 1/(s(s+1)(s+5)): Routh gives k = 30 at w = sqrt(5); breakaway from d/ds: 3s^2 + 12 s + 5 = 0.
  const TransferFunction L = tf({1}, {1, 6, 5, 0});
  const RootLocus rl = root_locus(L);
  ASSERT_EQ(rl.crossings.size(), 1u);
  EXPECT_NEAR(rl.crossings[0].s.imag(), std::sqrt(5.0), 1e-9);
  EXPECT_NEAR(rl.crossings[0].k, 30.0, 1e-8);
  ASSERT_EQ(rl.breakaways.size(), 1u);
  const double sb = (-12 + std::sqrt(144 - 60)) / 6;
  EXPECT_NEAR(rl.breakaways[0].s.real(), sb, 1e-10);
  EXPECT_NEAR(rl.breakaways[0].k, -(sb * (sb + 1) * (sb + 5)), 1e-9);
  EXPECT_NEAR(rl.centroid, -2.0, 1e-12);
  expect_on_locus(L, rl);
  // The sampled gains include the crossing exactly: a branch sits on the axis there.
  const auto it = std::find(rl.gains.begin(), rl.gains.end(), rl.crossings[0].k);
  ASSERT_NE(it, rl.gains.end());
  const std::size_t i = static_cast<std::size_t>(it - rl.gains.begin());
  double best = 1e300;
  for (const auto& br : rl.branches) best = std::min(best, std::abs(br[i] - cplx(0, std::sqrt(5.0))));
  EXPECT_LT(best, 1e-8);
}

TEST(RootLocus, TenthOrderBranchesStayContinuousAndOnTheLocus) {
  std::vector<cplx> poles = {{0, 0}, {-1, 0}, {-2, 1}, {-2, -1}, {-3, 4}, {-3, -4},
                             {-5, 0}, {-6, 0}, {-0.5, 2}, {-0.5, -2}};
  const TransferFunction L{Poly::from_roots({{-1.5, 0}, {-4, 2}, {-4, -2}}), Poly::from_roots(poles)};
  const RootLocus rl = root_locus(L);
  ASSERT_EQ(rl.branches.size(), 10u);
  expect_on_locus(L, rl);
  // Branch b starts at a pole (k = 0) and the ones that end at a zero get there.
  for (const auto& br : rl.branches) EXPECT_LT(nearest(poles, br.front()), 1e-9);
  int ended_at_zero = 0;
  for (const auto& br : rl.branches) ended_at_zero += nearest(rl.zeros, br.back()) < 1e-2;
  EXPECT_EQ(ended_at_zero, 3);
  EXPECT_EQ(count_big_jumps(rl, 0.011), 0);
  EXPECT_EQ(rl.asymptote_angles.size(), 7u);
}

TEST(RootLocus, ZeroDegreeLocusRunsOnTheComplementaryRealAxis) {
  // 1/(s(s+2)) with k < 0: roots -1 +- sqrt(1 - k) stay real, one goes right to +inf.
  const TransferFunction L = tf({1}, {1, 2, 0});
  LocusOptions o;
  o.negative = true;
  const RootLocus rl = root_locus(L, o);
  EXPECT_LT(rl.gains.back(), 0.0);
  EXPECT_NEAR(rl.asymptote_angles[0], 0.0, 1e-12);
  EXPECT_NEAR(rl.asymptote_angles[1], std::numbers::pi, 1e-12);
  for (const auto& br : rl.branches)
    for (const cplx& s : br) EXPECT_EQ(s.imag(), 0.0);
  expect_on_locus(L, rl);
  EXPECT_TRUE(rl.breakaways.empty());
}

TEST(RootLocus, EqualOrderLocusPassesThroughInfinityAtMinusLeadRatio) {
  // L = (s + 1) / (2 - s)... written as (-s - 1)/(s - 2) would be unusual; use (s+1)/(s+2), k<0:
  // den + k num = (1 + k) s + 2 + k: the root -(2 + k)/(1 + k) passes infinity at k = -1.
  const TransferFunction L = tf({1, 1}, {1, 2});
  LocusOptions o;
  o.negative = true;
  const RootLocus rl = root_locus(L, o);
  ASSERT_TRUE(rl.infinite_gain.has_value());
  EXPECT_DOUBLE_EQ(*rl.infinite_gain, -1.0);
  ASSERT_EQ(rl.branches.size(), 1u);
  for (std::size_t i = 0; i < rl.gains.size(); ++i) {
    const double k = rl.gains[i];
    const cplx s = rl.branches[0][i];
    if (k == -1.0) EXPECT_TRUE(std::isnan(s.real()));
    else EXPECT_NEAR(s.real(), -(2 + k) / (1 + k), 1e-9 * (1 + std::abs(s.real())));
  }
  // Positive equal-order locus: from -2 to the zero -1, no infinity.
  const RootLocus rp = root_locus(L);
  EXPECT_FALSE(rp.infinite_gain.has_value());
  EXPECT_NEAR(rp.branches[0].back().real(), -1.0, 1e-4);
}

TEST(RootLocus, PassesThroughTheLeadDesignsClosedLoopPolesAtItsGain) {
  // G1 with the Kv = 5 lead: loop L = Gc G / Kc, gain Kc.
  const TransferFunction G = tf({4}, {1, 2, 0});
  const LeadDesign d = design_for_constant(G, {0.5, 4.0}, 5.0);
  const TransferFunction L{G.num * Poly({d.z, 1.0}), G.den * Poly({d.p, 1.0})};
  LocusOptions o;
  o.extra_gains = {d.Kc};
  const RootLocus rl = root_locus(L, o);
  const auto it = std::find(rl.gains.begin(), rl.gains.end(), d.Kc);
  ASSERT_NE(it, rl.gains.end());
  const std::size_t i = static_cast<std::size_t>(it - rl.gains.begin());
  std::vector<cplx> at;
  for (const auto& br : rl.branches) at.push_back(br[i]);
  for (const cplx& p : d.closed_loop_poles) EXPECT_LT(nearest(at, p), 1e-8);
  EXPECT_LT(nearest(at, cplx(-2, std::sqrt(12.0))), 1e-8);
  // And the gain read back from the dominant root is Kc (real).
  const cplx k = gain_at(L, cplx(-2, std::sqrt(12.0)));
  EXPECT_NEAR(k.real(), d.Kc, 1e-9);
  EXPECT_NEAR(k.imag(), 0.0, 1e-9);
}

namespace {
// A random real polynomial's roots: each a real root in [-6, 1], a pair re [-5, 1] +- j [0.2, 5],
// or (p_origin) a root at the origin.
std::vector<cplx> random_roots(std::mt19937& rng, int n, double p_origin) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<cplx> r;
  while (static_cast<int>(r.size()) < n) {
    const double w = u(rng);
    if (w < p_origin) {
      r.emplace_back(0.0, 0.0);
    } else if (w < 0.5 && static_cast<int>(r.size()) + 2 <= n) {
      const double re = -5.0 + 6.0 * u(rng), im = 0.2 + 4.8 * u(rng);
      r.emplace_back(re, im);
      r.emplace_back(re, -im);
    } else {
      r.emplace_back(-6.0 + 7.0 * u(rng), 0.0);
    }
  }
  return r;
}
}  // namespace

// The locus continues each gain's roots from the previous gain's (predictor + Newton, Aberth,
// eigenvalues as fallbacks). Over random 2nd..10th order loops (fixed seed; type 0-2, zeros up to
// equal order, both locus signs): every sample is a root of den + k num by residual, the root set
// at every sampled gain is the eigen solver's (closed_loop_poles, optimal matching), and inside
// the view no branch moves more than max_jump x width between successive gains.
TEST(RootLocus, ContinuedRootsAgreeWithTheEigenSolverOverRandomLoops) {
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int loops = 0, samples = 0;
  for (int trial = 0; trial < 180; ++trial) {
    const int n = 2 + trial % 9;
    const int m = static_cast<int>(u(rng) * (n + 1)) % (n + 1);  // 0..n zeros
    const double lead = (0.5 + 2.5 * u(rng)) * (u(rng) < 0.5 ? -1.0 : 1.0);
    const TransferFunction L{Poly::from_roots(random_roots(rng, m, 0.0), lead),
                             Poly::from_roots(random_roots(rng, n, 0.12))};
    LocusOptions o;
    o.negative = u(rng) < 0.3;
    const RootLocus rl = root_locus(L, o);
    ++loops;
    const double tol = o.max_jump * rl.view.width();
    for (std::size_t i = 0; i < rl.gains.size(); ++i) {
      const double k = rl.gains[i];
      const Poly c = L.den + L.num * k;
      std::vector<cplx> got;
      for (const auto& br : rl.branches) got.push_back(br[i]);
      const std::vector<cplx> ref = closed_loop_poles(L, k);
      ASSERT_EQ(got.size(), ref.size());
      double scale = 1.0;
      for (const cplx& s : ref)
        if (!std::isnan(s.real())) scale = std::max(scale, std::abs(s));
      const int nn = static_cast<int>(got.size());
      std::vector<double> cost(static_cast<std::size_t>(nn * nn));
      for (int a = 0; a < nn; ++a)
        for (int b = 0; b < nn; ++b) {
          const bool na = std::isnan(got[a].real()), nb = std::isnan(ref[b].real());
          cost[static_cast<std::size_t>(a * nn + b)] =
              (na && nb) ? 0.0 : (na || nb) ? 1e6 : std::abs(got[a] - ref[b]);
        }
      const auto col = solve_assignment(cost, nn);
      for (int a = 0; a < nn; ++a) {
        ASSERT_LE(cost[static_cast<std::size_t>(a * nn + col[a])], 1e-5 * scale)
            << "trial " << trial << " k = " << k << " root " << got[a] << " vs " << ref[col[a]]
            << " c = " << to_string(c) << " got " << ::testing::PrintToString(got) << " ref "
            << ::testing::PrintToString(ref) << " L " << to_string(L.num) << " / " << to_string(L.den);
        const cplx s = got[a];
        if (std::isnan(s.real())) continue;
        double terms = 0.0;
        for (int j = 0; j <= c.degree(); ++j) terms += std::abs(c.coeff(j)) * std::pow(std::abs(s), j);
        ASSERT_LE(std::abs(c(s)), 1e-9 * terms) << "trial " << trial << " k = " << k << " s = " << s << " c = " << to_string(c) << " got " << ::testing::PrintToString(got);
        ++samples;
      }
      if (i == 0) continue;
      const bool can_split = std::abs(k - rl.gains[i - 1]) > 1e-12 * std::abs(k);
      for (const auto& br : rl.branches) {
        const cplx a = br[i - 1], b = br[i];
        if (std::isnan(a.real()) || std::isnan(b.real()) || !can_split) continue;
        if (!rl.view.contains(a) && !rl.view.contains(b)) continue;
        const auto cl = [&](cplx s) {
          return cplx(std::clamp(s.real(), rl.view.re_min, rl.view.re_max),
                      std::clamp(s.imag(), rl.view.im_min, rl.view.im_max));
        };
        EXPECT_LE(std::abs(cl(a) - cl(b)), tol * (1 + 1e-9)) << "trial " << trial << " k = " << k;
      }
    }
  }
  EXPECT_EQ(loops, 180);
  EXPECT_GT(samples, 10000);
}
