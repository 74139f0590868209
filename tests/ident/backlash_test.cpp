// Backlash as the contact's motion behind a dead band (core/ident/effects.hpp, through_dead_band),
// checked against formulas on random motions, and against the independent generator of
// tests/ident/random_records.hpp (its contact clamped within b / 2 of the motor at every
// sub-step): the model fitted with the backlash column at the generator's lost motion reaches the
// generator's floor, and the residual loop names backlash first on records that have one and
// nothing on the same truths without it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/ident/ablation.hpp"
#include "core/ident/fit.hpp"
#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"
#include "tests/ident/study_cases.hpp"

namespace gmslab::ident {
namespace {

// A record of a sine or a triangle through x0 with amplitude A, n samples at `rate` (jittered
// steps when `jitter`), quantised to `quantum`.
MeasuredRecord motion_record(std::mt19937_64& rng, double A, std::size_t n, double rate,
                             bool jitter, double quantum) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const bool triangle = U(rng) < 0.5;
  const double f = (0.5 + 3.0 * U(rng)) * rate / static_cast<double>(n);  // 0.5-3.5 periods
  const double x0 = (U(rng) - 0.5) * 10 * A, phase = 2 * std::numbers::pi * U(rng);
  MeasuredRecord r;
  r.source = "dead band test";
  double t = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double p = 2 * std::numbers::pi * f * t + phase;
    const double s = triangle ? 2 / std::numbers::pi * std::asin(std::sin(p)) : std::sin(p);
    const double x = x0 + A * s;
    r.t.push_back(t);
    r.x.push_back(quantum > 0 ? quantum * std::round(x / quantum) : x);
    r.F.push_back(0.0);
    t += (jitter ? 0.7 + 0.6 * U(rng) : 1.0) / rate;
  }
  return r;
}

// Over random motions at scales from micrometres to centimetres and plays from 1 % to half the
// amplitude, on every step of the path: the contact stays within b / 2 of the encoder, never moves
// against the encoder's motion, and moves only when dragged (at the band's edge after the step),
// which together define the play. Where every stroke of the path but the last is longer than b,
// it loses b / 2 of the first stroke (it starts in the middle of the band) and b of every later
// one: sum |v_c h| = sum over strokes s_i of max(0, s_i - b) (s_1 - b / 2 for the first).
TEST(DeadBand, ContactStaysInTheBandAndLosesTheLostMotionAtEveryReversal) {
  std::mt19937_64 rng(4101);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int cases = 0, travel_checked = 0;
  for (int i = 0; i < 60; ++i) {
    const double A = std::pow(10.0, -6.0 + 4.0 * U(rng));
    const double b = A * std::pow(10.0, -2.0 + 1.7 * U(rng));
    const std::size_t n = 300 + static_cast<std::size_t>(2000 * U(rng));
    const double rate = std::pow(10.0, 2.0 + 2.0 * U(rng));
    const bool jitter = U(rng) < 0.5;
    const double quantum = U(rng) < 0.5 ? A * 1e-4 : 0.0;
    const Dataset d = prepare_dataset(motion_record(rng, A, n, rate, jitter, quantum));
    const Dataset c = through_dead_band(d, b);
    ASSERT_EQ(c.size(), d.size());
    const double tol = 1e-9 * (A + b);
    double enc = 0, con = 0, worst_gap = 0, against = 0, stroke = 0, shortest = 1e300, kept = 0;
    int reversals = 0, lazy = 0;
    double dir = 0, xm = d.x[0], xc = d.x[0];
    for (std::size_t k = 1; k < d.size(); ++k) {
      xm = d.x[k - 1];
      auto part = [&](double v, double vc, double h) {
        xm += v * h, xc += vc * h;
        enc += std::abs(v * h), con += std::abs(vc * h);
        if (v != 0.0) {
          const double s = v > 0 ? 1.0 : -1.0;
          if (dir != 0.0 && s != dir) {
            shortest = std::min(shortest, stroke);
            kept += std::max(0.0, stroke - (reversals == 0 ? 0.5 : 1.0) * b);
            ++reversals, stroke = 0;
          }
          dir = s;
          stroke += std::abs(v * h);
        }
        if (vc * v < 0) against += std::abs(vc * h);
        worst_gap = std::max(worst_gap, std::abs(xm - xc) - 0.5 * b);
        if (vc != 0.0 && std::abs(xm - xc) < 0.5 * b - tol) ++lazy;  // moved though not dragged
      };
      if (!d.sub.empty() && d.sub[k + 1] > d.sub[k]) {
        for (std::uint32_t j = d.sub[k]; j < d.sub[k + 1]; ++j) part(d.sv[j], c.sv[j], d.sh[j]);
      } else {
        part(d.vstep[k], c.vstep[k], d.h[k]);
      }
      EXPECT_NEAR(c.x[k], xc, tol) << "case " << i << " sample " << k;
    }
    EXPECT_LE(worst_gap, tol) << "case " << i;
    EXPECT_LE(against, tol) << "case " << i;
    EXPECT_EQ(lazy, 0) << "case " << i;
    if (reversals > 0 && shortest > b) {
      kept += std::max(0.0, stroke - b);  // the last stroke
      EXPECT_NEAR(con, kept, 1e-9 * (enc + b))
          << "case " << i << ": " << reversals << " reversals, A " << A << ", b " << b;
      ++travel_checked;
    }
    ++cases;
  }
  EXPECT_EQ(cases, 60);
  EXPECT_GE(travel_checked, 30);  // most motions have no stroke shorter than the play
}

// A play passes the whole friction force through it: a backlash level far from the Coulomb level
// is refused, as a mass that is not positive is; levels near it and other effects pass.
TEST(IdentBacklash, LevelFarFromTheCoulombLevelIsNotAPlay) {
  std::mt19937_64 rng(4102);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int cases = 0;
  for (int i = 0; i < 200; ++i) {
    const double fc = std::pow(10.0, -2.0 + 5.0 * U(rng));
    const double ratio = std::pow(10.0, -6.0 + 7.0 * U(rng)) * (U(rng) < 0.2 ? -1.0 : 1.0);
    const std::vector<LinearTerm> terms = {{"base", "Fc", "N", fc},
                                           {"base", "sigma2", "N s/m", 3.0},
                                           {"backlash", "backlash_level", "N", ratio * fc}};
    const bool play = ratio >= 0.5 && ratio <= 2.0;
    EXPECT_EQ(unphysical(terms, Effect::Backlash).empty(), play) << "level " << ratio << " Fc";
    EXPECT_TRUE(unphysical(terms, Effect::Offset).empty());
    const std::vector<LinearTerm> mass = {{"base", "Fc", "N", fc}, {"inertia", "M", "kg", ratio}};
    EXPECT_EQ(unphysical(mass, Effect::Inertia).empty(), ratio > 0) << "M " << ratio;
    ++cases;
  }
  EXPECT_EQ(cases, 200);
}

// The study's records with one generated backlash (1.5-50x the noise, the study's draw).
study::Record backlash_record(unsigned seed) {
  study::Record r;
  r.truth = records::draw_truth(seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  r.truth.effects.push_back({records::GenEffect::Backlash, 1.5 * std::pow(50.0 / 1.5, U(rng))});
  auto [tg, vg] = records::synthesize_pair(r.truth, seed, 3000);
  r.train = std::move(tg), r.validation = std::move(vg);
  r.floor = records::floor_rms(r.truth, r.validation);
  return r;
}

// GMS with the backlash column at the generator's own lost motion, fitted from the base fit's
// shape, on records of 6 seeds: validation within 1.5x the generator's floor on at least 5, and
// on every record at least 1.5x better than the base fit without it where the base fit is above
// 2x the floor. Measured on seeds 30001-30008 (the per-kind study's): within 1.5x on 6 of 8
// (1.01, 1.00, 1.08, 0.81, 1.42, 1.19; 1.96 and 4.19 on 30004 and 30006), the base fit 1.9-18x.
TEST(IdentBacklash, ColumnAtTheGeneratorsLostMotionReachesItsFloor) {
  int within = 0, cases = 0;
  for (unsigned seed = 33001; seed < 33007; ++seed) {
    const study::Record r = backlash_record(seed);
    const Dataset train = prepare_dataset(r.train.record),
                  val = prepare_dataset(r.validation.record);
    EffectContext c = make_context(train);
    FitSpec spec;
    spec.elements = r.truth.elements();
    FitOptions fo;
    const FitResult base = fit_model(spec, train, c, fo);
    spec.effects = {Effect::Backlash};
    c.backlash = r.truth.effects[0].param;
    const FitResult fit = fit_model(spec, train, c, fo, &base.u);
    const double base_ratio = rms_on(base, val, c) / r.floor, ratio = rms_on(fit, val, c) / r.floor;
    std::printf("seed %u: b %.3g um, base %.2fx, with backlash %.2fx the floor\n", seed,
                1e6 * c.backlash, base_ratio, ratio);
    within += ratio <= 1.5;
    if (base_ratio > 2.0) {
      EXPECT_LT(ratio, base_ratio / 1.5) << "seed " << seed;
    }
    ++cases;
  }
  EXPECT_EQ(cases, 6);
  EXPECT_GE(within, 5);
}

// The residual loop on records with a backlash and on the same truths without it (seeds 33101-
// 33104): backlash named first on at least 3 of 4, its lost motion within 30 % of the
// generator's where it is; nothing named on at least 3 of the 4 effect-free records. Measured on
// the per-kind study's seeds 30001-30008: named first on 8 of 8, the lost motion within 0.3-15 %.
TEST(IdentBacklash, LoopNamesABacklashAndNothingWithoutIt) {
  int named = 0, clean = 0, b_close = 0;
  for (unsigned seed = 33101; seed < 33105; ++seed) {
    const study::Record r = backlash_record(seed);
    FitSpec spec;
    spec.elements = r.truth.elements();
    const auto rep = identify(prepare_dataset(r.train.record), prepare_dataset(r.validation.record),
                              spec, study::study_options());
    const bool first = !rep.effects_added.empty() && rep.effects_added.front() == Effect::Backlash;
    const double b = r.truth.effects[0].param;
    named += first;
    if (first && std::abs(rep.context.backlash - b) < 0.3 * b) {
      ++b_close;
    }
    std::printf("seed %u: b %.3g um found %.3g um, named %s, %.2fx the floor\n", seed, 1e6 * b,
                1e6 * rep.context.backlash, first ? "backlash" : "other or nothing",
                rep.rms_after_validation / r.floor);

    records::Truth t0 = r.truth;
    t0.effects.clear();
    auto [tg, vg] = records::synthesize_pair(t0, seed, 3000);
    const auto rep0 = identify(prepare_dataset(tg.record), prepare_dataset(vg.record), spec,
                               study::study_options());
    clean += rep0.effects_added.empty();
  }
  EXPECT_GE(named, 3);
  EXPECT_GE(b_close, named - 1);
  EXPECT_GE(clean, 3);
}

}  // namespace
}  // namespace gmslab::ident
