// Long records: the residual loop screens every k-th sample (LoopOptions::screen_samples,
// core/ident/dataset.hpp decimated) and the ripple search scans a fixed random subset of the sliding
// samples (kRippleScan). Records from the independent GMS implementation
// (tests/ident/random_records.hpp) and a hand-made constant-speed record; expectations from the
// generating truth or from the full-record arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "core/ident/loop.hpp"
#include "core/ident/structure.hpp"
#include "tests/ident/random_records.hpp"

using namespace gmslab;
using namespace gmslab::ident;

// Every k-th sample with the full-rate derived signals; steps, step velocities and the path made
// again between the kept samples: the parts of an interval add up to its step and its travel.
TEST(IdentScreen, DecimatedKeepsEveryKthSampleAndRebuildsThePath) {
  for (unsigned seed : {4u, 17u, 33u}) {
    records::Truth tr = records::draw_truth(seed);
    const Dataset d = prepare_dataset(records::synthesize(tr, seed, 3000).record);
    for (std::size_t k : {std::size_t{2}, std::size_t{3}, std::size_t{7}}) {
      const Dataset s = decimated(d, k, PathRule{});
      ASSERT_EQ(s.size(), (d.size() + k - 1) / k) << "seed " << seed << " every " << k;
      for (std::size_t j = 0; j < s.size(); ++j) {
        ASSERT_EQ(s.t[j], d.t[j * k]);
        ASSERT_EQ(s.x[j], d.x[j * k]);
        ASSERT_EQ(s.F[j], d.F[j * k]);
        ASSERT_EQ(s.v[j], d.v[j * k]);
        ASSERT_EQ(s.a[j], d.a[j * k]);
        ASSERT_EQ(s.use[j], d.use[j * k]);
      }
      for (std::size_t j = 1; j < s.size(); ++j) {
        EXPECT_DOUBLE_EQ(s.h[j], d.t[j * k] - d.t[(j - 1) * k]);
        double h = 0, dx = 0;
        for_each_step(s, j, [&](double v, double hh) { h += hh, dx += v * hh; });
        EXPECT_NEAR(h, s.h[j], 1e-12 * s.h[j]);
        EXPECT_NEAR(dx, s.x[j] - s.x[j - 1], 1e-9 * std::max(std::abs(s.x[j] - s.x[j - 1]), 1e-9));
      }
    }
    // every = 1 is the record itself.
    const Dataset same = decimated(d, 1, PathRule{});
    EXPECT_EQ(same.x, d.x);
    EXPECT_EQ(same.sv, d.sv);
  }
}

// A ripple shorter than the mean travel between the scanned samples of a long record: strokes of
// 50 mm at 20 mm/s sampled at 1 kHz (20 um steps), wavelength 70 um (3.5 samples); 30,000 samples,
// of which the periodogram scans 6,000 (on average one in 100 um of travel). An aliasing subset
// (an even stride on a grid) would show the ripple at a longer wavelength as well; the peak's
// refinement and fit use all samples. Amplitude 3 x the noise. Expected: the wavelength within
// 0.5 %, the amplitude within 15 %, significant; the same on a record the scan covers whole, at
// position scales 0.05-20 and force scales 0.01-100.
TEST(IdentRipple, ScanSubsetOfALongRecordFindsAShortRipple) {
  // Position scales (speed, stroke and wavelength together) and force scales (amplitude and noise).
  for (double xs : {0.05, 1.0, 20.0})
    for (double fs : {1e-2, 1.0, 1e2})
      for (std::size_t n : {std::size_t{30000}, kRippleScan}) {
        MeasuredRecord r;
        r.source = "constant-speed strokes";
        const double h = 1e-3, v = 0.02 * xs, L = 3.5 * v * h, A = 0.3 * fs, noise = 0.1 * fs;
        const long stroke = 2500;  // samples per stroke (50 mm at xs = 1)
        std::mt19937 rng(7);
        std::normal_distribution<double> N(0.0, noise);
        long m = 0, dir = 1;
        for (std::size_t k = 0; k < n + 200; ++k) {
          r.t.push_back(static_cast<double>(k) * h);
          r.x.push_back(static_cast<double>(m) * v * h);
          r.F.push_back(0.0);
          m += dir;
          if (m >= stroke || m <= 0) dir = -dir;
        }
        const Dataset d = prepare_dataset(r);
        const EffectContext c = make_context(d);
        std::vector<double> res(d.size());
        for (std::size_t k = 0; k < d.size(); ++k) res[k] = A * std::sin(2 * std::numbers::pi * d.x[k] / L + 0.4) + N(rng);
        const RippleSearch s = ripple_search(d, c, res, {});
        const std::string where = std::to_string(n) + " samples, x scale " + std::to_string(xs) + ", F scale " + std::to_string(fs);
        ASSERT_FALSE(s.peaks.empty()) << where;
        EXPECT_GT(s.samples, kRippleScan / 2) << where;
        EXPECT_NEAR(s.peaks[0].wavelength, L, 0.005 * L) << where;
        EXPECT_NEAR(s.peaks[0].amplitude, A, 0.15 * A) << where;
        EXPECT_LT(s.peaks[0].false_alarm, 1e-6) << where;
      }
}

// The loop on long records (8,000 samples) that it screens on every 3rd sample (the study's records
// 11, 19 and 21: a friction ripple; none; a quadratic drag and an offset, each 2-10 x the noise, as
// `gmslab_study loop` draws them). Expected from the truth: the generated effects are named and
// nothing else, the validation RMS within 1.5 x the floor that noise and quantisation leave; the
// final training RMS is the final model's on all samples.
TEST(IdentScreen, ScreenedLoopNamesTheEffectsAndReachesTheFloor) {
  using records::GenEffect;
  const GenEffect one[] = {GenEffect::Inertia, GenEffect::Offset, GenEffect::DirectionAsymmetry,
                           GenEffect::PositionRipple, GenEffect::PositionDependent,
                           GenEffect::TimeDrift, GenEffect::VelocityExtra, GenEffect::NormalLoad};
  for (unsigned seed : {11u, 19u, 21u}) {
    const int i = static_cast<int>(seed) - 1, kind = i % 3;  // as bench/study/ident_study.cpp
    records::Truth tr = records::draw_truth(seed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    if (kind >= 1) tr.effects.push_back({one[(i / 3) % 8], 2.0 + 8.0 * U(rng)});
    if (kind == 2) tr.effects.push_back({one[(i / 3 + 3) % 8], 2.0 + 8.0 * U(rng)});
    auto [g_train, g_val] = records::synthesize_pair(tr, seed, 8000);
    const Dataset train = prepare_dataset(g_train.record), val = prepare_dataset(g_val.record);
    FitSpec spec;
    spec.elements = tr.elements();
    const IdentReport rep = identify(train, val, spec, LoopOptions{});
    EXPECT_EQ(rep.screen_every, 3u) << "seed " << seed;
    std::vector<std::string> named, generated;
    for (auto e : rep.effects_added) named.emplace_back(effect_name(e));
    for (const auto& g : tr.effects) generated.emplace_back(records::gen_effect_name(g.kind));
    std::sort(named.begin(), named.end());
    std::sort(generated.begin(), generated.end());
    EXPECT_EQ(named, generated) << "seed " << seed;
    EXPECT_LE(rep.rms_after_validation, 1.5 * records::floor_rms(tr, g_val)) << "seed " << seed;
    EXPECT_NEAR(rep.rms_after_train, rms_on(rep.final_fit(), train, rep.context), 1e-9 * rep.rms_after_train);
  }
}
