// The residual loop on records with one undeclared effect, generated with gmslab's own GMS model
// (tests/ident/synthetic.hpp): the loop must name the effect and bring the validation error to the
// noise level; on a record without an effect it must add nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/ident/evidence.hpp"
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

// The report figure's panel D shows the residual's position spectrum after each stage (the stages
// panels B and C show). On a record with an undeclared ripple the base fit's residual spectrum
// peaks at the ripple's spatial frequency; in panel D's final stage that peak is gone.
TEST(IdentLoop, ReportFigureSpectrumShowsTheRippleAndItsRemoval) {
  const LoopRun run = run_loop(Effect::PositionPeriodic);
  const IdentReport& rep = run.report;
  ASSERT_EQ(rep.effects_added.front(), Effect::PositionPeriodic);
  const Figure f = report_figure(rep, run.train, run.val);
  ASSERT_EQ(f.panels.size(), 4u);
  const Panel& d = f.panels[3];
  EXPECT_EQ(d.letter, "D");
  EXPECT_EQ(d.series.size(), f.panels[1].series.size());
  const double f_ripple = 1.0 / 2.5;  // synthesize()'s ripple: 2.5 mm wavelength [1/mm]
  // The base model's residual, straight from the evidence code.
  auto res = predict(rep.stages.front(), run.train, rep.context);
  for (std::size_t k = 0; k < res.size(); ++k) res[k] = run.train.F[k] - res[k];
  const Spectrum base = position_spectrum(run.train, rep.context, res);
  EXPECT_NEAR(1e-3 / base.peak_wavelength, f_ripple, 0.05 * f_ripple);
  EXPECT_GT(base.peak_to_median, 4.0);
  // Panel D's last series is the final model's residual spectrum, against 1 / wavelength in 1/mm,
  // and its range covers the ripple.
  const Series& last = d.series.back();
  auto fres = predict(rep.final_fit(), run.train, rep.context);
  for (std::size_t k = 0; k < fres.size(); ++k) fres[k] = run.train.F[k] - fres[k];
  const Spectrum fin = position_spectrum(run.train, rep.context, fres);
  ASSERT_EQ(last.x.size(), fin.wavelength.size());
  EXPECT_DOUBLE_EQ(last.x.front(), 1e-3 / fin.wavelength.back());
  EXPECT_DOUBLE_EQ(last.y.front(), fin.amplitude.back());
  EXPECT_LT(last.x.front(), 0.5 * f_ripple);
  EXPECT_GT(last.x.back(), 2.0 * f_ripple);
  // Nothing left near the ripple.
  double near_ripple = 0;
  for (std::size_t k = 0; k < last.x.size(); ++k)
    if (std::abs(last.x[k] - f_ripple) < 0.1 * f_ripple) near_ripple = std::max(near_ripple, last.y[k]);
  EXPECT_LT(near_ripple, 0.3 * base.peak_amplitude);
}
