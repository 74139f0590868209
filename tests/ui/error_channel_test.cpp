// One error channel in the window: a failing action in a panel shows in that panel (its error
// field, drawn there) and on the one status line, with its kind; a later success clears both.
// Drives whole frames (an ImGui context without a renderer). Built only with the app (ImGui).
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include "core/io/scenario_io.hpp"
#include "ui/app.hpp"
#include "ui/plot/plot.hpp"
#include "tests/ui/imgui_test_context.hpp"

using namespace gmslab;

namespace {
struct Window {
  ui::AppState s;
  ui::ScopedPlotContext plots;
  explicit Window(const char* tab) {
    uitest::make_headless_imgui(ImVec2(1600, 1000));
    ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"), "");
    s.view.tab = tab;
    frames(2);
  }
  ~Window() { ImGui::DestroyContext(); }
  void frames(int n) {
    for (int i = 0; i < n; ++i) {
      ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
      ImGui::NewFrame();
      ui::draw_frame(s);
      ImGui::Render();
    }
  }
  bool status_names(const char* panel) const { return s.status.rfind(std::string(panel) + ": ", 0) == 0; }
};
}  // namespace

TEST(ErrorChannel, SimulationLoadFailureShowsInThePanelAndOnTheStatusLine) {
  Window w("Simulation");
  EXPECT_TRUE(w.s.status.empty()) << w.s.status;
  w.s.pending.load_path = "/nonexistent/gmslab/scenario.json";
  w.frames(2);
  EXPECT_NE(w.s.error.find("load failed"), std::string::npos) << w.s.error;  // the panel's error
  EXPECT_TRUE(w.status_names("Simulation")) << w.s.status;
  EXPECT_NE(w.s.status.find("/nonexistent/gmslab/scenario.json"), std::string::npos) << w.s.status;
  EXPECT_EQ(w.s.status_kind, ErrorKind::Input);
  EXPECT_EQ(w.s.status_panel, ui::Panel::Simulation);
  // Running again clears the panel's error and the status line.
  w.s.pending.reset = true;
  w.frames(1);
  EXPECT_TRUE(w.s.error.empty()) << w.s.error;
  EXPECT_TRUE(w.s.status.empty()) << w.s.status;
}

TEST(ErrorChannel, SaveFailureIsAnIoErrorOnTheStatusLine) {
  Window w("Simulation");
  w.s.pending.save_path = "/proc/gmslab-no-such-dir/scenario.json";
  w.frames(1);
  EXPECT_NE(w.s.error.find("save failed"), std::string::npos) << w.s.error;
  EXPECT_TRUE(w.status_names("Simulation")) << w.s.status;
  EXPECT_EQ(w.s.status_kind, ErrorKind::Io);
}

TEST(ErrorChannel, FigureFailureShowsInTheFiguresPanelAndOnTheStatusLine) {
  Window w("Figures");
  w.s.figures.id = "no-such-figure";
  w.s.figures.figure = {};
  w.frames(2);
  EXPECT_FALSE(w.s.figures.error.empty());
  EXPECT_TRUE(w.status_names("Figures")) << w.s.status;
  EXPECT_NE(w.s.status.find(w.s.figures.error), std::string::npos) << w.s.status;
  EXPECT_EQ(w.s.status_panel, ui::Panel::Figures);
}

TEST(ErrorChannel, DesignFailureShowsInTheDesignPanelAndOnTheStatusLine) {
  Window w("Design");
  ASSERT_TRUE(w.s.design.out.error.empty()) << w.s.design.out.error;
  w.s.design.settings.use_K = true;
  w.s.design.settings.K = -3.0;  // a bad desired error constant: an input error of the design
  w.s.design.dirty = true;
  w.frames(2);
  EXPECT_NE(w.s.design.out.error.find("design"), std::string::npos) << w.s.design.out.error;
  EXPECT_TRUE(w.status_names("Design")) << w.s.status;
  EXPECT_EQ(w.s.status_kind, ErrorKind::Input);
  // Fixed: the panel's error and the status line clear.
  w.s.design.settings.K = 1000.0;
  w.s.design.dirty = true;
  w.frames(2);
  EXPECT_TRUE(w.s.design.out.error.empty()) << w.s.design.out.error;
  EXPECT_TRUE(w.s.status.empty()) << w.s.status;
}

TEST(ErrorChannel, IdentifyLoadFailureShowsInTheIdentifyPanelAndOnTheStatusLine) {
  Window w("Identify");
  w.s.identify.data = "/nonexistent/gmslab/record.csv";
  w.frames(2);
  EXPECT_FALSE(w.s.identify.preview.error.empty());
  EXPECT_TRUE(w.status_names("Identify")) << w.s.status;
  EXPECT_NE(w.s.status.find("record.csv"), std::string::npos) << w.s.status;
  EXPECT_EQ(w.s.status_panel, ui::Panel::Identify);
}

TEST(ErrorChannel, ReportNamesThePanelAndKindAndANoteReplacesIt) {
  ui::AppState s;
  s.report(ui::Panel::Simulation, SimulationError("energy grows"), "GMS");
  EXPECT_EQ(s.error, "simulation stopped: GMS: energy grows");
  EXPECT_EQ(s.status, "Simulation: simulation stopped: GMS: energy grows");
  EXPECT_EQ(s.status_kind, ErrorKind::Simulation);
  s.report(ui::Panel::Figures, std::logic_error("bug"), "");
  EXPECT_EQ(s.figures.error, "internal error: bug");  // not a gmslab::Error: a bug, still shown
  EXPECT_EQ(s.status_kind, ErrorKind::Internal);
  s.note("saved x.json");
  EXPECT_EQ(s.status, "saved x.json");
  EXPECT_FALSE(s.status_kind.has_value());
}
#endif
