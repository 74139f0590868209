// Fixed-seed study of the residual loop on records of an independent GMS implementation
// (tests/ident/random_records.hpp) at several scales: with no effect nothing is added; one effect
// at 2-10x the noise is named first; two effects are both named. Expectations come from the
// generating truth. GMSLAB_STUDY_RECORDS=N runs N records per case (and all twelve effects) instead
// of the CI's few, prints the rates and asserts the targets; the CI run asserts what holds
// per record (see each test).
#include <gtest/gtest.h>

#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <string>

#include "core/ident/loop.hpp"
#include "tests/ident/study_cases.hpp"

using namespace gmslab;
using namespace gmslab::ident;
using records::GenEffect;

namespace {

int records_per_case(int ci) {
  const char* s = std::getenv("GMSLAB_STUDY_RECORDS");
  return s ? std::max(1, std::atoi(s)) : ci;
}

struct Outcome {
  std::vector<std::string> added;
  IdentReport rep;
  records::Truth truth;
  double floor = 0;  // what noise and quantisation alone leave (generator's floor_rms) [N]
};

// max_floor > 0: records whose floor exceeds max_floor x the noise are not identified (returns
// floor only): an effect of a few times the noise would lie below what the data can resolve.
Outcome run(unsigned seed, const std::vector<records::EffectSpec>& effects, double max_floor = 0) {
  records::Truth tr = records::draw_truth(seed, study::ranges(seed));
  tr.effects = effects;
  auto [tg, vg] = records::synthesize_pair(tr, seed, 3000);
  if (max_floor > 0 && records::floor_rms(tr, vg) > max_floor * tr.noise) {
    Outcome skip;
    skip.truth = tr;
    skip.floor = records::floor_rms(tr, vg);
    return skip;
  }
  const Dataset train = prepare_dataset(tg.record), val = prepare_dataset(vg.record);
  const LoopOptions o = study::study_options();
  FitSpec spec;
  Outcome out;
  out.rep = identify(train, val, spec, o);
  for (auto e : out.rep.effects_added) out.added.emplace_back(effect_name(e));
  out.truth = tr;
  out.floor = records::floor_rms(tr, vg);
  std::printf("seed %u Fs %.3g N, x %.2g-%.2g um, noise %.2g N, %.0f Hz:", seed, tr.Fs, tr.x_min() * 1e6,
              tr.x_max() * 1e6, tr.noise, tr.rate);
  for (const auto& e : effects) std::printf(" [%s %.1fx]", records::gen_effect_name(e.kind), e.size);
  std::printf(" -> added:");
  for (const auto& a : out.added) std::printf(" %s", a.c_str());
  std::printf(" (val %.3g -> %.3g N = %.2fx noise, floor %.2fx, est. noise %.2fx)\n", out.rep.rms_before_validation,
              out.rep.rms_after_validation, out.rep.rms_after_validation / tr.noise, records::floor_rms(tr, vg) / tr.noise,
              out.rep.noise.sigma / tr.noise);
  std::printf("    est. floor %.2fx (quantum %.3g nm, truth %.3g nm)\n", out.rep.noise.floor() / tr.noise, out.rep.noise.quantum * 1e9, tr.quantum * 1e9);
  for (const auto& rd : out.rep.rounds)
    for (const auto& a : rd.attempts)
      std::printf("    try %-20s val %.4g size %.3g: %s\n", std::string(effect_name(a.effect)).c_str(), a.rms_validation,
                  a.size / tr.noise, a.verdict.c_str());
  for (const auto* rows : {&out.rep.ablation.rows, &out.rep.ablation.dropped})
    for (const auto& a : *rows)
      std::printf("    ablation %-17s without %.4g N (all %.4g N), z %.3g, size %.3g: %s\n",
                  std::string(effect_name(a.effect)).c_str(), a.rms_validation_without,
                  out.rep.ablation.rms_validation_all, a.test.z, a.contribution / tr.noise, a.verdict.c_str());
  return out;
}

}  // namespace

TEST(IdentStudy, NoEffectAddsNothing) {
  const int n = records_per_case(3);
  int clean = 0;
  for (int i = 0; i < n; ++i) clean += run(1000u + static_cast<unsigned>(i), {}).added.empty();
  std::printf("no effect: nothing added in %d / %d\n", clean, n);
  EXPECT_GE(clean, (n * 95 + 99) / 100 - (n < 20 ? 0 : 0));
}

// Records whose floor (noise, quantisation and sampling: the generator's floor_rms) is more than
// twice the noise would put an effect of 2-10x the noise at or below the floor: the next seed is
// drawn instead (decided from the generated record, before any fit).
TEST(IdentStudy, OneEffectIsNamedFirst) {
  const GenEffect kinds[] = {GenEffect::Offset, GenEffect::DirectionAsymmetry, GenEffect::TimeShift,
                             GenEffect::Inertia, GenEffect::PositionRipple, GenEffect::SensorFilter,
                             GenEffect::Backlash, GenEffect::PositionDependent, GenEffect::TimeDrift,
                             GenEffect::VelocityExtra, GenEffect::DwellStiction, GenEffect::NormalLoad};
  const std::size_t ci_kinds = 5;  // CI: the first five (offset vs asymmetry, lag vs inertia, ripple)
  const bool all = std::getenv("GMSLAB_STUDY_RECORDS") != nullptr;
  const int n = records_per_case(1);
  int right = 0, total = 0, skipped = 0;
  unsigned seed = 2000u;
  for (int i = 0; i < n; ++i)
    for (std::size_t j = 0; j < (all ? std::size(kinds) : ci_kinds); ++j) {
      Outcome o;
      for (;; ++skipped) {
        const double size = study::one_effect_size(seed);  // 2..10 x noise
        o = run(seed++, {{kinds[j], size}}, 2.0);
        if (o.floor <= 2.0 * o.truth.noise) break;
      }
      ++total;
      const std::string truth = records::gen_effect_name(kinds[j]);
      const bool first = !o.added.empty() && o.added.front() == truth;
      right += first;
      if (!all) {
        // CI (5 records): offset, level asymmetry and ripple are named first (asymmetry not as
        // offset); inertia is not named as a channel effect.
        // (The target, named first in >= 90 %, is measured with GMSLAB_STUDY_RECORDS.)
        // A lag and a first-order filter agree to first order: a lag may come first as
        // sensor_filter, but time_shift must be named and inertia must not come first.
        if (kinds[j] == GenEffect::Inertia) {
          EXPECT_TRUE(o.added.empty() || (o.added.front() != "time_shift" && o.added.front() != "sensor_filter"))
              << o.added.front() << " seed " << seed - 1;
        } else if (kinds[j] == GenEffect::TimeShift) {
          ASSERT_FALSE(o.added.empty()) << "seed " << seed - 1;
          EXPECT_NE(o.added.front(), "inertia") << "seed " << seed - 1;
          EXPECT_NE(std::find(o.added.begin(), o.added.end(), truth), o.added.end()) << "seed " << seed - 1;
        } else {
          EXPECT_TRUE(first) << truth << " seed " << seed - 1;
        }
      }
    }
  std::printf("one effect: named first in %d / %d (%d records with the floor above 2x the noise drawn again)\n",
              right, total, skipped);
  EXPECT_EQ(total, n * static_cast<int>(all ? std::size(kinds) : ci_kinds));
  if (all) {
    EXPECT_GE(right * 10, total * 9);
  }
}

TEST(IdentStudy, TwoEffectsAreBothNamed) {
  const std::pair<GenEffect, GenEffect> pairs[] = {{GenEffect::Offset, GenEffect::TimeShift},
                                                   {GenEffect::Inertia, GenEffect::DirectionAsymmetry},
                                                   {GenEffect::PositionRipple, GenEffect::Offset}};
  const int n = records_per_case(1);
  int both = 0, total = 0;
  unsigned seed = 3000u;
  for (int i = 0; i < n; ++i)
    for (std::size_t j = 0; j < std::size(pairs); ++j) {
      Outcome o;
      do o = run(seed++, {{pairs[j].first, 6.0}, {pairs[j].second, 6.0}}, 2.0);
      while (o.floor > 2.0 * o.truth.noise);
      ++total;
      auto has = [&](GenEffect e) {
        return std::find(o.added.begin(), o.added.end(), records::gen_effect_name(e)) != o.added.end();
      };
      both += has(pairs[j].first) && has(pairs[j].second);
      // At least one of the two, and nothing outside them named first.
      ASSERT_FALSE(o.added.empty()) << "seed " << seed - 1;
      EXPECT_TRUE(o.added.front() == records::gen_effect_name(pairs[j].first) ||
                  o.added.front() == records::gen_effect_name(pairs[j].second))
          << o.added.front() << " seed " << seed - 1;
    }
  std::printf("two effects: both named in %d / %d\n", both, total);
  EXPECT_EQ(total, n * static_cast<int>(std::size(pairs)));
  if (std::getenv("GMSLAB_STUDY_RECORDS")) {
    EXPECT_GE(both * 10, total * 9);
  } else {
    // The CI subset: both named on every record (the second effect is in the data at its size
    // since the generator sizes it against the record with the first).
    EXPECT_EQ(both, total);
  }
}
