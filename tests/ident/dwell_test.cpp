// Dwell stiction's rests and its model (core/ident/effects.hpp, fit.cpp):
// - motion_starts finds the motion after every rest of at least dwell_min, with its length, on
//   random motions read by an encoder of 10-100 nm (strokes with raised-cosine speed, rests of
//   0.06-2 s and of 5-15 ms, direct reversals, slow oscillations below the rest speed), and
//   nothing else (the rest lengths, from the first standstill sample, within 20 % and 35 ms;
//   measured: within 11.1 ms);
// - the dwell model (the break-away level raised after each rest, fading with travel) follows a
//   generated dwell effect: on random-truth records with dwell stiction of 5x the noise
//   (random_records.hpp), the dwell columns at the generator's decay length and rise, with the
//   base shape fitted on the same truth's record without the effect, lower the validation RMS
//   where the base model leaves 1.5x the generator's floor or more: by 5 % on all but one of
//   them, by a quarter on half of them at least (limits set on seeds 30001-30008 and
//   52001-52008; measured with the rise per step of the path: by 5 % on 13 of 13 of those and on
//   5 of 5 of seeds 41001-41008, by a quarter on 12 of 13 and 5 of 5). The model is not the
//   generator's: the generator raises the level after rests of any length.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>

#include "core/ident/effects.hpp"
#include "core/ident/fit.hpp"
#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

struct Segment {
  double dur;  // [s]
  double v;    // stroke: peak speed [m/s] (signed); oscillation: amplitude [m]; rest: 0
  enum { Rest, Stroke, Oscillation } kind;
};

double speed_at(const Segment& s, double tl) {
  const double u = tl / s.dur;
  if (s.kind == Segment::Stroke) return s.v * 0.5 * (1 - std::cos(2 * std::numbers::pi * u));
  if (s.kind == Segment::Oscillation) {
    const double w = 2 * std::numbers::pi * 2 / s.dur;  // two periods
    return s.v * w * std::cos(w * tl);
  }
  return 0.0;
}

}  // namespace

TEST(DwellStarts, EveryRestOfTheMotionAndNothingElse) {
  int long_rests = 0, found = 0, extra = 0;
  double worst = 0.0;  // the largest error of a rest length [s]
  for (unsigned seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(7000 + seed);
    std::uniform_real_distribution<double> U(0, 1);
    const double rate = 500 * std::pow(10.0, U(rng));   // 0.5-5 kHz
    const double vpk = 0.005 * std::pow(20.0, U(rng));  // 5-100 mm/s
    const double quantum = 1e-8 * std::pow(10.0, U(rng));
    std::vector<Segment> plan;
    std::vector<double> expected;                            // the long rests, in order
    plan.push_back({0.2 + 0.3 * U(rng), 0, Segment::Rest});  // the record begins at rest
    expected.push_back(plan.back().dur);
    double dir = 1;
    for (int i = 0; i < 10; ++i) {
      plan.push_back({0.15 + 0.3 * U(rng), dir * vpk * (0.5 + U(rng)), Segment::Stroke});
      const double r = U(rng);
      if (r < 0.4) {
        plan.push_back({0.06 * std::pow(2.0 / 0.06, U(rng)), 0, Segment::Rest});
        expected.push_back(plan.back().dur);
      } else if (r < 0.6) {
        plan.push_back({0.005 + 0.01 * U(rng), 0, Segment::Rest});  // too short to count
      } else if (r < 0.8) {
        // A slow oscillation below the rest speed (peaks of 1.2 % of the strokes' speed, hundreds
        // of encoder counts) between two rests too short to count: it passes through zero only
        // for instants.
        plan.push_back({0.01, 0, Segment::Rest});
        plan.push_back({0.6, 0.012 * vpk * 0.6 / (2 * std::numbers::pi * 2), Segment::Oscillation});
        plan.push_back({0.01, 0, Segment::Rest});
      }  // else a direct reversal
      dir = -dir;
    }
    MeasuredRecord rec;
    double t = 0, x = 0, ts = 0;
    for (const auto& s : plan) {
      for (; t < ts + s.dur; t += 1.0 / rate) {
        rec.t.push_back(t);
        rec.x.push_back(quantum * std::round(x / quantum));
        rec.F.push_back(0.0);
        // The exact position: the speed integrated in 16 parts of the step.
        for (int j = 0; j < 16; ++j)
          x += speed_at(s, t - ts + (j + 0.5) / (16 * rate)) / (16 * rate);
      }
      ts += s.dur;
    }
    const Dataset d = prepare_dataset(rec);
    const EffectContext c = make_context(d);
    const auto starts = motion_starts(d, c);
    std::size_t next = 0;
    long_rests += static_cast<int>(expected.size());
    for (const auto& s : starts) {
      // The nearest expected rest ending at most 30 ms around the start.
      double t_end = 0;
      std::size_t i = 0;
      for (double acc = 0; i < plan.size(); ++i) {
        acc += plan[i].dur;
        if (plan[i].kind == Segment::Rest && plan[i].dur >= 0.06 &&
            std::abs(acc - d.t[s.k]) < 0.03) {
          t_end = acc;
          break;
        }
      }
      if (t_end == 0) {
        ++extra;
        ADD_FAILURE() << "seed " << seed << ": a start at t = " << d.t[s.k] << " s after "
                      << s.dwell << " s that no rest of the motion ends";
        continue;
      }
      ++found, ++next;
      // The rest's length, from its first standstill sample to the start (the raised-cosine
      // ramps' tails below 2 % of the speed scale are motion): within 20 % of the rest and 35 ms.
      worst = std::max(worst, std::abs(s.dwell - plan[i].dur));
      EXPECT_NEAR(s.dwell, plan[i].dur, 0.2 * plan[i].dur + 0.035)
          << "seed " << seed << " start at " << d.t[s.k] << " rate " << rate << " peak " << vpk;
    }
  }
  std::printf("%d long rests, %d starts found after them, %d others; rest lengths within %.1f ms\n",
              long_rests, found, extra, 1e3 * worst);
  EXPECT_EQ(extra, 0);
  EXPECT_GE(found * 10, long_rests * 9);
}

TEST(DwellModel, LowersTheValidationErrorAtTheGeneratorsValues) {
  using namespace gmslab::records;
  int visible = 0, lowered = 0, by_a_quarter = 0;
  const unsigned s0 = std::getenv("DWELL_SEED0")
                          ? static_cast<unsigned>(std::atoi(std::getenv("DWELL_SEED0")))
                          : 41001;
  for (unsigned seed = s0; seed < s0 + 8; ++seed) {
    Truth tr = draw_truth(seed);
    tr.effects.push_back({GenEffect::DwellStiction, 5.0});
    auto [gt, gv] = synthesize_pair(tr, seed, 3000);
    const double a = tr.effects.front().param;
    Truth without = tr;
    without.effects.clear();
    auto [g0, g0v] = synthesize_pair(without, seed, 3000);
    const Dataset train = prepare_dataset(gt.record), val = prepare_dataset(gv.record),
                  train0 = prepare_dataset(g0.record);
    const double floor = floor_rms(tr, gv);
    EffectContext c = make_context(train);
    LoopOptions lo;
    const FitSpec base{"gms", tr.elements(), {}};
    const FitResult b0 = fit_model(base, train0, c, lo.base);
    const FitResult b = refit_linear(base, train, c, b0.u);
    c.dwell_s0 = 2 * tr.x_max();
    c.dwell_rise = a / tr.Fc;
    const FitResult f =
        refit_linear({"gms", tr.elements(), {Effect::DwellStiction}}, train, c, b0.u);
    const double before = rms_on(b, val, c) / floor, after = rms_on(f, val, c) / floor;
    std::printf(
        "seed %u: %zu rests, rise %.3g Fc per unit ln; validation / floor: base %.2f, "
        "with the dwell model %.2f\n",
        seed, motion_starts(train, c).size(), a / tr.Fc, before, after);
    if (before < 1.5) continue;  // the effect is hardly visible at this size
    ++visible;
    lowered += after < 0.95 * before;
    by_a_quarter += after <= 0.75 * before;
  }
  std::printf("base above 1.5x the floor on %d records: lowered by 5 %% on %d, by 25 %% on %d\n",
              visible, lowered, by_a_quarter);
  EXPECT_GE(visible, 4);
  EXPECT_GE(lowered, visible - 1);
  EXPECT_GE(2 * by_a_quarter, visible);
}

// The generator's records of a truth with dwell stiction rest after every stroke, for 0.05 s up
// to min(4 s, 1.5 x the record's planned length / strokes) (at least 0.1 s), log-uniformly; the
// motion is otherwise that of the same seed without them.
TEST(DwellRecords, EveryStrokeIsFollowedByARestOfTheDrawnRange) {
  using namespace gmslab::records;
  int rests = 0, long_ones = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    Truth tr = draw_truth(seed);
    const std::size_t samples = 3000;
    const Motion plain = draw_motion(tr, seed, samples);
    tr.dwell_rests = true;
    const Motion m = draw_motion(tr, seed, samples);
    int strokes = 0;
    for (const auto& s : m.seg) strokes += s.kind == records::Segment::Stroke;
    const double hi = std::clamp(1.5 * static_cast<double>(samples) / tr.rate / strokes, 0.1, 4.0);
    std::vector<records::Segment> moving, moving_plain;
    for (std::size_t i = 0; i < m.seg.size(); ++i) {
      if (m.seg[i].kind != records::Segment::Rest) moving.push_back(m.seg[i]);
      if (m.seg[i].kind != records::Segment::Stroke) continue;
      ASSERT_LT(i + 1, m.seg.size()) << "seed " << seed;
      ASSERT_EQ(m.seg[i + 1].kind, records::Segment::Rest) << "seed " << seed << " stroke " << i;
      EXPECT_GE(m.seg[i + 1].dur, 0.05) << "seed " << seed;
      EXPECT_LE(m.seg[i + 1].dur, hi) << "seed " << seed;
      ++rests;
      long_ones += m.seg[i + 1].dur > std::sqrt(0.05 * hi);
    }
    for (const auto& s : plain.seg)
      if (s.kind != records::Segment::Rest) moving_plain.push_back(s);
    ASSERT_EQ(moving.size(), moving_plain.size()) << "seed " << seed;
    for (std::size_t i = 0; i < moving.size(); ++i) {
      EXPECT_EQ(moving[i].dur, moving_plain[i].dur) << "seed " << seed;
      EXPECT_EQ(moving[i].amp, moving_plain[i].amp) << "seed " << seed;
    }
  }
  // Log-uniform: about half above the geometric middle of the range.
  EXPECT_GT(long_ones * 4, rests);
  EXPECT_LT(long_ones * 4, 3 * rests);
}

// Dwell stiction raises the friction after a rest: a response coefficient that is not positive
// is refused, whatever the level term and the base; a positive one passes.
TEST(DwellModel, ARiseThatIsNotPositiveIsNotADwellStiction) {
  std::mt19937_64 rng(4417);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int refused = 0, passed = 0;
  for (int i = 0; i < 200; ++i) {
    const double fc = std::pow(10.0, -2.0 + 5.0 * U(rng));
    const double resp = std::pow(10.0, -4.0 + 5.0 * U(rng)) * (U(rng) < 0.3 ? -1.0 : 1.0);
    const double level = fc * std::pow(10.0, -4.0 + 4.0 * U(rng)) * (U(rng) < 0.5 ? -1.0 : 1.0);
    const std::vector<LinearTerm> terms = {{"base", "Fc", "N", fc},
                                           {"dwell_stiction", "dwell_response", "N", resp},
                                           {"dwell_stiction", "dwell_level", "N", level}};
    const std::string why = unphysical(terms, Effect::DwellStiction);
    EXPECT_EQ(why.empty(), resp > 0) << "response " << resp << ", level " << level;
    (why.empty() ? passed : refused) += 1;
    EXPECT_TRUE(unphysical(terms, Effect::Offset).empty());
  }
  EXPECT_GE(refused, 30);
  EXPECT_GE(passed, 100);
  std::vector<LinearTerm> zero = {{"dwell_stiction", "dwell_response", "N", 0.0}};
  EXPECT_FALSE(unphysical(zero, Effect::DwellStiction).empty());
}
