// Phase-lead design with the largest reachable error constant: every worked example of
// docs/references.md (G1 to G4, relocation), to 1e-4.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/control/design_session.hpp"
#include "core/control/lead_design.hpp"
#include "core/error.hpp"

using namespace gmslab::control;

namespace {
TransferFunction tf(std::vector<double> num, std::vector<double> den) {
  return {Poly::descending(num), Poly::descending(den)};
}
const TransferFunction G1 = tf({4}, {1, 2, 0});
const TransferFunction G2 = tf({1}, {1, 6, 5, 0});  // 1/(s(s+1)(s+5))
const TransferFunction G3 = tf({1}, {1, 4, 3});     // 1/((s+1)(s+3))
const TransferFunction G4 = tf({1}, {1, 0, 0});     // 1/s^2
constexpr double kTol = 1e-4;
constexpr double kDeg = 180.0 / std::numbers::pi;

// True when every expected pole appears among the computed ones (to tol).
void expect_poles(const std::vector<cplx>& got, const std::vector<cplx>& want, double tol) {
  ASSERT_EQ(got.size(), want.size());
  for (const cplx& w : want) {
    double best = 1e300;
    for (const cplx& g : got) best = std::min(best, std::abs(g - w));
    EXPECT_LT(best, tol) << "expected closed-loop pole " << w.real() << " + j" << w.imag();
  }
}

struct Row {
  double K, z, p, Kc;
  std::vector<cplx> poles;
};
}  // namespace

TEST(LeadDesignG1, LimitsMatchTheWorkedExample) {
  const LeadLimits L = lead_limits(G1, {0.5, 4.0});
  EXPECT_NEAR(L.phi * kDeg, 30.0, kTol);
  EXPECT_NEAR(L.beta * kDeg, 60.0, kTol);
  EXPECT_NEAR(L.G_abs, 0.288675, 1e-6);
  EXPECT_NEAR(L.M, 6.928203, 1e-6);
  EXPECT_TRUE(L.applicable);
  EXPECT_NEAR(L.K_max, 8.0, kTol);
  EXPECT_NEAR(L.pd_Kd, 0.5, kTol);
  EXPECT_NEAR(L.pd_z, 8.0, kTol);
  EXPECT_NEAR(plant_type(G1).K0, 2.0, 1e-12);
  EXPECT_EQ(plant_type(G1).n, 1);
}

TEST(LeadDesignG1, TableRowsPlaceTheDominantRootsAndReachKv) {
  const double r3 = 3.4641016;
  const std::vector<Row> rows = {
      {2, 0.8, 2.6666667, 3.3333333, {{-2, r3}, {-2, -r3}, {-0.6666667, 0}}},
      {4, 2.0, 4.0, 4.0, {{-2, r3}, {-2, -r3}, {-2, 0}}},
      {5, 2.8571429, 5.3333333, 4.6666667, {{-2, r3}, {-2, -r3}, {-3.3333333, 0}}},
      {7, 5.6, 16.0, 10.0, {{-2, r3}, {-2, -r3}, {-14, 0}}},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE("Kv = " + std::to_string(r.K));
    const LeadDesign d = design_for_constant(G1, {0.5, 4.0}, r.K);
    EXPECT_NEAR(d.z, r.z, kTol);
    EXPECT_NEAR(d.p, r.p, kTol);
    EXPECT_NEAR(d.Kc, r.Kc, kTol);
    EXPECT_NEAR(d.K, r.K, 1e-9);
    expect_poles(d.closed_loop_poles, r.poles, kTol);
  }
}

TEST(LeadDesignG1, LinearSystemCheckAgreesWithClosedForm) {
  for (double K : {0.5, 2.0, 4.0, 5.0, 7.0, 7.9}) {
    const LeadDesign a = design_for_constant(G1, {0.5, 4.0}, K);
    const LeadDesign b = design_by_linear_system(G1, {0.5, 4.0}, K);
    EXPECT_NEAR(a.z, b.z, 1e-8 * (1 + a.z));
    EXPECT_NEAR(a.p, b.p, 1e-8 * (1 + a.p));
    EXPECT_NEAR(a.Kc, b.Kc, 1e-8 * (1 + a.Kc));
  }
}

TEST(LeadDesignG1, ErrorConstantRisesMonotonicallyTowardKmaxAsTheZeroMovesLeft) {
  const LeadLimits L = lead_limits(G1, {0.5, 4.0});
  double prev = 0.0;
  for (double t = 0.99; t > 0.01; t -= 0.01) {
    const double th = L.phi + t * (std::numbers::pi - L.beta - L.phi);
    const LeadDesign d = design_at_zero_angle(G1, {0.5, 4.0}, th);
    EXPECT_GT(d.K, prev);
    EXPECT_LT(d.K, L.K_max);
    prev = d.K;
  }
  EXPECT_GT(prev, 0.95 * L.K_max);
}

TEST(LeadDesignG1, Kv12IsBeyondReachAndKeepZetaNeedsWnAboveSqrt24) {
  const LeadReport r = lead_design(G1, {0.5, 4.0}, 12.0, {20.0, 1e-9});
  EXPECT_FALSE(r.design.has_value());
  ASSERT_EQ(r.relocations.size(), 3u);
  const Relocation& kz = r.relocations[0];
  EXPECT_EQ(kz.path, "keep_zeta");
  ASSERT_TRUE(kz.found) << kz.reason;
  EXPECT_NEAR(kz.root.zeta, 0.5, 1e-12);
  EXPECT_NEAR(kz.root.wn, std::sqrt(24.0), 1e-6);
  // The document's example point on that path: wn = 5.5.
  const LeadDesign d = design_for_constant(G1, {0.5, 5.5}, 12.0);
  EXPECT_NEAR(d.z, 5.7840, kTol);
  EXPECT_NEAR(d.p, 16.940, 5e-4);
  EXPECT_NEAR(d.Kc, 17.573, 6e-4);  // printed to 3 decimals (17.5725 rounded up)
  // With the default 10% margin every found path's design reaches Kv = 12 exactly.
  for (const Relocation& rel : lead_design(G1, {0.5, 4.0}, 12.0).relocations) {
    if (!rel.found) continue;
    EXPECT_NEAR(rel.K_max, 13.2, 1e-6) << rel.path;
    EXPECT_NEAR(rel.design.K, 12.0, 1e-9) << rel.path;
    // The new dominant root is a closed-loop pole.
    double best = 1e300;
    for (const cplx& p : rel.design.closed_loop_poles) best = std::min(best, std::abs(p - rel.root.s()));
    EXPECT_LT(best, 1e-6) << rel.path;
  }
}

TEST(LeadDesignG2, LimitsAndTableRows) {
  const LeadLimits L = lead_limits(G2, {0.5, 2.0});
  EXPECT_NEAR(L.phi * kDeg, 53.413, 1e-3);
  EXPECT_NEAR(L.M, 3.019934, 1e-6);
  EXPECT_NEAR(L.K_max, 3.2, kTol);
  EXPECT_NEAR(L.pd_Kd, 7.0, kTol);
  EXPECT_NEAR(L.pd_z, 2.285714, 1e-6);
  const double r3 = 1.7320508;
  const std::vector<Row> rows = {
      {1, 0.64220, 2.54545, 19.818, {{-1, r3}, {-1, -r3}, {-0.5288, 0}, {-6.0166, 0}}},
      {2, 1.34615, 4.66667, 34.667, {{-1, r3}, {-1, -r3}, {-1.6667, 0}, {-7.0, 0}}},
      {3, 2.12121, 28.0, 198.0, {{-1, r3}, {-1, -r3}, {-3.7118, 0}, {-28.288, 0}}},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE("Kv = " + std::to_string(r.K));
    const LeadDesign d = design_for_constant(G2, {0.5, 2.0}, r.K);
    // z, p are printed to 5 decimals, Kc and -28.288 to 3: each checked to its printed precision.
    EXPECT_NEAR(d.z, r.z, 1e-5);
    EXPECT_NEAR(d.p, r.p, 1e-5);
    EXPECT_NEAR(d.Kc, r.Kc, 5e-4);
    expect_poles(d.closed_loop_poles, r.poles, r.K == 3 ? 5e-4 : 1e-4);
  }
}

TEST(LeadDesignG2, KmaxAtConstantZetaPeaksAt6Point4AndVanishesAtWn6) {
  for (double wn : {1.0, 2.0, 3.0, 4.0, 5.0, 5.9}) {
    const LeadLimits L = lead_limits(G2, {0.5, wn});
    ASSERT_TRUE(L.applicable) << wn;
    EXPECT_NEAR(L.K_max, wn * wn * (6 - wn) / 5, 1e-9) << wn;
  }
  EXPECT_FALSE(lead_limits(G2, {0.5, 6.1}).applicable);
  // Kv = 8 is out of reach at zeta = 0.5 whatever wn: the keep-zeta path says so and why.
  const auto rel = relocate(G2, {0.5, 2.0}, 8.0, 0.1);
  const Relocation& kz = rel[0];
  EXPECT_FALSE(kz.found);
  EXPECT_NEAR(kz.peak_K, 6.4, 1e-6);
  EXPECT_NEAR(kz.peak_root.wn, 4.0, 1e-3);
  EXPECT_NE(kz.reason.find("peaks at 6.4"), std::string::npos) << kz.reason;
  EXPECT_NE(kz.reason.find("phi reaches pi - beta"), std::string::npos) << kz.reason;
}

TEST(LeadDesignG2, KeepingZetaWnTheDampedFrequencyRaisesKmax) {
  for (auto [wd, kv] : {std::pair{2.0, 4.0}, {3.0, 8.0}, {4.0, 13.6}}) {
    const double wn = std::hypot(1.0, wd);
    EXPECT_NEAR(lead_limits(G2, {1.0 / wn, wn}).K_max, kv, kTol) << wd;
  }
  // Relocation for Kv = 8 (margin ~0) along keep zeta wn lands on wd = 3.
  const auto rel = relocate(G2, {0.5, 2.0}, 8.0, 1e-9);
  const Relocation& ks = rel[1];
  EXPECT_EQ(ks.path, "keep_zeta_wn");
  ASSERT_TRUE(ks.found) << ks.reason;
  EXPECT_NEAR(ks.root.zeta * ks.root.wn, 1.0, 1e-9);
  EXPECT_NEAR(ks.root.wn * std::sqrt(1 - ks.root.zeta * ks.root.zeta), 3.0, 1e-5);
}

TEST(LeadDesignTypes, Type0PlantG3) {
  const LeadLimits L = lead_limits(G3, {0.5, 6.0});
  EXPECT_EQ(plant_type(G3).n, 0);
  EXPECT_NEAR(L.K_max, 11.0, kTol);
  const LeadDesign d = design_for_constant(G3, {0.5, 6.0}, 5.0);
  EXPECT_NEAR(d.z, 2.069, 5e-4);  // printed to 3 decimals
  EXPECT_NEAR(d.p, 4.0, kTol);
  EXPECT_NEAR(d.Kc, 29.0, kTol);
  const LeadDesign c = design_by_linear_system(G3, {0.5, 6.0}, 5.0);
  EXPECT_NEAR(c.z, d.z, 1e-8);
  EXPECT_NEAR(c.Kc, d.Kc, 1e-7);
}

TEST(LeadDesignTypes, Type2PlantG4) {
  const LeadLimits L = lead_limits(G4, {0.5, 1.0});
  EXPECT_EQ(plant_type(G4).n, 2);
  EXPECT_NEAR(L.K_max, 1.0, kTol);
  const LeadDesign d = design_for_constant(G4, {0.5, 1.0}, 0.5);
  EXPECT_NEAR(d.z, 0.5, kTol);
  EXPECT_NEAR(d.p, 2.0, kTol);
  EXPECT_NEAR(d.Kc, 2.0, kTol);
  const double r = std::sqrt(3.0) / 2;
  // (s + 2) s^2 + 2 (s + 0.5) = (s^2 + s + 1)(s + 1)
  expect_poles(d.closed_loop_poles, {{-0.5, r}, {-0.5, -r}, {-1, 0}}, kTol);
}

TEST(LeadDesignApplicability, LeadCannotAddMoreThanPiMinusBeta) {
  // 1/s^3 at zeta = 0.5: arg G = -3 (2 pi / 3) = -2 pi -> phi = pi; pi - beta = 120 deg.
  const LeadLimits L = lead_limits(tf({1}, {1, 0, 0, 0}), {0.5, 1.0});
  EXPECT_FALSE(L.applicable);
  EXPECT_NE(L.reason.find("one lead cannot"), std::string::npos);
  // A plant with more than enough phase: phi <= 0, s_d needs lag, not lead.
  const LeadLimits M = lead_limits(tf({1}, {1, 1}), {0.5, 1.0});
  EXPECT_FALSE(M.applicable);
  EXPECT_LE(M.phi, 0.0);
  EXPECT_NE(M.reason.find("needs phase lag"), std::string::npos) << M.reason;
}

TEST(LeadDesignUsableMax, BoundedPoleZeroRatioGivesTheLargestKWithinTheBound) {
  const LeadReport r = lead_design(G1, {0.5, 4.0}, std::nullopt, {20.0, 0.1});
  ASSERT_TRUE(r.usable_design.has_value());
  EXPECT_NEAR(r.usable_design->p / r.usable_design->z, 20.0, 1e-6);
  EXPECT_LT(r.K_max_usable, r.limits.K_max);
  EXPECT_GT(r.K_max_usable, 7.0);  // the table's Kv = 7 design has p/z = 2.86
  // A slightly larger K needs p/z > 20.
  const LeadDesign d = design_for_constant(G1, {0.5, 4.0}, r.K_max_usable * 1.001);
  EXPECT_GT(d.p / d.z, 20.0);
}

TEST(LeadDesignDominance, SlowPoleNearTheZeroIsFlaggedOrCancelled) {
  // G2 at Kv = 1: a slow pole at -0.5288 next to the zero at -0.6422.
  const LeadDesign d = design_for_constant(G2, {0.5, 2.0}, 1.0);
  ASSERT_FALSE(d.dominance.notes.empty());
  // G1 at Kv = 4: the third pole -2 sits exactly on the zero -2: zero residue, dominant.
  const LeadDesign e = design_for_constant(G1, {0.5, 4.0}, 4.0);
  EXPECT_TRUE(e.dominance.dominant);
  ASSERT_EQ(e.dominance.others.size(), 1u);
  EXPECT_LT(e.dominance.others[0].residue, 1e-6);
}

TEST(LeadDesignInput, BadDominantRootsAndConstantsAreRejected) {
  EXPECT_THROW(lead_limits(G1, {0.0, 4.0}), gmslab::InputError);
  EXPECT_THROW(lead_limits(G1, {1.0, 4.0}), gmslab::InputError);
  EXPECT_THROW(lead_limits(G1, {0.5, -1.0}), gmslab::InputError);
  // wn beyond [1e-12, 1e12] rad/s (cli_fuzz: wn = 2.2e119 overflowed the design's polynomials);
  // the message names the range, and its ends are accepted.
  for (double wn : {1e-13, 1.1e12, 2.2e119, std::numeric_limits<double>::infinity()}) {
    try {
      lead_limits(G1, {0.5, wn});
      ADD_FAILURE() << "accepted wn = " << wn;
    } catch (const gmslab::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("must be in [1e-12, 1e+12] rad/s"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(lead_limits(G1, {0.5, kMinWn}));
  EXPECT_NO_THROW(lead_limits(G1, {0.5, kMaxWn}));
  EXPECT_THROW(design_for_constant(G1, {0.5, 4.0}, -1.0), gmslab::InputError);
  EXPECT_THROW(design_for_constant(G1, {0.5, 4.0}, 8.0), gmslab::InputError);
  EXPECT_THROW(lead_design(tf({1, 0}, {1, 2, 1}), {0.5, 4.0}, 1.0), gmslab::InputError);
  EXPECT_THROW(lead_design(tf({1, 0, 0}, {1, 2}), {0.5, 4.0}, 1.0), gmslab::InputError);
}

// Lead-lag over random type-1 plants K/(s (s + a)) and desired roots: the lead is designed for
// K_lead (design_for_constant), the lag buys the factor F = K_target/K_lead. Checked independently:
// the error constant lim s Gc G as s -> 0 (evaluated at s = 1e-9 |s_d|) equals K_target; the lag's
// angle at s_d is the phase of Gc_leadlag / Gc_lead there and is small (zero at 0.1 |Re s_d|); the
// closed-loop pole set has a pair within 25 % of |s_d| of s_d (the lag's small angle moves it a
// little; up to x20 lags), and the price: a slow real pole within 50 % of the lag zero -z_l
// (its branch ends there), time constant about 1/z_l, over 3x that of the dominant pair.
TEST(LeadLag, LagBuysTheErrorConstantAndLeavesASlowPoleNearItsZero) {
  std::mt19937 rng(1229);
  std::uniform_real_distribution<double> ua(0.5, 5.0), uk(0.5, 10.0), uz(0.4, 0.8), uw(2.0, 8.0), uf(3.0, 20.0);
  int designs = 0;
  for (int i = 0; i < 60; ++i) {
    const double a = ua(rng), k = uk(rng);
    const TransferFunction g{Poly({k}), Poly({0.0, a, 1.0})};
    const DominantRoot root{uz(rng), uw(rng)};
    const LeadLimits lim = lead_limits(g, root);
    if (!lim.applicable || !(lim.K_max > 0.0)) continue;
    const double K_lead = 0.5 * lim.K_max;
    const LeadDesign ld = design_for_constant(g, root, K_lead);
    const double F = uf(rng);
    const LeadLagDesign ll = design_lead_lag(g, {ld.Kc, ld.z, ld.p}, root, F * K_lead);
    ++designs;
    const TransferFunction c = ll.tf();
    const double s0 = 1e-9 * root.wn;
    const double K = (cplx(s0) * c.num(cplx(s0)) * g.num(cplx(s0)) / (c.den(cplx(s0)) * g.den(cplx(s0)))).real();
    EXPECT_NEAR(ll.K_lead, K_lead, 1e-6 * K_lead);
    EXPECT_NEAR(K, F * K_lead, 1e-5 * F * K_lead) << "i " << i;
    const cplx sd = root.s();
    const TransferFunction cl{Poly({ld.Kc * ld.z, ld.Kc}), Poly({ld.p, 1.0})};
    const double ang = std::arg((c.num(sd) / c.den(sd)) / (cl.num(sd) / cl.den(sd))) * 180 / std::numbers::pi;
    EXPECT_NEAR(ll.lag_angle_deg, ang, 1e-9);
    EXPECT_LT(ll.lag_angle_deg, 0.0);
    EXPECT_GT(ll.lag_angle_deg, -8.0);
    EXPECT_LT(std::abs(ll.dominant - sd), 0.25 * std::abs(sd)) << "i " << i;
    // Closed-loop poles independently: roots of (s+p)(s+pl) den + Kc (s+z)(s+zl) num.
    const std::vector<cplx> ref = (c.den * g.den + c.num * g.num).roots();
    ASSERT_EQ(ref.size(), ll.closed_loop_poles.size());
    int slow = 0;
    for (const cplx& s : ref)
      if (std::abs(s.imag()) < 1e-9 && std::abs(s.real() + ll.zl) < 0.5 * ll.zl) ++slow;
    EXPECT_GE(slow, 1) << "i " << i;
    EXPECT_NEAR(std::abs(ll.slow_pole.imag()), 0.0, 1e-9);
    EXPECT_LT(ll.time_constant, 1.0 / (0.5 * ll.zl));
    EXPECT_GT(ll.time_constant, 1.0 / (1.5 * ll.zl));
    EXPECT_GT(ll.time_constant, 3.0 / std::abs(sd.real()));  // far slower than the dominant pair
  }
  EXPECT_GT(designs, 40);
  const DominantRoot root{0.5, 4.0};
  const TransferFunction g1{Poly({4.0}), Poly({0.0, 2.0, 1.0})};
  const LeadDesign ld = design_for_constant(g1, root, 5.0);
  EXPECT_THROW(design_lead_lag(g1, {ld.Kc, ld.z, ld.p}, root, 4.0), gmslab::InputError);  // below the lead's
}
