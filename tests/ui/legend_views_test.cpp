// Legends in the app's views hide no data (issues 15, 27): the views of the golden renders
// (Simulation and Design on presets/fig4_stick_slip.json, the Figures tab, the Plant tab on
// presets/two_mass_drive.json), drawn by ui::draw_frame as the window and the headless renderer
// draw them, at 1280x720 and 1600x1000 with the renderer's font size: no legend meets a drawn
// segment of its plot (ui::TakeLegendStats counts them). Built only with the app (ImGui). The
// Identify tab's report figure after the EMPS example is checked the same way, also at the docs'
// render size 1400x875.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <algorithm>
#include <filesystem>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "core/io/assembly_io.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/ui/app_frame.hpp"
#include "ui/identify/identify_panel.hpp"
#include "ui/plant/plant_view.hpp"
#include "ui/style.hpp"

using namespace gmslab;

namespace {

struct ViewCase {
  const char* tab;
  const char* preset;
  bool plant;  // an assembled preset, in the Plant tab
};

// Draws the tab as `gmslab render PRESET --view TAB --size WxH` does and returns its legends.
std::vector<ui::LegendStat> legends_of(const ViewCase& c, int w, int h) {
  ImGuiContext* ctx = ImGui::CreateContext();
  ui::ScopedPlotContext plots;
  ui::setup_style(std::clamp(17.0f * static_cast<float>(h) / 1000.0f, 12.0f, 26.0f));  // as Offscreen
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(w), static_cast<float>(h));
  io.IniFilename = nullptr;
  unsigned char* px = nullptr;
  int tw = 0, th = 0;
  io.Fonts->GetTexDataAsRGBA32(&px, &tw, &th);
  ui::AppState s;
  const std::string src = GMSLAB_SOURCE_DIR;
  ui::load_scenario_into(s, load_scenario(src + "/presets/fig4_stick_slip.json"), "");
  if (c.plant) {
    ui::load_plant(s.plant, load_assembly_scenario(src + "/" + c.preset), c.preset);
    ui::plant_run_until(s.plant, 1e9);
  } else {
    ui::load_scenario_into(s, load_scenario(src + "/" + c.preset), "");
  }
  s.view.tab = c.tab;
  if (!c.plant) ui::run_until(s, 1e9);
  for (int i = 0; i < 3; ++i) uitest::draw_app_frame(s, uitest::kNoMouse, false);
  ui::TakeLegendStats();
  uitest::draw_app_frame(s, uitest::kNoMouse, false);
  std::vector<ui::LegendStat> out = ui::TakeLegendStats();
  ImGui::DestroyContext(ctx);
  return out;
}

}  // namespace

TEST(LegendViews, LegendsHideNoDataOfTheirPlot) {
  const std::string src = GMSLAB_SOURCE_DIR;
  if (!std::filesystem::exists(src + "/presets/two_mass_drive.json")) GTEST_SKIP() << "presets not found";
  const ViewCase cases[] = {{"Simulation", "presets/fig4_stick_slip.json", false},
                            {"Design", "presets/fig4_stick_slip.json", false},
                            {"Figures", "presets/fig4_stick_slip.json", false},
                            {"Plant", "presets/two_mass_drive.json", true}};
  int boxed = 0;
  for (const auto& c : cases)
    for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{1600, 1000}}) {
      for (const ui::LegendStat& st : legends_of(c, w, h)) {
        SCOPED_TRACE(std::string(c.tab) + " " + std::to_string(w) + "x" + std::to_string(h) + ": '" + st.plot + "'");
        ++boxed;
        EXPECT_EQ(st.hidden, 0u) << st.hidden << " of " << st.segments << " segments under the legend";
      }
    }
  EXPECT_GT(boxed, 0) << "no legend was drawn: the test checks nothing";
}

// The Identify tab's report figure after the EMPS example (panels A-D), as the other views.
TEST(LegendViews, IdentifyReportLegendsHideNoDataOfTheirPlot) {
  const auto example = ui::emps_example();
  if (!example) GTEST_SKIP() << "EMPS data not found (../shared/data/emps or $GMSLAB_SHARED/data/emps)";
  ui::IdentifyState done;
  ui::identify_start(done, *example);
  while (ui::identify_busy(done)) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_NE(ui::identify_report(done), nullptr) << ui::identify_error(done);
  int boxed = 0;
  for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{1400, 875}, std::pair{1600, 1000}}) {
    ImGuiContext* ctx = ImGui::CreateContext();
    {
      ui::ScopedPlotContext plots;
      ui::setup_style(std::clamp(17.0f * static_cast<float>(h) / 1000.0f, 12.0f, 26.0f));
      ImGuiIO& io = ImGui::GetIO();
      io.DisplaySize = ImVec2(static_cast<float>(w), static_cast<float>(h));
      io.IniFilename = nullptr;
      unsigned char* px = nullptr;
      int tw = 0, th = 0;
      io.Fonts->GetTexDataAsRGBA32(&px, &tw, &th);
      ui::AppState s;
      ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"), "");
      ui::apply_identify_settings(s.identify, ui::identify_settings(done));
      s.identify.result = std::make_unique<ui::IdentifyResult>(*done.result);
      s.view.tab = "Identify";
      for (int i = 0; i < 3; ++i) uitest::draw_app_frame(s, uitest::kNoMouse, false);
      ui::TakeLegendStats();
      uitest::draw_app_frame(s, uitest::kNoMouse, false);
      for (const ui::LegendStat& st : ui::TakeLegendStats()) {
        SCOPED_TRACE("Identify " + std::to_string(w) + "x" + std::to_string(h) + ": '" + st.plot + "'");
        std::printf("Identify %dx%d '%s': %zu of %zu segments under the legend\n", w, h, st.plot.c_str(), st.hidden,
                    st.segments);
        ++boxed;
        EXPECT_EQ(st.hidden, 0u) << st.hidden << " of " << st.segments << " segments under the legend";
      }
    }
    ImGui::DestroyContext(ctx);
  }
  EXPECT_GE(boxed, 12) << "the report's four panels at three sizes";
}
#endif
