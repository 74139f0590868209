// The app's frame logic without drawing: pending requests apply at one point, the speed setting
// advances simulated time by speed * wall time, an overlay model sees the same input, and a
// diverging run stops with its message instead of crashing the window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/io/scenario_io.hpp"
#include "ui/app.hpp"
#include "ui/design/design_view.hpp"
#include "ui/identify/identify_panel.hpp"

using namespace gmslab;

namespace {
Scenario stick_slip() {
  return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
}
}  // namespace

TEST(AppState, EditsWaitForApplyPendingThenTakeEffect) {
  ui::AppState s;
  ui::load_scenario_into(s, stick_slip(), "");
  ModelParams p = s.scenario.friction;
  p.set_scalar("Fs", 2.0);
  s.pending.friction = p;
  EXPECT_DOUBLE_EQ(s.main.sim->one_body()->friction.scalar("Fs"), 1.5);  // not yet
  ui::apply_pending(s);
  EXPECT_DOUBLE_EQ(s.main.sim->one_body()->friction.scalar("Fs"), 2.0);
  EXPECT_DOUBLE_EQ(s.scenario.friction.scalar("Fs"), 2.0);  // what "save" writes
  EXPECT_FALSE(s.pending.friction.has_value());
}

TEST(AppState, InvalidEditIsRejectedWithAMessageAndTheRunKeepsItsParameters) {
  ui::AppState s;
  ui::load_scenario_into(s, stick_slip(), "");
  Plant bad = s.scenario.plant;
  bad.mass = -1.0;
  s.pending.plant = bad;
  ui::apply_pending(s);
  EXPECT_DOUBLE_EQ(s.main.sim->one_body()->plant.mass, 1.0);
  EXPECT_NE(s.status.find("plant.mass"), std::string::npos) << s.status;
}

TEST(AppState, SpeedSetsSimulatedSecondsPerWallSecond) {
  ui::AppState s;
  ui::load_scenario_into(s, stick_slip(), "");
  s.view.speed = 0.5;
  s.frame_dt = 0.1;
  s.pending.run = true;
  ui::apply_pending(s);
  ui::advance(s);
  // 0.5 s/s * 0.1 s = 0.05 s of simulated time = 5000 steps of 1e-5 s.
  EXPECT_NEAR(s.main.sim->time(), 0.05, 1e-12);
  EXPECT_TRUE(s.running);
  s.pending.pause = true;
  ui::apply_pending(s);
  ui::advance(s);
  EXPECT_NEAR(s.main.sim->time(), 0.05, 1e-12);
}

TEST(AppState, OverlayOfTheSameModelReproducesTheMainTraceExactly) {
  ui::AppState s;
  ui::load_scenario_into(s, stick_slip(), "");
  ui::run_until(s, 3.0);
  s.pending.compare = s.scenario.friction;  // joins mid-run: catches up on the same input
  ui::apply_pending(s);
  ASSERT_TRUE(s.overlay.sim);
  s.pending.run = true;
  s.frame_dt = 0.05;
  s.view.speed = 100.0;
  ui::apply_pending(s);
  for (int i = 0; i < 3; ++i) ui::advance(s);
  const Trace& a = s.main.sim->one_body_trace();
  const Trace& b = s.overlay.sim->one_body_trace();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a.friction[k], b.friction[k]) << k;
    ASSERT_EQ(a.x[k], b.x[k]) << k;
  }
  EXPECT_GT(s.main.sim->time(), 7.55);  // past the first slip
}

TEST(AppState, DivergingRunStopsAndReportsWhy) {
  ui::AppState s;
  ui::load_scenario_into(s, stick_slip(), "");
  // Viscous friction sigma2 = 1e7 N s/m on 1 kg: the explicit velocity update multiplies v by
  // (1 - h sigma2 / m) = -99 each step, far outside the stable |.| < 1. The live edit is accepted
  // (the model itself is valid), the run blows up, and the window must stop it with a message
  // rather than crash.
  ModelParams p = s.scenario.friction;
  p.set_scalar("sigma2", 1e7);
  s.pending.friction = p;
  s.pending.run = true;
  s.view.speed = 1.0;
  s.frame_dt = 0.1;
  ui::apply_pending(s);
  for (int i = 0; i < 50 && s.running; ++i) ui::advance(s);
  EXPECT_FALSE(s.running);
  EXPECT_NE(s.error.find("diverged"), std::string::npos) << s.error;
  s.pending.reset = true;  // still usable: reset clears the error
  ui::apply_pending(s);
  EXPECT_TRUE(s.error.empty());
  EXPECT_EQ(s.main.sim->time(), 0.0);
}

TEST(AppState, SessionRestoresScenarioOverlayAndView) {
  ui::AppState a;
  ui::load_scenario_into(a, stick_slip(), "presets/fig4_stick_slip.json");
  a.compare = a.scenario.friction;
  a.compare->set_scalar("Fc", 0.8);
  a.view.speed = 0.25;
  a.view.tab = "Figures";
  const Session sess = ui::make_session(a);
  ui::AppState b;
  ui::restore_session(b, sess);
  EXPECT_EQ(b.scenario, a.scenario);
  ASSERT_TRUE(b.compare.has_value());
  EXPECT_EQ(*b.compare, *a.compare);
  ASSERT_TRUE(b.overlay.sim);
  EXPECT_EQ(b.view, a.view);
  EXPECT_EQ(b.scenario_path, "presets/fig4_stick_slip.json");
}

// The Design tab's settings (desired roots, K, references, compensation) are saved in the session
// and come back; the view's own defaults agree with the session's.
TEST(AppState, SessionRestoresTheDesignSettings) {
  EXPECT_EQ(ui::design_settings(ui::DesignViewState{}), DesignSettings{});
  ui::AppState a;
  ui::load_scenario_into(a, stick_slip(), "");
  EXPECT_EQ(ui::make_session(a).design, DesignSettings{});  // design tab never opened
  auto& d = a.design;
  d.settings.zeta = 0.35;
  d.settings.wn = 140.0;
  d.settings.regime = "presliding";
  d.settings.use_K = true;
  d.settings.K = 2.5e4;
  d.settings.reference = DesignReference::Ramp;
  d.settings.slope = 0.02;
  d.settings.compensation = "coulomb";
  d.settings.mismatch_force = 0.8;
  d.settings.sample_time = 5e-4;
  d.settings.other_regime = true;
  const Session sess = session_from_json(to_json(ui::make_session(a)), "mem");
  EXPECT_EQ(sess.design.zeta, 0.35);
  EXPECT_EQ(sess.design.reference, DesignReference::Ramp);
  ui::AppState b;
  ui::restore_session(b, sess);
  const auto& e = b.design;
  EXPECT_EQ(ui::design_settings(e), ui::design_settings(d));
  EXPECT_EQ(e.in.root.wn, 140.0);
  EXPECT_EQ(e.in.regime, control::Regime::Presliding);
  EXPECT_EQ(e.in.compensation, control::Compensation::Coulomb);
  EXPECT_TRUE(e.dirty);
}

// The Identify tab's fields are saved in the session and come back; the panel's defaults agree
// with the session's.
TEST(AppState, SessionRestoresTheIdentifyFields) {
  ui::AppState a;
  ui::load_scenario_into(a, stick_slip(), "");
  EXPECT_EQ(ui::make_session(a).identify, IdentifySettings{});  // identify tab never opened
  ui::IdentifyInputs in;
  in.data = "/measurements/axis 2/run.csv";
  in.validate = "/measurements/axis 2/check.csv";
  in.mask = "0:0.5";
  in.mask_edges = "";
  in.model = "maxwell_slip";
  in.elements = 9;
  in.compare = true;
  ui::apply_identify_settings(a.identify, in);
  const Session sess = session_from_json(to_json(ui::make_session(a)), "mem");
  EXPECT_EQ(sess.identify.data, in.data);
  EXPECT_EQ(sess.identify.model, "maxwell_slip");
  ui::AppState b;
  ui::restore_session(b, sess);
  EXPECT_EQ(ui::identify_settings(b.identify), sess.identify);
  EXPECT_EQ(ui::identify_settings(b.identify).elements, 9);
  EXPECT_TRUE(ui::identify_settings(b.identify).compare);
}

// A slip threshold changed in the Simulation panel after a run applies to the whole recorded trace
// (the phases are computed from the trace, not appended as it grows).
TEST(AppState, ChangedSlipThresholdReclassifiesTheRecordedTrace) {
  ui::AppState s;
  ui::load_scenario_into(s, stick_slip(), "");
  s.view.slip_velocity = 1e-4;
  ui::run_until(s, 12.0);
  const auto before = s.main.phases(s.view.slip_velocity);
  std::vector<std::uint8_t> low(before.begin(), before.end());
  s.view.slip_velocity = 10.0;  // no |v| in this run comes near: only all-elements-slipping counts
  const auto after = s.main.phases(s.view.slip_velocity);
  const Trace& tr = s.main.sim->one_body_trace();
  ASSERT_EQ(after.size(), tr.size());
  std::size_t changed = 0;
  for (std::size_t k = 0; k < tr.size(); ++k) {
    bool all = true;
    for (std::size_t i = 0; i < tr.n_elements; ++i) all = all && tr.element_slip[k * tr.n_elements + i];
    ASSERT_EQ(after[k], all ? 1 : 0) << k;
    changed += after[k] != low[k];
  }
  EXPECT_GT(changed, 100u);
}

// The window's (and render's) live runs keep a bounded trace: main and overlay stay within
// history_bytes each, and the recorded extremes of the friction force survive.
TEST(AppState, LiveRunsKeepABoundedHistoryWithTheExtremes) {
  ui::AppState s;
  s.history_bytes = 2000 * trace_sample_bytes(4);
  ui::load_scenario_into(s, stick_slip(), "");
  s.pending.compare = s.scenario.friction;
  ui::apply_pending(s);
  ASSERT_TRUE(s.overlay.sim);
  ui::run_until(s, -1.0);
  const Trace full = simulate(s.scenario);
  for (const ui::LiveRun* r : {&s.main, &s.overlay}) {
    const Trace& tr = r->sim->one_body_trace();
    EXPECT_LE(tr.size(), 2000u);
    EXPECT_GT(r->sim->trace_bucket_steps(), 0u);
    EXPECT_EQ(*std::max_element(tr.friction.begin(), tr.friction.end()),
              *std::max_element(full.friction.begin(), full.friction.end()));
    EXPECT_EQ(*std::min_element(tr.v.begin(), tr.v.end()), *std::min_element(full.v.begin(), full.v.end()));
    EXPECT_EQ(tr.t.back(), full.t.back());
  }
}
