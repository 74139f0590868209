// Tests of the variable-projection fit on records generated with gmslab's own GMS model.
#include "core/ident/fit.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "core/ident/effects.hpp"
#include "core/ident/structure.hpp"
#include "tests/ident/random_records.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

TEST(IdentFit, GmsFitOfCleanGmsRecordReachesNoiseLevel) {
  synth::SynthOptions so;
  const auto rec = synth::synthesize(so);
  const auto d = prepare_dataset(rec);
  const auto c = make_context(d);
  FitOptions o;
  o.starts = 2;
  FitSpec spec;
  auto t0 = std::chrono::steady_clock::now();
  const auto r = fit_model(spec, d, c, o);
  auto dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("n=%zu evaluations=%d rms=%.4f N (%.2f s)\n", d.size(), r.evaluations, r.rms_train, dt);
  EXPECT_LT(r.rms_train, 1.3 * so.noise);
  // The shared Stribeck curve and viscous term of the generating model are recovered.
  const auto g = synth::synth_gms();
  EXPECT_NEAR(r.friction.scalar("Fs"), g.S.Fs, 0.02 * g.S.Fs);
  EXPECT_NEAR(r.friction.scalar("Fc"), g.S.Fc, 0.02 * g.S.Fc);
  EXPECT_NEAR(r.friction.scalar("Vs"), g.S.Vs, 0.1 * g.S.Vs);
  EXPECT_NEAR(r.friction.scalar("sigma2"), g.sigma2, 0.05 * g.sigma2);
  double sum = 0;
  for (double a : r.friction.column("alpha")) sum += a;
  EXPECT_NEAR(sum, 1.0, 1e-9);
}


// Any registered model can be fitted through its ModelInfo: the identified parameters are valid
// for the model, and every model with a state (presliding memory) explains most of the force of a
// GMS record. Static models (state-free) return zero force at rest while the GMS record holds
// its presliding force through every dwell, so they only have to beat the zero model.
TEST(IdentFit, EveryRegisteredModelFitsThroughItsModelInfo) {
  synth::SynthOptions so;
  so.moves = 4;
  so.rate = 250.0;
  const auto d = prepare_dataset(synth::synthesize(so));
  const auto c = make_context(d);
  double f2 = 0;
  for (std::size_t k = 0; k < d.size(); ++k) f2 += d.F[k] * d.F[k];
  const double null_rms = std::sqrt(f2 / static_cast<double>(d.size()));
  for (const auto& info : model_registry()) {
    FitSpec spec;
    spec.model = std::string(info.tag);
    spec.elements = 2;
    FitOptions o;
    o.starts = 1;
    o.max_evaluations = 60;
    const auto r = fit_model(spec, d, c, o);
    EXPECT_TRUE(validate(r.friction).empty()) << info.tag;
    const bool dynamic = build_model(info.defaults())->state_size() > 0;
    EXPECT_LT(r.rms_train, (dynamic ? 0.2 : 0.9) * null_rms) << info.tag;
    std::printf("  %-14s rms %.3f N\n", std::string(info.tag).c_str(), r.rms_train);
  }
}

// The path between samples. A model driven along straight lines between coarse samples misses
// what happens between them (here: every reversal of a sine falls between two samples); along the
// cubic through the samples (the dataset's substeps) it follows the motion. The reference is the
// same model along the same motion sampled 8x finer. The floor's sampling share sizes the
// straight-line error. Random amplitudes, phases and rates (fixed seeds).
TEST(IdentFit, CubicPathBetweenSamplesFollowsADenseRecordAndSizesTheSamplingFloor) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    const double A = 1e-4 * std::pow(10.0, 2 * U(rng));   // 0.1 .. 10 mm
    const double f = 0.5 + U(rng);                         // 0.5 .. 1.5 Hz
    const double rate = f * (16 + 16 * U(rng));            // 16 .. 32 samples per period
    const double phase = U(rng);
    const double w = 2 * std::numbers::pi * f;
    auto record = [&](int fine) {
      MeasuredRecord r;
      r.source = "sine";
      const double dt = 1.0 / (rate * fine);
      for (int k = 0; k < static_cast<int>(8 / f * rate * fine); ++k) {
        const double t = (k + phase * fine) * dt;
        r.t.push_back(t);
        r.x.push_back(A * std::sin(w * t));
        r.v.push_back(A * w * std::cos(w * t));
        r.F.push_back(0.0);
      }
      return prepare_dataset(r);
    };
    const Dataset coarse = record(1), dense = record(8);
    const EffectContext c = make_context(coarse);
    FitResult r;
    r.spec.model = "gms";
    r.spec.elements = 3;
    r.u = Parameterization(model_info("gms"), 3, c).initial();
    const auto g_line = unit_friction(r, with_straight_steps(coarse), c);
    const auto g_cubic = unit_friction(r, coarse, c);  // along the cubic where it is curved
    const auto g_dense = unit_friction(r, dense, c);
    double e_line = 0, e_cubic = 0, n = 0;
    for (std::size_t k = 0; k < coarse.size(); ++k) {
      if (!coarse.use[k] || k < coarse.size() / 8) continue;  // past the virgin first cycle
      const double ref = g_dense[8 * k];
      e_line += (g_line[k] - ref) * (g_line[k] - ref);
      e_cubic += (g_cubic[k] - ref) * (g_cubic[k] - ref);
      n += 1;
    }
    e_line = std::sqrt(e_line / n), e_cubic = std::sqrt(e_cubic / n);
    // The straight lines cut every reversal short: a visible error on the unit force level.
    ASSERT_GT(e_line, 1e-3) << "trial " << trial;
    EXPECT_LT(e_cubic, 0.25 * e_line) << "trial " << trial;
    // The floor's sampling share sizes the straight-line error.
    NoiseEstimate ne;
    add_sampling(ne, coarse, g_cubic, g_line);
    EXPECT_GT(ne.sampling, 0.5 * e_line / std::sqrt(3.0)) << "trial " << trial;
    EXPECT_LT(ne.sampling, 2.0 * e_line / std::sqrt(3.0)) << "trial " << trial;
    EXPECT_NEAR(ne.floor(), ne.sampling, 1e-12);
  }
}

// The motion a model is stepped through moves by the measured displacement over every step, with
// or without a velocity column: a file's v (sampled, possibly filtered) sets the path's shape, not
// how far a step goes. Random sines and velocity columns off by a random factor over scales.
TEST(IdentDataset, EveryStepMovesByTheMeasuredDisplacementWithOrWithoutAVelocityColumn) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    const double amp = std::pow(10.0, -7 + 5 * U(rng)), f = std::pow(10.0, -1 + 2 * U(rng));
    const double dt = 1.0 / (f * (50 + 2000 * U(rng))), bias = 0.8 + 0.4 * U(rng);
    MeasuredRecord r;
    for (int k = 0; k < 800; ++k) {
      const double t = k * dt, w = 2 * std::numbers::pi * f;
      r.t.push_back(t);
      r.x.push_back(amp * std::sin(w * t));
      r.F.push_back(std::sin(w * t) > 0 ? 1.0 : -1.0);
      if (trial % 2 == 0) r.v.push_back(bias * amp * w * std::cos(w * t));
    }
    const Dataset d = prepare_dataset(r);
    double moved = 0;
    for (std::size_t k = 1; k < d.size(); ++k) for_each_step(d, k, [&](double v, double h) { moved += v * h; });
    // Along the path every step's parts add up to the sample-to-sample displacement.
    EXPECT_NEAR(moved, d.x.back() - d.x.front(), 1e-9 * amp) << "trial " << trial;
    for (std::size_t k = 1; k < d.size(); ++k)
      ASSERT_NEAR(d.vstep[k] * d.h[k], d.x[k] - d.x[k - 1], 1e-12 * amp) << "trial " << trial << " step " << k;
  }
}

namespace {

// 200 samples of a polynomial of `degree` in u = t rate / 50 (a few units over the record) with
// random coefficients of a random scale, on a jittered non-uniform grid at a random rate.
struct PolynomialRecord {
  std::vector<double> t, y, c;
  double scale = 0, rate = 0;
};
PolynomialRecord random_polynomial_record(std::mt19937& rng, int degree) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  PolynomialRecord p;
  p.scale = std::pow(10.0, -6 + 4 * U(rng)), p.rate = 200 * std::pow(50.0, U(rng));
  p.c.resize(static_cast<std::size_t>(degree) + 1);
  for (auto& x : p.c) x = p.scale * (2 * U(rng) - 1);
  double tt = 0;
  for (int k = 0; k < 200; ++k) {
    p.t.push_back(tt);
    const double u = tt * p.rate / 50;
    double y = 0;
    for (auto j = p.c.size(); j-- > 0;) y = y * u + p.c[j];
    p.y.push_back(y);
    tt += (0.5 + U(rng)) / p.rate;
  }
  return p;
}

}  // namespace

// The velocity estimate: a local least-squares cubic is exact for cubic motions on any time grid
// (random coefficients, jittered non-uniform samples), and on a sine its error is far below the
// local straight line's (which is biased by the curvature).
TEST(IdentDataset, LocalCubicDerivativeIsExactForCubicsAndUnbiasedOnSines) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    const PolynomialRecord p = random_polynomial_record(rng, 3);
    const auto &t = p.t, &y = p.y, &c = p.c;
    const double scale = p.scale, rate = p.rate;
    const auto d = local_derivative(t, y, 3);
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double u = t[k] * rate / 50;
      const double exact = (c[1] + 2 * c[2] * u + 3 * c[3] * u * u) * rate / 50;
      EXPECT_NEAR(d[k], exact, 1e-6 * (std::abs(c[1]) + std::abs(c[2]) + std::abs(c[3])) * rate)
          << "trial " << trial << " k " << k;
    }
    // A sine at 12 samples per period.
    std::vector<double> s;
    const double w = 2 * std::numbers::pi * rate / 12;
    for (double ti : t) s.push_back(scale * std::sin(w * ti));
    const auto dc = local_derivative(t, s, 3), dl = local_slope(t, s, 3);
    double ec = 0, el = 0;
    for (std::size_t k = 10; k + 10 < t.size(); ++k) {
      const double exact = scale * w * std::cos(w * t[k]);
      ec += (dc[k] - exact) * (dc[k] - exact), el += (dl[k] - exact) * (dl[k] - exact);
    }
    EXPECT_LT(ec, 0.1 * el) << "trial " << trial;
  }
}

TEST(IdentDataset, LocalQuarticSecondDerivativeIsExactForQuartics) {
  std::mt19937 rng(913);
  for (int trial = 0; trial < 6; ++trial) {
    const PolynomialRecord p = random_polynomial_record(rng, 4);
    const auto &t = p.t, &y = p.y, &c = p.c;
    const double rate = p.rate;
    const auto a = local_second_derivative(t, y, 4);
    const double r = rate / 50;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double u = t[k] * r;
      const double exact = (2 * c[2] + 6 * c[3] * u + 12 * c[4] * u * u) * r * r;
      EXPECT_NEAR(a[k], exact,
                  1e-6 * (std::abs(c[2]) + std::abs(c[3]) + std::abs(c[4])) * 12 * r * r)
          << "trial " << trial << " k " << k;
    }
  }
}

// The acceleration a record's fit uses reads the generator's inertia: the force M a_true of the
// random records (raised-cosine ramps and modulated sines, sampled at 200 Hz-10 kHz, jittered,
// quantised by the encoder) regressed on Dataset::a gives M within 1 %.
TEST(IdentDataset, AccelerationFromPositionsCarriesTheGeneratorsInertia) {
  using namespace gmslab::records;
  int n = 0;
  for (unsigned seed = 8001; seed < 8025; seed += 2) {
    Truth tr = draw_truth(seed);
    tr.effects.push_back({GenEffect::Inertia, 5.0});
    auto [g, gv] = synthesize_pair(tr, seed, 3000);
    const Dataset d = prepare_dataset(g.record);
    const double M = tr.effects[0].param;
    double aa = 0, ay = 0;
    for (std::size_t k = 0; k < d.size(); ++k)
      if (d.use[k]) {
        const double y = g.clean[k] - g.clean_base[k];  // exactly M a_true at the sample
        aa += d.a[k] * d.a[k], ay += d.a[k] * y;
      }
    EXPECT_NEAR(ay / aa / M, 1.0, 0.01) << "seed " << seed << ", rate " << tr.rate << " Hz, step "
                                        << tr.quantum << " m, jitter " << tr.jitter;
    ++n;
  }
  EXPECT_EQ(n, 12);
}

// The smoothest positions the encoder allows (within_encoder_step) lie within half a count of the
// recorded ones, and nearer the true motion than the counts where a local cubic over 7 samples
// resolves the motion: sines of 0.2-50 Hz, 20-20,000 counts of amplitude, 200 Hz-10 kHz sampling,
// rounded to the encoder step q (1 nm-1 um). The counts alone are off by q / sqrt(12) RMS.
TEST(IdentDataset, PositionsWithinTheEncoderStepFollowTheTrueMotionCloserThanTheCounts) {
  std::mt19937 rng(24017);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto logu = [&](double lo, double hi) { return lo * std::pow(hi / lo, U(rng)); };
  int cases = 0, resolved = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const double q = logu(1e-9, 1e-6), amp = logu(20, 2e4) * q, rate = logu(200, 1e4);
    const double f = logu(0.2, 50), phase = 2 * std::numbers::pi * U(rng);
    const double counts_per_sample = 2 * std::numbers::pi * f * amp / rate / q;
    // Below ~0.3 counts per sample the counts hold still for several samples: a staircase no
    // local fit over 7 samples undoes. Not drawn.
    if (counts_per_sample < 0.3 || rate / f < 20) continue;
    ++cases;
    // What the cubic misses of the sine over 7 samples, in counts: amp (2 pi f / rate)^4 / q.
    const double curvature = amp * std::pow(2 * std::numbers::pi * f / rate, 4) / q;
    MeasuredRecord r;
    r.source = "encoder trial " + std::to_string(trial);
    std::vector<double> truth;
    for (int k = 0; k < 3000; ++k) {
      const double t = k / rate, x = amp * std::sin(2 * std::numbers::pi * f * t + phase);
      r.t.push_back(t), truth.push_back(x), r.x.push_back(q * std::round(x / q)),
          r.F.push_back(0.0);
    }
    const Dataset d = prepare_dataset(r);
    const Dataset s = within_encoder_step(d, q, PathRule{});
    double e_counts = 0, e_smooth = 0, n = 0;
    for (std::size_t k = 5; k + 5 < d.size(); ++k) {
      ASSERT_LE(std::abs(s.x[k] - d.x[k]), 0.5 * q + 1e-12 * (std::abs(d.x[k]) + q))
          << r.source << " k " << k;
      e_counts += std::pow(d.x[k] - truth[k], 2), e_smooth += std::pow(s.x[k] - truth[k], 2),
          n += 1;
    }
    const double rc = std::sqrt(e_counts / n), rs = std::sqrt(e_smooth / n);
    EXPECT_NEAR(rc, q / std::sqrt(12.0), 0.1 * q) << r.source;
    // Limit from seed 511: the ratio is at most 0.64 where the curvature is below a tenth of a
    // count. Where it is 0.5-9 counts (seed 24017) the ratio is 0.74-1.9, bounded by the clamp.
    if (curvature < 0.1) {
      ++resolved;
      EXPECT_LT(rs, 0.8 * rc) << r.source << ": " << counts_per_sample << " counts per sample, "
                              << rate / f << " samples per period";
    }
    for (std::size_t k = 1; k < s.size(); ++k)
      ASSERT_NEAR(s.vstep[k], (s.x[k] - s.x[k - 1]) / s.h[k], 1e-9 * std::abs(s.vstep[k]) + 1e-15);
  }
  EXPECT_GE(cases, 15);
  EXPECT_GE(resolved, 10);
}
