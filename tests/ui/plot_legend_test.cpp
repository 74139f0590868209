// Boxed legends go where they hide the fewest drawn segments and can be moved: data filling random
// regions of the plot (fixed seed) never lies under the legend when an empty place exists; a drag
// on the legend moves it by the mouse distance, not the view; a double-click puts it back.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "tests/ui/imgui_test_context.hpp"
#include "ui/plot/plot.hpp"

using namespace gmslab;

namespace {
struct Harness {
  ui::ScopedPlotContext plots;
  std::vector<std::vector<double>> xs, ys;  // one series each
  ImVec4 box;
  ui::PlotTransform t;
  bool fixed = true;  // limits `lim` always (else the view follows the data)
  double lim[4] = {0, 1, 0, 1};
  std::vector<std::string> names;  // series labels (default: a long one, then "s")
  ImVec2 size{900, 800};           // the window the plot fills [px]
  Harness() {
    uitest::make_headless_imgui(ImVec2(900, 800));
  }
  ~Harness() { ImGui::DestroyContext(); }
  void frame(ImVec2 mouse = ImVec2(-FLT_MAX, -FLT_MAX), bool down = false) {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = mouse;
    io.MouseDown[0] = down;
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(size);
    ImGui::Begin("w", nullptr, ImGuiWindowFlags_NoDecoration);
    ui::PlotOptions o;
    o.paper = true;  // boxed legend
    if (ui::BeginPlot("##p", ImVec2(-1, -1), o)) {
      ui::SetupAxes("x [-]", "y [-]");
      if (fixed) ui::SetupAxisLimits(lim[0], lim[1], lim[2], lim[3], true);
      for (std::size_t k = 0; k < xs.size(); ++k)
        if (!xs[k].empty())
          ui::PlotLine(k < names.size() ? names[k].c_str() : k == 0 ? "a long series label" : "s", xs[k].data(),
                       ys[k].data(), xs[k].size(), {.x_sorted = std::is_sorted(xs[k].begin(), xs[k].end())});
      ui::EndPlot();
      box = ui::LastLegendBox();
      t = ui::LastPlotTransform();
    }
    ImGui::End();
    ImGui::Render();
  }
  // Samples (in pixels) inside the legend box.
  int covered() const {
    int n = 0;
    for (std::size_t k = 0; k < xs.size(); ++k)
      for (std::size_t i = 0; i < xs[k].size(); ++i) {
        const double px = t.to_px_x(xs[k][i]), py = t.to_px_y(ys[k][i]);
        n += px >= box.x && px <= box.z && py >= box.y && py <= box.w;
      }
    return n;
  }
};
}  // namespace

TEST(PlotLegend, GoesWhereItHidesNoDataWhenSuchAPlaceExists) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Harness h;
    // Dense zigzags (one series each, sample spacing far below the legend size) filling every
    // cell of a 3x3 grid but one random free cell.
    const int free_i = static_cast<int>(rng() % 3), free_j = static_cast<int>(rng() % 3);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (i == free_i && j == free_j) continue;
        auto& sx = h.xs.empty() || !h.xs.back().empty() ? h.xs.emplace_back() : h.xs.back();
        auto& sy = h.ys.size() < h.xs.size() ? h.ys.emplace_back() : h.ys.back();
        for (int k = 0; k < 400; ++k) {
          sx.push_back((i + 0.02 + 0.96 * u(rng)) / 3.0);
          sy.push_back((j + 0.02 + 0.96 * (k % 2 ? u(rng) * 0.5 + 0.5 : u(rng) * 0.5)) / 3.0);
        }
      }
    h.frame();
    h.frame();
    ASSERT_GT(h.box.z - h.box.x, 10.0f);
    EXPECT_EQ(h.covered(), 0) << "free cell " << free_i << "," << free_j;
  }
}

TEST(PlotLegend, DraggingMovesTheLegendNotTheViewAndDoubleClickPutsItBack) {
  Harness h;
  h.xs.emplace_back();
  h.ys.emplace_back();
  for (int k = 0; k <= 100; ++k) h.xs[0].push_back(k / 100.0), h.ys[0].push_back(0.5);
  h.frame();
  h.frame();
  const ImVec4 b0 = h.box;
  const ui::PlotTransform t0 = h.t;
  const ImVec2 grab(std::floor(0.5f * (b0.x + b0.z)), std::floor(0.5f * (b0.y + b0.w)));
  const ImVec2 d(-120, 150);
  h.frame(grab, false);
  h.frame(grab, true);
  h.frame(ImVec2(grab.x + 0.5f * d.x, grab.y + 0.5f * d.y), true);
  h.frame(ImVec2(grab.x + d.x, grab.y + d.y), true);
  h.frame(ImVec2(grab.x + d.x, grab.y + d.y), false);
  h.frame();
  EXPECT_NEAR(h.box.x - b0.x, d.x, 1.0);
  EXPECT_NEAR(h.box.y - b0.y, d.y, 1.0);
  EXPECT_DOUBLE_EQ(h.t.x0, t0.x0);  // the view did not pan
  EXPECT_DOUBLE_EQ(h.t.y0, t0.y0);
  // Double-click on it: back to the automatic place.
  const ImVec2 at(std::floor(0.5f * (h.box.x + h.box.z)), std::floor(0.5f * (h.box.y + h.box.w)));
  for (int k = 0; k < 2; ++k) {
    h.frame(at, true);
    h.frame(at, false);
  }
  h.frame();
  EXPECT_NEAR(h.box.x, b0.x, 1.0);
  EXPECT_NEAR(h.box.y, b0.y, 1.0);
}

// Every cell of a 3x3 grid but one corner holds data; the other corner cells hold far fewer samples
// than the rest, in a random order of density: the legend goes into the empty corner, through the
// same EndPlot the window draws with.
TEST(PlotLegend, GoesIntoTheEmptiestCorner) {
  std::mt19937 rng(1515);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 16; ++trial) {
    Harness h;
    int dens[4] = {0, 6, 60, 150};
    std::shuffle(dens, dens + 4, rng);
    const int corner_i[4] = {0, 2, 0, 2}, corner_j[4] = {0, 0, 2, 2};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        int n = 500;
        for (int c = 0; c < 4; ++c)
          if (i == corner_i[c] && j == corner_j[c]) n = dens[c];
        auto& sx = h.xs.emplace_back();
        auto& sy = h.ys.emplace_back();
        for (int k = 0; k < n; ++k) {
          sx.push_back((i + 0.02 + 0.96 * u(rng)) / 3.0);
          sy.push_back((j + 0.02 + 0.96 * (k % 2 ? u(rng) * 0.5 + 0.5 : u(rng) * 0.5)) / 3.0);
        }
      }
    h.frame();
    h.frame();
    ASSERT_GT(h.box.z - h.box.x, 10.0f);
    const int emptiest = static_cast<int>(std::min_element(dens, dens + 4) - dens);
    // The box's centre in data units lies in that corner's cell.
    const double cx = (0.5 * (h.box.x + h.box.z) - h.t.px0) / (h.t.px1 - h.t.px0);
    const double cy = 1.0 - (0.5 * (h.box.y + h.box.w) - h.t.py0) / (h.t.py1 - h.t.py0);
    EXPECT_EQ(static_cast<int>(cx * 3), corner_i[emptiest]) << "trial " << trial;
    EXPECT_EQ(static_cast<int>(cy * 3), corner_j[emptiest]) << "trial " << trial;
  }
}

// A view that follows the data, with data everywhere (no empty place for the box): the y range
// grows above the data by the legend's height, so the legend hides no segment and lies above every
// sample. Random offsets and scales (fixed seed).
TEST(PlotLegend, AutoFittedViewMakesRoomAboveTheDataForTheLegend) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 10; ++trial) {
    Harness h;
    h.fixed = false;
    const double x0 = -5 + 10 * u(rng), sx = std::pow(10.0, -3 + 6 * u(rng));
    const double y0 = -5 + 10 * u(rng), sy = std::pow(10.0, -3 + 6 * u(rng));
    for (int s = 0; s < 1 + trial % 4; ++s) {
      auto& xs = h.xs.emplace_back();
      auto& ys = h.ys.emplace_back();
      for (int k = 0; k < 3000; ++k) xs.push_back(x0 + sx * u(rng)), ys.push_back(y0 + sy * u(rng));
    }
    h.frame();
    h.frame();
    ASSERT_GT(h.box.z - h.box.x, 10.0f);
    const std::vector<ui::LegendStat> stats = ui::TakeLegendStats();
    ASSERT_FALSE(stats.empty());
    EXPECT_EQ(stats.back().hidden, 0u) << "trial " << trial;
    EXPECT_GT(stats.back().segments, 1000u);
    double top = INFINITY;  // the highest sample, in pixels
    for (const auto& ys : h.ys)
      for (double y : ys) top = std::min(top, h.t.to_px_y(y));
    EXPECT_LT(h.box.w, top) << "trial " << trial;
  }
}

// Residuals as the Identify report's panels B and D show them: a dense noise band across the whole
// x range and sparse spikes, up and down, at random places, reaching into every place a box could
// take inside the plot; the limits fixed to the data's range (no room above it), at several
// scales, with 1 to 6 series (long labels: more than two rows, so a column beside the plot).
// No sample lies under the legend: it goes outside the plot area (fixed seeds).
TEST(PlotLegend, NeverCoversResidualSpikesThatReachEveryPlaceInside) {
  std::mt19937 rng(2727);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 12; ++trial) {
    Harness h;
    const double x0 = -50 + 100 * u(rng), sx = std::pow(10.0, -4 + 8 * u(rng));
    const double y0 = -50 + 100 * u(rng), sy = std::pow(10.0, -4 + 8 * u(rng));
    const int n_series = 1 + trial % 6;
    for (int k = 0; k < n_series; ++k) {
      auto& xs = h.xs.emplace_back();
      auto& ys = h.ys.emplace_back();
      h.names.push_back(trial % 3 == 2 ? "+ residual after round " + std::to_string(k + 1) + " (velocity_extra)"
                                       : "+ round " + std::to_string(k + 1));
      const int n = 1500;
      for (int i = 0; i < n; ++i) {
        xs.push_back(static_cast<double>(i) / (n - 1));
        double y = 0.5 + 0.06 * (u(rng) - 0.5);  // the noise band
        if (rng() % 10 == 0) y = u(rng);         // a spike anywhere in y
        ys.push_back(y);
      }
      ys.front() = 0.0, ys.back() = 1.0;  // the data spans the limits
    }
    for (auto& xs : h.xs)
      for (double& x : xs) x = x0 + sx * x;
    for (auto& ys : h.ys)
      for (double& y : ys) y = y0 + sy * y;
    h.lim[0] = x0, h.lim[1] = x0 + sx, h.lim[2] = y0, h.lim[3] = y0 + sy;
    h.fixed = trial % 2 == 0;  // fixed limits, or a view that follows the data
    h.frame();
    h.frame();
    SCOPED_TRACE("trial " + std::to_string(trial) + ", " + std::to_string(n_series) + " series");
    ASSERT_GT(h.box.z - h.box.x, 10.0f) << "no legend drawn";
    EXPECT_EQ(h.covered(), 0) << "samples under the legend";
    const std::vector<ui::LegendStat> stats = ui::TakeLegendStats();
    ASSERT_FALSE(stats.empty());
    EXPECT_EQ(stats.back().hidden, 0u) << "drawn segments under the legend";
  }
}
// A narrow plot whose legend must go outside (spikes reach every place inside) and would need
// more than two rows: a column on the right would take most of the width, so the legend goes in
// rows above the plot area, and the plot area keeps at least two thirds of the window's width.
// Widths from 260 to 420 px, 3 to 4 series with the Identify panel's round labels (fixed seed).
TEST(PlotLegend, ANarrowPlotKeepsItsWidthWithTheLegendInRowsAbove) {
  std::mt19937 rng(5150);
  std::uniform_real_distribution<double> u(0, 1);
  const std::vector<std::string> labels = {"+ inertia", "+ direction_asymmetry", "+ velocity_extra",
                                           "+ discovered"};
  for (int trial = 0; trial < 8; ++trial) {
    Harness h;
    h.size = ImVec2(static_cast<float>(260 + 160 * u(rng)), 320);
    const int n_series = 3 + trial % 2;
    for (int k = 0; k < n_series; ++k) {
      auto& xs = h.xs.emplace_back();
      auto& ys = h.ys.emplace_back();
      h.names.push_back(labels[static_cast<std::size_t>(k)]);
      for (int i = 0; i < 1500; ++i) {
        xs.push_back(i / 1499.0);
        ys.push_back(rng() % 8 == 0 ? u(rng) : 0.5 + 0.05 * (u(rng) - 0.5));
      }
      ys.front() = 0.0, ys.back() = 1.0;
    }
    h.fixed = true;
    h.frame();
    h.frame();
    SCOPED_TRACE("trial " + std::to_string(trial) + ", width " + std::to_string(h.size.x) + " px");
    ASSERT_GT(h.box.z - h.box.x, 10.0f) << "no legend drawn";
    EXPECT_EQ(h.covered(), 0) << "samples under the legend";
    EXPECT_LE(h.box.w, h.t.py0 + 0.5) << "the legend is not above the plot area";
    EXPECT_GE(h.t.px1 - h.t.px0, 2.0 / 3.0 * h.size.x - 80.0)
        << "the plot area lost its width to the legend";
    EXPECT_LE(h.box.z, h.size.x) << "the legend leaves the window";
  }
}
#endif
