// The credit bound (LoopOptions::credit_bound, loop_stages.cpp: no_effect_creditable): the rounds
// are not run when the base fit (after round 1's control refit) is within sqrt(2) x the floor.
// That is a bound for the credit test's size clause only (an effect cannot lower the validation
// MSE by more than what lies above the floor); its block-test clause (z >= 3) is not bounded by
// size. Checked here on random-truth records (tests/ident/random_records.hpp) with one effect of
// 1.5-50x the noise (log-uniform; backlash, dwell stiction, time drift, inertia and others) and
// effect-free ones, each identified with and without the bound:
//   - where the bound skipped the rounds, the full rounds name nothing either;
//   - where it did not, the answer is the same to the last bit (the bound's control refit is
//     round 1's own: the same fit of the same inputs).
// Every case is counted; the test fails if the bound never fired (it would test nothing).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/ident/loop.hpp"
#include "tests/ident/study_cases.hpp"

using namespace gmslab;
using namespace gmslab::ident;
using records::GenEffect;

namespace {

std::string named(const IdentReport& r) {
  std::string s;
  for (Effect e : r.effects_added) s += (s.empty() ? "" : " ") + std::string(effect_name(e));
  return s.empty() ? "nothing" : s;
}

struct Counts {
  int records = 0, skipped = 0, skipped_with_effect = 0, same = 0;
};

// One record: identified with the bound and without it; the checks above.
void check_record(unsigned seed, const std::vector<records::EffectSpec>& effects, Counts& n) {
  study::Case k{seed, effects};
  const study::Record r = study::make_record(k);
  const Dataset train = prepare_dataset(r.train.record), val = prepare_dataset(r.validation.record);
  const FitSpec spec;
  LoopOptions with = study::study_options(), without = with;
  without.credit_bound = false;
  const IdentReport a = identify(train, val, spec, with);
  const IdentReport b = identify(train, val, spec, without);
  ++n.records;
  std::printf("seed %u", seed);
  for (const auto& e : effects)
    std::printf(" [%s %.1fx noise]", records::gen_effect_name(e.kind), e.size);
  std::printf(
      ": bound %s; named %s / without the bound %s (validation %.4g / %.4g N, floor %.3g N)\n",
      a.rounds_skipped.empty() ? "not met, rounds run" : "met, rounds skipped", named(a).c_str(),
      named(b).c_str(), a.rms_after_validation, b.rms_after_validation, a.noise.floor());
  if (!a.rounds_skipped.empty()) {
    ++n.skipped;
    n.skipped_with_effect += !effects.empty();
    EXPECT_TRUE(a.effects_added.empty()) << "seed " << seed;
    EXPECT_TRUE(b.effects_added.empty())
        << "seed " << seed << ": the rounds would have credited " << named(b);
  } else {
    EXPECT_EQ(a.effects_added, b.effects_added) << "seed " << seed;
    EXPECT_EQ(a.rms_after_validation, b.rms_after_validation) << "seed " << seed;
    EXPECT_EQ(a.rounds.size(), b.rounds.size()) << "seed " << seed;
    n.same +=
        a.effects_added == b.effects_added && a.rms_after_validation == b.rms_after_validation;
  }
}

}  // namespace

TEST(IdentCreditBound, SkipsOnlyWhereTheRoundsWouldCreditNothing) {
  const GenEffect kinds[] = {GenEffect::Backlash,       GenEffect::DwellStiction,
                             GenEffect::TimeDrift,      GenEffect::Inertia,
                             GenEffect::Offset,         GenEffect::SensorFilter,
                             GenEffect::PositionRipple, GenEffect::VelocityExtra};
  std::mt19937 rng(8800);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Counts n;
  unsigned seed = 8800;
  for (int i = 0; i < 3; ++i) check_record(seed++, {}, n);
  for (GenEffect e : kinds) {
    const double size = 1.5 * std::pow(50.0 / 1.5, U(rng));  // log-uniform 1.5..50 x the noise
    check_record(seed++, {{e, size}}, n);
  }
  std::printf(
      "credit bound: %d records, rounds skipped on %d (%d of them with an effect), the same answer "
      "with and without the bound on %d of the %d others\n",
      n.records, n.skipped, n.skipped_with_effect, n.same, n.records - n.skipped);
  EXPECT_EQ(n.records, 11);
  EXPECT_GE(n.skipped, 1) << "the bound never fired: the test would check nothing";
}
