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

struct LoopRun {
  IdentReport report;
  double noise;
  Dataset train, val;
  LoopOptions options;
};

// Training (seed 11) and validation (seed 23) records with the effect, and the loop over them.
LoopRun run_loop(std::optional<Effect> effect) {
  synth::SynthOptions so;
  so.effect = effect;
  so.seed = 11;
  auto train = prepare_dataset(synth::synthesize(so));
  so.seed = 23;
  auto val = prepare_dataset(synth::synthesize(so));
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
  return {std::move(rep), so.noise, std::move(train), std::move(val), o};
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

// The model comparison fits every model with the effects the loop found. On a GMS record (presliding
// hysteresis, Stribeck) with an offset: GMS reaches the noise level on validation; a static
// Coulomb law, which has neither presliding nor Stribeck, cannot; and the comparison's GMS fit, which
// starts from the loop's final model, is never worse than it on the training record.
TEST(IdentLoop, ModelComparisonRanksGmsAboveStaticFrictionOnAGmsRecord) {
  const LoopRun run = run_loop(Effect::Offset);
  const IdentReport& rep = run.report;
  ASSERT_EQ(rep.effects_added, std::vector<Effect>{Effect::Offset});
  FitOptions fo = run.options.base;
  fo.max_seconds = 120;
  const auto cmp = compare_models(rep, run.train, run.val, parse_model_list("gms,coulomb"), fo);
  ASSERT_EQ(cmp.size(), 2u);
  std::printf("loop final train %.4f val %.4f; gms %.4f %.4f (%d evals); coulomb %.4f %.4f\n",
              rep.rms_after_train, rep.rms_after_validation, cmp[0].rms_train, cmp[0].rms_validation,
              cmp[0].evaluations, cmp[1].rms_train, cmp[1].rms_validation);
  const ModelComparison& gms = cmp[0];
  const ModelComparison& coulomb = cmp[1];
  EXPECT_EQ(gms.model, "gms");
  EXPECT_EQ(gms.elements, 4u);
  EXPECT_EQ(coulomb.elements, 0u);
  EXPECT_FALSE(gms.time_limited);
  EXPECT_LE(gms.rms_train, rep.rms_after_train * (1 + 1e-12));
  EXPECT_LT(gms.rms_validation, 1.35 * run.noise);
  EXPECT_GT(coulomb.rms_validation, 1.5 * gms.rms_validation);
  EXPECT_LT(gms.shape_parameters, 20u);
  EXPECT_GT(gms.shape_parameters, coulomb.shape_parameters);
  // In the report JSON, with the time limit flag.
  IdentReport with = rep;
  with.comparison = cmp;
  const auto j = to_json(with);
  ASSERT_EQ(j.at("model_comparison").size(), 2u);
  EXPECT_EQ(j["model_comparison"][1]["model"], "coulomb");
  EXPECT_DOUBLE_EQ(j["model_comparison"][0]["rms"]["validation"].get<double>(), gms.rms_validation);
}

TEST(IdentLoop, ModelListAcceptsAllAndNamesAnUnknownTag) {
  EXPECT_EQ(parse_model_list("all").size(), model_registry().size());
  EXPECT_EQ(parse_model_list("lugre,gms"), (std::vector<std::string>{"lugre", "gms"}));
  EXPECT_TRUE(parse_model_list("").empty());
  try {
    parse_model_list("gms,friction9");
    ADD_FAILURE() << "unknown tag accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("friction9"), std::string::npos) << e.what();
  }
}
