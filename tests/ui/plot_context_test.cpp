// The plot widget's state lives in a PlotContext owned by the caller: two ImGui contexts (two
// windows, two renders) with their own plot contexts never share view state, even for plots of
// the same ID; a context keeps its own views across frames.
#include <gtest/gtest.h>
#include <imgui.h>

#include <cfloat>

#include "ui/plot/plot.hpp"
#include "tests/ui/imgui_test_context.hpp"

using namespace gmslab;

namespace {
struct Host {
  ImGuiContext* imgui = nullptr;
  ui::PlotContext* plots = nullptr;
  Host() {
    imgui = uitest::make_headless_imgui(ImVec2(800, 600));
    plots = ui::CreatePlotContext();
  }
  ~Host() {
    ui::DestroyPlotContext(plots);
    ImGui::DestroyContext(imgui);
  }
  // One frame with one plot "##same" whose first-frame x limits are [0, x1]; its transform.
  ui::PlotTransform frame(double x1) {
    ImGui::SetCurrentContext(imgui);
    ui::SetCurrentPlotContext(plots);
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(io.DisplaySize);
    ImGui::Begin("host", nullptr, ImGuiWindowFlags_NoDecoration);
    ui::PlotTransform t;
    if (ui::BeginPlot("##same", ImVec2(600, 400))) {
      ui::SetupAxisLimits(0.0, x1, -1.0, 1.0);
      const double xs[2] = {0.0, 1.0}, ys[2] = {0.0, 0.5};
      ui::PlotLine("line", xs, ys, 2);
      ui::EndPlot();
      t = ui::LastPlotTransform();
    }
    ImGui::End();
    ImGui::Render();
    return t;
  }
};
}  // namespace

TEST(PlotContext, TwoHostsKeepTheirOwnViewStateForTheSameId) {
  Host a, b;
  EXPECT_EQ(a.frame(10.0).x1, 10.0);
  // Same window and plot ID in another context: its own first frame, its own limits (with one
  // process-wide state the view would already exist and keep [0, 10]).
  EXPECT_EQ(b.frame(2.0).x1, 2.0);
  // Each keeps its view from its first frame on (limits only apply to a new view).
  EXPECT_EQ(a.frame(99.0).x1, 10.0);
  EXPECT_EQ(b.frame(99.0).x1, 2.0);
  ASSERT_EQ(ui::GetCurrentPlotContext(), b.plots);
}

TEST(PlotContext, DestroyingTheCurrentContextClearsItAndANewContextStartsFresh) {
  double first = 0.0;
  {
    Host a;
    first = a.frame(5.0).x1;
    EXPECT_EQ(ui::GetCurrentPlotContext(), a.plots);
  }
  EXPECT_EQ(first, 5.0);
  EXPECT_EQ(ui::GetCurrentPlotContext(), nullptr);
  Host c;
  EXPECT_EQ(c.frame(7.0).x1, 7.0);
}
