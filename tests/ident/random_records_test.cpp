// The study's record generator (tests/ident/random_records.hpp) gives every requested effect the
// size it was asked for, also the second of two, and makes a force along the stroke one function
// of position in the training and the validation record. The identification study's rates mean
// nothing unless the effects it scores are in the data at their sizes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/ident/random_records.hpp"

using namespace gmslab;
using records::GenEffect;

namespace {
// RMS of `with` less `without` over the record [N].
double rms_between(const records::Generated& with, const records::Generated& without) {
  double s = 0;
  for (std::size_t k = 0; k < with.clean.size(); ++k) s += std::pow(with.clean[k] - without.clean[k], 2);
  return std::sqrt(s / static_cast<double>(with.clean.size()));
}
}  // namespace

// Two effects over random truths (fixed seeds), sizes 2-10 x the noise drawn independently, in
// either order: each effect's own contribution on the training motion (the record with both less
// the record with only the other; for the first, the record with it alone less none) is its size
// times the noise within 2 %. Before the fix the second was measured against the effect-free
// record, and one smaller than the first was bisected down to nothing.
TEST(RandomRecords, EachOfTwoEffectsHasTheSizeItWasAskedFor) {
  const GenEffect kinds[] = {GenEffect::Inertia,          GenEffect::Offset,       GenEffect::DirectionAsymmetry,
                             GenEffect::PositionDependent, GenEffect::TimeDrift,   GenEffect::VelocityExtra,
                             GenEffect::NormalLoad};
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (unsigned i = 0; i < 10; ++i) {
    const unsigned seed = 500 + i;
    records::Truth tr = records::draw_truth(seed);
    const GenEffect a = kinds[i % 7], b = kinds[(i + 3) % 7];
    const double sa = 2.0 + 8.0 * U(rng), sb = 2.0 + 8.0 * U(rng);
    tr.effects = {{a, sa}, {b, sb}};
    records::synthesize_pair(tr, seed, 1500);
    ASSERT_EQ(tr.effects.size(), 2u);
    records::Truth none = tr, only_a = tr;
    none.effects.clear();
    only_a.effects = {tr.effects[0]};
    const auto g_none = records::synthesize(none, seed, 1500);
    const auto g_a = records::synthesize(only_a, seed, 1500);
    const auto g_ab = records::synthesize(tr, seed, 1500);
    EXPECT_NEAR(rms_between(g_a, g_none) / tr.noise, sa, 0.02 * sa)
        << records::gen_effect_name(a) << " seed " << seed;
    EXPECT_NEAR(rms_between(g_ab, g_a) / tr.noise, sb, 0.02 * sb)
        << records::gen_effect_name(b) << " after " << records::gen_effect_name(a) << " seed " << seed;
  }
}

// A friction that depends on where the slide is: the same function of x in both records of a
// truth. The validation record's force less its effect-free force, divided by the friction's
// hysteretic part, is a (1 + a xi) factor whose xi is linear in x with the training record's span.
TEST(RandomRecords, PositionDependenceIsOneFunctionOfPositionInBothRecords) {
  for (unsigned seed = 600; seed < 606; ++seed) {
    records::Truth tr = records::draw_truth(seed);
    tr.sigma2 = 0.0;  // the friction is then all hysteretic: fr = the effect-free force
    tr.effects = {{GenEffect::PositionDependent, 5.0}};
    auto [train, val] = records::synthesize_pair(tr, seed, 1500);
    ASSERT_LT(tr.x_span_lo, tr.x_span_hi);
    double lo = 1e9, hi = -1e9;
    for (double x : train.record.x) lo = std::min(lo, x), hi = std::max(hi, x);
    // The span is the training record's (to the encoder step).
    EXPECT_NEAR(tr.x_span_lo, lo, 2 * tr.quantum) << "seed " << seed;
    EXPECT_NEAR(tr.x_span_hi, hi, 2 * tr.quantum) << "seed " << seed;
    // Both records' effect share, regressed on (x - mid) / half times the effect-free friction,
    // give the same coefficient a (the drawn parameter).
    records::Truth none = tr;
    none.effects.clear();
    const unsigned seeds[2] = {seed, seed + 100003u};
    double coef[2] = {0, 0};
    for (int r = 0; r < 2; ++r) {
      const auto with = records::synthesize(tr, seeds[r], 1500), without = records::synthesize(none, seeds[r], 1500);
      const auto& rec = r == 0 ? train.record : val.record;
      double sxy = 0, sxx = 0;
      const double mid = 0.5 * (tr.x_span_lo + tr.x_span_hi), half = 0.5 * (tr.x_span_hi - tr.x_span_lo);
      for (std::size_t k = 0; k < with.clean.size(); ++k) {
        const double col = without.clean[k] * (rec.x[k] - mid) / half;
        sxy += col * (with.clean[k] - without.clean[k]), sxx += col * col;
      }
      coef[r] = sxy / sxx;
    }
    EXPECT_NEAR(coef[0], tr.effects[0].param, 0.1 * tr.effects[0].param) << "seed " << seed;
    EXPECT_NEAR(coef[1], coef[0], 0.1 * std::abs(coef[0])) << "seed " << seed;
  }
}
