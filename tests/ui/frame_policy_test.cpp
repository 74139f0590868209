// The window's one frame policy (ui/frame_policy.hpp) and what the app feeds it: poll while a run,
// an identification or an animation is active and for kSettleFrames frames after every input
// event; wait otherwise (with a timeout for the status report or a blinking caret). Also the
// status report line and the launcher's checks (gmslab --open PRESET --tab TAB --run).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/assembly_io.hpp"
#include "ui/app.hpp"
#include "ui/frame_policy.hpp"

using namespace gmslab;
using ui::FrameWait;
using ui::FrameWaitKind;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
const FrameWait kPoll{FrameWaitKind::Poll, 0.0};
const FrameWait kWait{FrameWaitKind::Wait, 0.0};
const std::string kPresets = std::string(GMSLAB_SOURCE_DIR) + "/presets/";
}  // namespace

TEST(FramePolicy, IdleWaitsForInput) {
  EXPECT_EQ(ui::frame_wait({}, ui::kSettleFrames), kWait);
  EXPECT_EQ(ui::frame_wait({}, 1000), kWait);
  EXPECT_EQ(ui::frame_wait({}, 1000, kInf), kWait);
}

TEST(FramePolicy, EveryActivityPollsAtDisplayRateWithNoInput) {
  for (int which = 0; which < 4; ++which) {
    ui::FrameActivity a;
    (which == 0 ? a.sim_running : which == 1 ? a.plant_running : which == 2 ? a.identifying : a.animating) = true;
    EXPECT_EQ(ui::frame_wait(a, 1000), kPoll) << which;
    EXPECT_EQ(ui::frame_wait(a, 1000, 0.7), kPoll) << which;
  }
}

TEST(FramePolicy, AfterAnInputEventAtLeastTwoMoreFramesAreDrawn) {
  // frames_since_input counts frames drawn since the one that handled the event.
  int polled = 0;
  for (int f = 0; f < 10 && ui::frame_wait({}, f) == kPoll; ++f) ++polled;
  EXPECT_EQ(polled, ui::kSettleFrames);
  EXPECT_GE(polled, 2);
  EXPECT_EQ(ui::frame_wait({}, ui::kSettleFrames), kWait);
}

TEST(FramePolicy, IdleWaitEndsAtTheDeadlineOrTheCaretBlink) {
  EXPECT_EQ(ui::frame_wait({}, 50, 0.6), (FrameWait{FrameWaitKind::Timeout, 0.6}));
  EXPECT_EQ(ui::frame_wait({}, 50, 0.0), kPoll);   // due now
  EXPECT_EQ(ui::frame_wait({}, 50, -0.3), kPoll);  // overdue
  ui::FrameActivity typing;
  typing.text_input = true;
  EXPECT_EQ(ui::frame_wait(typing, 50), (FrameWait{FrameWaitKind::Timeout, ui::kCaretBlinkS}));
  EXPECT_EQ(ui::frame_wait(typing, 50, 0.05), (FrameWait{FrameWaitKind::Timeout, 0.05}));
  EXPECT_EQ(ui::frame_wait(typing, 0), kPoll);  // settling comes first
}

TEST(FramePolicy, AppActivityFollowsTheRunsAndTheShownTab) {
  ui::AppState s;
  s.select_tab = 0;
  EXPECT_FALSE(ui::frame_activity(s).any_active());
  ui::load_scenario_into(s, load_scenario(kPresets + "fig4_stick_slip.json"), "");
  s.view.tab = "Simulation";
  EXPECT_FALSE(ui::frame_activity(s).any_active());
  s.running = true;  // the Simulation run advances under every tab
  EXPECT_TRUE(ui::frame_activity(s).sim_running);
  s.view.tab = "Identify";
  EXPECT_TRUE(ui::frame_activity(s).sim_running);
  s.running = false;

  ui::load_plant(s.plant, load_assembly_scenario(kPresets + "two_mass_drive.json"), "");
  s.plant.running = true;
  EXPECT_FALSE(ui::frame_activity(s).plant_running);  // it advances only while its tab is shown
  s.view.tab = "Plant";
  EXPECT_TRUE(ui::frame_activity(s).plant_running);
  s.plant.running = false;
  EXPECT_FALSE(ui::frame_activity(s).any_active());

  s.select_tab = 1;  // a tab being selected takes a frame
  EXPECT_TRUE(ui::frame_activity(s).animating);
  s.select_tab = 0;
  s.view.tab = "Design";
  s.design.dirty = true;  // the design is computed in the next frame
  EXPECT_TRUE(ui::frame_activity(s).animating);
}

TEST(UiStatus, OneJsonLineWithFramesTabAndTheActiveRun) {
  ui::AppState s;
  ui::load_scenario_into(s, load_scenario(kPresets + "fig4_stick_slip.json"), "");
  ui::load_plant(s.plant, load_assembly_scenario(kPresets + "two_mass_drive.json"), "");
  s.view.tab = "Plant";
  s.plant.running = true;
  ui::plant_run_until(s.plant, 0.25);
  EXPECT_EQ(ui::ui_status_json(s, 42), R"({"frames": 42, "tab": "plant", "running": true, "run_time_s": 0.25})");
  s.view.tab = "Simulation";
  ui::run_until(s, 0.5);
  EXPECT_EQ(ui::ui_status_json(s, 43), R"({"frames": 43, "tab": "simulation", "running": false, "run_time_s": 0.5})");
}

TEST(Launch, ResolvesShippedNamesAndDefaultsTheTabByPresetKind) {
  const ui::LaunchRequest plant = ui::check_launch({"two_mass_drive", "", false});
  EXPECT_EQ(plant.preset, ui::presets_dir() + "/two_mass_drive.json");
  EXPECT_EQ(plant.tab, "Plant");
  const ui::LaunchRequest sim = ui::check_launch({kPresets + "fig4_stick_slip.json", "", true});
  EXPECT_EQ(sim.tab, "Simulation");
  EXPECT_EQ(ui::check_launch({"fig4_stick_slip.json", "PLANT", true}).tab, "Plant");  // any case
}

TEST(Launch, BadRequestsNameWhatIsWrongAndTheFix) {
  auto message = [](const ui::LaunchRequest& r) {
    try {
      ui::check_launch(r);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string missing = message({"no_such_preset", "", false});
  EXPECT_NE(missing.find("'no_such_preset': no such file"), std::string::npos) << missing;
  EXPECT_NE(missing.find("two_mass_drive"), std::string::npos) << missing;  // lists the shipped ones
  const std::string tab = message({"two_mass_drive", "plot", false});
  EXPECT_NE(tab.find("--tab 'plot': no such tab; use simulation"), std::string::npos) << tab;
  const std::string assembled = message({"two_mass_drive", "simulation", false});
  EXPECT_NE(assembled.find("--tab plant"), std::string::npos) << assembled;
  const std::string run = message({"fig4_stick_slip", "design", true});
  EXPECT_NE(run.find("drop --run"), std::string::npos) << run;
}

TEST(Launch, OpensThePresetOnItsTabAndStartsItsRun) {
  ui::AppState s;
  ui::apply_launch(s, ui::check_launch({"two_mass_drive", "plant", true}));
  EXPECT_EQ(s.view.tab, "Plant");
  ASSERT_TRUE(s.plant.sim);
  EXPECT_TRUE(s.plant.running);
  EXPECT_FALSE(s.running);

  ui::AppState t;
  ui::apply_launch(t, ui::check_launch({"fig4_stick_slip", "", true}));
  EXPECT_EQ(t.view.tab, "Simulation");
  ASSERT_TRUE(t.main.sim);
  EXPECT_EQ(t.scenario.name, load_scenario(kPresets + "fig4_stick_slip.json").name);
  EXPECT_TRUE(t.running);
  EXPECT_TRUE(ui::frame_activity(t).sim_running);
}
