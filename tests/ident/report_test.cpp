// Report, scenario export, masks, hold-out, cancellation and figure JSON of the identification.
#include <gtest/gtest.h>


#include <chrono>
#include <cmath>

#include <atomic>
#include <filesystem>

#include "core/error.hpp"
#include "core/ident/element_fit.hpp"
#include "core/ident/figure_json.hpp"
#include "core/ident/loop.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

TEST(IdentReport, HoldOutRunWritesRequiredKeysAndALoadableScenario) {
  synth::SynthOptions so;
  so.effect = Effect::Offset;
  so.moves = 8;
  const auto [train, val] = split_holdout(prepare_dataset(synth::synthesize(so)));
  // Complementary masks: every used sample is in exactly one part.
  std::size_t both = 0;
  for (std::size_t k = 0; k < train.size(); ++k) both += train.use[k] && val.use[k];
  EXPECT_EQ(both, 0u);
  EXPECT_NEAR(static_cast<double>(val.used()) / (train.used() + val.used()), 0.25, 0.03);
  LoopOptions o;
  o.candidates = {Effect::Inertia, Effect::Offset};
  const auto rep = identify(train, val, FitSpec{}, o);
  const auto j = to_json(rep);
  for (const char* k : {"base_model", "rms_before", "rms_after", "effects_added", "rounds"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["base_model"], "gms");
  EXPECT_TRUE(j["rms_after"].contains("train") && j["rms_after"].contains("validation"));
  ASSERT_EQ(j["effects_added"].size(), 1u);
  EXPECT_EQ(j["effects_added"][0], "offset");
  EXPECT_NEAR(j["rounds"][0]["parameters"]["F0"]["value"].get<double>(), 1.5, 0.05);  // generated 1.5 N
  EXPECT_LT(rep.rms_after_validation, 1.35 * so.noise);
  // The identified model as a scenario: saved, loaded back strictly, and simulated.
  const auto path = (std::filesystem::temp_directory_path() / "gmslab_ident_scenario.json").string();
  const Scenario sc = identified_scenario(rep, train);
  save_scenario(sc, path);
  const Scenario back = load_scenario(path);
  EXPECT_EQ(back.friction, rep.final_fit().friction);
  EXPECT_GT(simulate(back).size(), 100u);
  std::filesystem::remove(path);
  // The report figure survives its JSON form.
  const Figure f = report_figure(rep, train, val);
  const Figure g = figure_from_json(figure_to_json(f), "mem");
  ASSERT_EQ(g.panels.size(), f.panels.size());
  EXPECT_EQ(g.panels[1].series.size(), f.panels[1].series.size());
  EXPECT_EQ(g.panels[0].series[0].y, f.panels[0].series[0].y);
}

namespace {
// A short synthetic record (four moves) for the tests of the fit's controls.
Dataset four_moves() {
  synth::SynthOptions so;
  so.moves = 4;
  return prepare_dataset(synth::synthesize(so));
}
}  // namespace

TEST(IdentReport, CancelFlagStopsTheFit) {
  const auto d = four_moves();
  const auto c = make_context(d);
  std::atomic<bool> cancel{true};
  FitOptions o;
  o.cancel = &cancel;
  int calls = 0;
  o.progress = [&](const FitProgress&) { ++calls; };
  EXPECT_THROW(fit_model(FitSpec{}, d, c, o), Cancelled);
}

// FitOptions::abandon (a fit whose result is no longer needed) stops the element grid fit and the
// local search as the cancel flag does, at the first check after it is set: the fit throws
// Cancelled after fewer evaluations than it makes otherwise.
TEST(IdentReport, AbandonFlagStopsTheFit) {
  const auto d = four_moves();
  const auto c = make_context(d);
  FitOptions full;
  int full_evals = 0;
  full.progress = [&](const FitProgress& p) { full_evals = std::max(full_evals, p.evaluations); };
  const FitResult f = fit_model(FitSpec{}, d, c, full);
  ASSERT_FALSE(f.u.empty());
  for (int after : {0, 50}) {
    std::atomic<bool> abandon{false};
    FitOptions o;
    o.abandon = &abandon;
    int seen = 0;
    o.progress = [&](const FitProgress& p) {
      seen = std::max(seen, p.evaluations);
      if (p.evaluations >= after) abandon = true;
    };
    if (after == 0) abandon = true;
    EXPECT_THROW(fit_model(FitSpec{}, d, c, o), Cancelled) << "abandoned after " << after;
    EXPECT_LT(seen, full_evals) << "abandoned after " << after;
  }
}

// The progress the panel's bar shows: the evaluations so far against the fit's budget (for the
// GMS grid fit: design points, grid starts, polish and restarts; element_fit_budget), never beyond
// it, and a time limit that stops the fit and says so.
TEST(IdentReport, ProgressReportsTheBudgetAndATimeLimitStopsTheFit) {
  const auto d = four_moves();
  const auto c = make_context(d);
  FitOptions o;
  o.starts = 2;
  o.max_evaluations = 150;
  std::vector<FitProgress> seen;
  o.progress = [&](const FitProgress& p) { seen.push_back(p); };
  const FitResult r = fit_model(FitSpec{}, d, c, o);
  ASSERT_FALSE(seen.empty());
  const int budget = element_fit_budget(FitSpec{}, c, o);
  EXPECT_GT(budget, 3 * 150);  // at least the polish and its restarts
  for (const auto& p : seen) {
    EXPECT_EQ(p.budget, budget);
    EXPECT_LE(p.evaluations, budget + 1);  // + the first guess's evaluation
  }
  EXPECT_EQ(seen.back().evaluations, r.evaluations);
  EXPECT_FALSE(r.time_limited);
  FitOptions quick = o;
  quick.max_evaluations = 100000;
  quick.rel_tol = 0;  // would run to the evaluation limit
  quick.max_seconds = 0.2;
  const auto t0 = std::chrono::steady_clock::now();
  const FitResult q = fit_model(FitSpec{}, d, c, quick);
  EXPECT_TRUE(q.time_limited);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_TRUE(std::isfinite(q.rms_train));
}

TEST(IdentReport, MasksParseAndBadMasksNameTheItem) {
  const auto w = parse_masks("1:2, 3.5:4");
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w[1].t0, 3.5);
  try {
    parse_masks("1:2,4:3");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'4:3'"), std::string::npos);
  }
  EXPECT_THROW(parse_masks("abc"), InputError);
  const std::vector<double> t = {0, 1, 2, 3, 4}, code = {0, 0, 5, 5, 0};
  const auto e = edge_windows(t, code, 0.1, 0.2);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[0].t0, 1.9);
  EXPECT_DOUBLE_EQ(e[1].t1, 4.2);
}

TEST(IdentReport, FigureJsonRejectsMismatchedSeries) {
  nlohmann::json j = {{"id", "x"}, {"title", "t"}, {"panels", {{{"x_label", "t [s]"}, {"y_label", "F [N]"},
                       {"series", {{{"x", {1, 2}}, {"y", {1}}}}}}}}};
  EXPECT_THROW(figure_from_json(j, "f.json"), InputError);
}
