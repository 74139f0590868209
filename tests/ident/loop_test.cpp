// The residual loop on records with one undeclared effect, generated with gmslab's own GMS model
// (tests/ident/synthetic.hpp): the loop must name the effect and bring the validation error to the
// noise level; on a record without an effect it must add nothing.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/ident/loop.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

struct Run {
  IdentReport report;
  double noise;
};

Run run_loop(std::optional<Effect> effect) {
  synth::SynthOptions so;
  so.effect = effect;
  so.seed = 11;
  const auto train = prepare_dataset(synth::synthesize(so));
  so.seed = 23;
  const auto val = prepare_dataset(synth::synthesize(so));
  LoopOptions o;
  o.base.starts = 2;
  FitSpec spec;
  auto rep = identify(train, val, spec, o);
  std::printf("effect %s: val %.4f -> %.4f, train %.4f -> %.4f, added:",
              effect ? std::string(effect_name(*effect)).c_str() : "none",
              rep.rms_before_validation, rep.rms_after_validation, rep.rms_before_train,
              rep.rms_after_train);
  for (auto e : rep.effects_added) std::printf(" %s", std::string(effect_name(e)).c_str());
  std::printf("\n");
  for (const auto& rd : rep.rounds) {
    for (const auto& k : rd.candidates)
      std::printf("   cand %-20s expl %.4f screen val %.4f\n", std::string(effect_name(k.effect)).c_str(), k.explained, k.screen_rms_validation);
    for (const auto& a : rd.attempts)
      std::printf("   try  %-20s train %.4f val %.4f kept %d\n", std::string(effect_name(a.effect)).c_str(), a.rms_train, a.rms_validation, a.kept);
  }
  return {std::move(rep), so.noise};
}

}  // namespace

class IdentLoopEffect : public ::testing::TestWithParam<Effect> {};

TEST_P(IdentLoopEffect, LoopNamesTheUndeclaredEffectAndReachesTheNoiseLevel) {
  const Effect e = GetParam();
  const auto run = run_loop(e);
  ASSERT_FALSE(run.report.effects_added.empty());
  EXPECT_EQ(run.report.effects_added.front(), e);
  EXPECT_LT(run.report.rms_after_validation, 1.35 * run.noise);
}

INSTANTIATE_TEST_SUITE_P(Catalog, IdentLoopEffect,
                         ::testing::Values(Effect::Inertia, Effect::Offset,
                                           Effect::DirectionAsymmetry, Effect::PositionPeriodic,
                                           Effect::PositionDependent, Effect::TimeDrift,
                                           Effect::VelocityExtra, Effect::DwellStiction,
                                           Effect::NormalLoad),
                         [](const auto& info) { return std::string(effect_name(info.param)); });

TEST(IdentLoop, RecordWithoutEffectGetsNoEffectAdded) {
  const auto run = run_loop(std::nullopt);
  EXPECT_TRUE(run.report.effects_added.empty());
  EXPECT_LT(run.report.rms_after_validation, 1.35 * run.noise);
}
