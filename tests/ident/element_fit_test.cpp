// The grid (variable projection) base fit on random records from an independent GMS
// implementation (tests/ident/random_records.hpp): the validation error must reach the floor that
// noise, quantisation and sampling leave (the true model along the measured positions), across
// force scales, break-away displacements, sampling rates and element counts; expectations come
// from the generating truth only. (Individual parameters are not asserted: on coarse sampling Fc, the
// Stribeck tail and viscosity trade off within the noise; the floor is what the data determine.)
#include "core/ident/element_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/error.hpp"
#include "core/ident/job.hpp"
#include "core/ident/loop.hpp"
#include "core/io/session_io.hpp"
#include "tests/ident/random_records.hpp"

using namespace gmslab;
using namespace gmslab::ident;
using namespace gmslab::records;

// NNLS against brute force: every subset of the constrained variables as the active set; the
// best feasible stationary point is the optimum of the convex problem.
TEST(Nnls, MatchesExhaustiveActiveSetsOnRandomProblems) {
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const int m = 2 + trial % 5, n = 30;
    Eigen::MatrixXd A(n, m);
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) {
      y(i) = N(rng);
      for (int j = 0; j < m; ++j) A(i, j) = N(rng) + (j == 0 ? 0.5 : 0.0);
    }
    std::vector<bool> nonneg(static_cast<std::size_t>(m), true);
    nonneg[0] = trial % 2 == 0;  // sometimes one free variable
    const Eigen::MatrixXd G = A.transpose() * A;
    const Eigen::VectorXd b = A.transpose() * y;
    const Eigen::VectorXd x = nnls_gram(G, b, nonneg);
    double best = 1e300;
    for (int mask = 0; mask < (1 << m); ++mask) {
      std::vector<int> P;
      for (int j = 0; j < m; ++j)
        if ((mask >> j & 1) || !nonneg[static_cast<std::size_t>(j)]) P.push_back(j);
      Eigen::VectorXd z = Eigen::VectorXd::Zero(m);
      if (!P.empty()) {
        Eigen::MatrixXd Ap(n, static_cast<int>(P.size()));
        for (std::size_t k = 0; k < P.size(); ++k) Ap.col(static_cast<int>(k)) = A.col(P[k]);
        const Eigen::VectorXd zp = Ap.colPivHouseholderQr().solve(y);
        for (std::size_t k = 0; k < P.size(); ++k) z(P[k]) = zp(static_cast<int>(k));
      }
      bool ok = true;
      for (int j = 0; j < m; ++j) ok &= !nonneg[static_cast<std::size_t>(j)] || z(j) >= -1e-12;
      if (ok) best = std::min(best, (A * z - y).squaredNorm());
    }
    for (int j = 0; j < m; ++j)
      if (nonneg[static_cast<std::size_t>(j)]) {
        EXPECT_GE(x(j), 0.0);
      }
    EXPECT_NEAR((A * x - y).squaredNorm(), best, 1e-8 * (1 + best)) << "trial " << trial;
  }
}

namespace {

struct Case {
  unsigned seed;
  DrawRanges ranges;
};

// Records at three force scales and three break-away scales (random within each).
std::vector<Case> cases() {
  std::vector<Case> out;
  const double fs[][2] = {{0.1, 1.0}, {5.0, 50.0}, {200.0, 1000.0}};
  const double xb[][2] = {{0.5e-6, 5e-6}, {3e-6, 40e-6}, {20e-6, 200e-6}};
  unsigned seed = 500;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if ((i + j) % 2) continue;  // 5 of the 9 combinations keep the suite fast
      DrawRanges r;
      r.fs_lo = fs[i][0], r.fs_hi = fs[i][1];
      r.xba_lo = xb[j][0], r.xba_hi = xb[j][1];
      out.push_back({seed++, r});
    }
  return out;
}

}  // namespace

TEST(ElementGridFit, ReachesTheNoiseFloorOnRandomRecordsAcrossScales) {
  int within = 0, total = 0;
  for (const auto& cs : cases()) {
    Truth tr = draw_truth(cs.seed, cs.ranges);
    auto [gt, gv] = synthesize_pair(tr, cs.seed, 3000);
    const Dataset train = prepare_dataset(gt.record), val = prepare_dataset(gv.record);
    const double floor = floor_rms(tr, gv);
    FitSpec spec;
    spec.elements = tr.elements();
    const EffectContext c = make_context(train);
    const FitResult f = fit_model(spec, train, c, FitOptions{});
    const double v = rms_on(f, val, c);
    SCOPED_TRACE("seed " + std::to_string(cs.seed) + ": N " + std::to_string(tr.elements()) +
                 ", Fs " + std::to_string(tr.Fs) + " N, x_ba " + std::to_string(1e6 * tr.x_min()) +
                 ".." + std::to_string(1e6 * tr.x_max()) + " um, " + std::to_string(tr.rate) + " Hz");
    // The floor is the truth along the record's own samples (records::floor_rms: the cubic
    // through them, 16 substeps). Per record within 2x, and 4 of the 5 within 1.4x (a record
    // whose training motion barely separates Fc from the viscous term overfits them); the study
    // (gmslab_study base) measures the 1.2x rate.
    EXPECT_LE(v, 2.0 * floor) << "validation " << v << " N, floor " << floor << " N";
    within += v <= 1.4 * floor;
    ++total;
    EXPECT_LE(f.spec.elements, tr.elements());
  }
  EXPECT_GE(within, total - 1);
}

// A base fit that stays above the floor is fitted again from other basins (retry_base_fit), from
// design points that sample the attraction C / Fs at 20, 120, 800 and 5000 1/s, between the first
// design's levels (20, 300, 5000). Expected from the truth on random records whose C / Fs is set
// to 120 or 800 1/s, over three force scales (Fs, Fc, C, sigma2, k and the noise scaled together):
// the base fit (first fit and retry, as identify runs them) within 1.5x the floor on validation,
// and C within 25 % where the record shows the attraction - a slipping element relaxes by 0.1 to 1
// of the way within a sample step (C / Fs h; beyond, C has only a lower bound) and the floor is
// the noise (within 1.2x; a larger floor is a path the data cannot resolve, e.g. the slip that goes
// on below one encoder step at every stop). Tolerances chosen on records 8, 21, 29, 39 and 53,
// where the worst were C 0.83x and 1.32x the floor.
TEST(ElementGridFit, BaseFitFindsAnAttractionBetweenTheFirstDesignLevels) {
  const double scales[] = {0.01, 1.0, 30.0};
  int case_no = 0, observable = 0;
  for (unsigned seed : {61u, 62u, 63u}) {
    for (double c_over_fs : {120.0, 800.0}) {
      const double scale = scales[case_no++ % 3];
      Truth tr = draw_truth(seed);
      tr.Fs *= scale, tr.Fc *= scale, tr.sigma2 *= scale, tr.noise *= scale;
      for (auto& k : tr.k) k *= scale;
      tr.C = c_over_fs * tr.Fs;
      auto [gt, gv] = synthesize_pair(tr, seed, 4000);
      const Dataset train = prepare_dataset(gt.record), val = prepare_dataset(gv.record);
      FitSpec spec;
      spec.elements = tr.elements();
      LoopOptions lo;
      lo.max_rounds = 0;  // the base fit (and its retry) only, as gmslab_study base
      const IdentReport rep = identify(train, val, spec, lo);
      const double floor = floor_rms(tr, gv), relax = c_over_fs / tr.rate;
      SCOPED_TRACE("seed " + std::to_string(seed) + ", C/Fs " + std::to_string(c_over_fs) +
                   " 1/s, force scale " + std::to_string(scale) + ", C/Fs h " +
                   std::to_string(relax) + ", floor " + std::to_string(floor / tr.noise) +
                   " x noise, retried " + std::to_string(rep.base_retried));
      EXPECT_LE(rep.rms_after_validation, 1.5 * floor);
      if (relax >= 0.1 && relax <= 1.0 && floor <= 1.2 * tr.noise) {
        ++observable;
        EXPECT_NEAR(rep.final_fit().friction.scalar("C"), tr.C, 0.25 * tr.C);
      }
    }
  }
  EXPECT_GE(observable, 2);  // the C check is not vacuous
}

TEST(ElementGridFit, MaxwellSlipRecoversItsBreakAwayDisplacements) {
  // A Maxwell-slip truth is a GMS truth with Fs = Fc and instant attraction.
  Truth tr = draw_truth(42);
  tr.Fc = tr.Fs;
  tr.C = tr.Fs * 1e7;
  tr.sigma2 = 0;
  tr.alpha = {0.3, 0.7};
  tr.k = {0.3 * tr.Fs / 2e-6, 0.7 * tr.Fs / 30e-6};
  auto [gt, gv] = synthesize_pair(tr, 42, 3000);
  const Dataset train = prepare_dataset(gt.record), val = prepare_dataset(gv.record);
  FitSpec spec;
  spec.model = "maxwell_slip";
  spec.elements = 2;
  const EffectContext c = make_context(train);
  const FitResult f = fit_model(spec, train, c, FitOptions{});
  EXPECT_LE(rms_on(f, val, c), 1.25 * floor_rms(tr, gv));
  ASSERT_EQ(f.friction.elements.size(), 2u);
  std::vector<double> x;  // break-away displacements W / k
  for (const auto& row : f.friction.elements) x.push_back(row[1] / row[0]);
  std::sort(x.begin(), x.end());
  EXPECT_NEAR(x[0], 2e-6, 0.2e-6);
  EXPECT_NEAR(x[1], 30e-6, 3e-6);
}

TEST(ElementGridFit, AutoElementCountReachesTheFloorWithAtMostTwiceTheTruth) {
  Truth tr = draw_truth(77);
  tr.alpha = {0.5, 0.5};
  tr.k = {0.5 * tr.Fs / 3e-6, 0.5 * tr.Fs / 40e-6};
  auto [gt, gv] = synthesize_pair(tr, 77, 3000);
  const Dataset train = prepare_dataset(gt.record), val = prepare_dataset(gv.record);
  FitSpec spec;
  spec.elements = 0;  // auto
  const EffectContext c = make_context(train);
  const FitResult f = fit_base(spec, train, val, c, FitOptions{});
  EXPECT_GE(f.spec.elements, 1u);
  EXPECT_LE(f.spec.elements, 4u);  // never more than twice what the data holds
  EXPECT_LE(rms_on(f, val, c), 1.25 * floor_rms(tr, gv));
}

TEST(IdentifyJob, ElementCountParsesNumbersAndAutoAndNamesTheOption) {
  EXPECT_EQ(parse_element_count("4"), 4u);
  EXPECT_EQ(parse_element_count("auto"), 0u);
  for (const char* bad : {"0", "65", "four", "4x", ""}) {
    try {
      parse_element_count(bad);
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--elements"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("1 to 64"), std::string::npos);
    }
  }
}

// The panel's saved settings start from the job's defaults (one set of defaults for every front
// end; before, the panel masked pulse_code edges by default and the CLI did not).
TEST(IdentifyJob, PanelSettingsDefaultsAreTheJobDefaults) {
  const IdentifySettings s;
  const IdentifyJob j;
  EXPECT_EQ(s.mask_edges, j.train.mask_edges);
  EXPECT_EQ(s.mask, j.train.mask);
  EXPECT_EQ(s.model, j.spec.model);
  EXPECT_EQ(static_cast<std::size_t>(s.elements), j.spec.elements);
}

// Records that cannot identify friction get an error naming the record and what is missing
// (before, a record without motion crashed in the parameter uncertainty's QR).
TEST(IdentifyJob, RecordsWithoutMotionOrReversalAreRejectedWithTheReason) {
  auto record = [](bool moving) {
    MeasuredRecord r;
    r.source = moving ? "one-way.csv" : "still.csv";
    for (int i = 0; i < 400; ++i) {
      r.t.push_back(i * 1e-3);
      r.x.push_back(moving ? i * 1e-5 : 0.0);
      r.F.push_back(1.0 + 0.01 * std::sin(i));
    }
    return r;
  };
  auto message = [](const MeasuredRecord& r) {
    const Dataset d = prepare_dataset(r);
    try {
      identify(d, d, FitSpec{}, LoopOptions{});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string still = message(record(false)), oneway = message(record(true));
  EXPECT_NE(still.find("still.csv"), std::string::npos) << still;
  EXPECT_NE(still.find("does not change"), std::string::npos) << still;
  EXPECT_NE(oneway.find("one-way.csv"), std::string::npos) << oneway;
  EXPECT_NE(oneway.find("never reverses"), std::string::npos) << oneway;
}
