// Rendering hot paths: one full headless frame with 10^6-sample traces in the plots (OSMesa,
// llvmpipe: CPU rasterisation, so this bounds the window's frame time from above), and the
// per-pixel-column decimation that makes it possible.
#include <benchmark/benchmark.h>
#include <imgui.h>

#include <cmath>
#include <vector>

#include "app/headless.hpp"
#include "ui/plot/decimate.hpp"
#include "ui/plot/plot.hpp"

namespace {
struct Trace1e6 {
  std::vector<double> t, y;
  std::vector<std::uint8_t> cls;
  Trace1e6() {
    const std::size_t n = 1'000'000;
    for (std::size_t i = 0; i < n; ++i) {
      const double ti = 25.0 * static_cast<double>(i) / (n - 1);
      t.push_back(ti);
      // Stick-slip-like: a saw tooth with a fast decaying vibration after each drop.
      const double ph = std::fmod(ti, 6.53);
      y.push_back(0.2 * ph + 0.05 * std::exp(-ph * 3) * std::sin(2 * M_PI * 72 * ti));
      cls.push_back(ph > 5.0 ? 1 : 0);
    }
  }
};
const Trace1e6& trace() {
  static const Trace1e6 tr;
  return tr;
}

void draw_plots() {
  const auto& tr = trace();
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(vp->Pos);
  ImGui::SetNextWindowSize(vp->Size);
  ImGui::Begin("bench", nullptr, ImGuiWindowFlags_NoDecoration);
  const ImVec2 a = ImGui::GetContentRegionAvail();
  const ImVec2 cell(a.x * 0.5f - 4, a.y * 0.5f - 4);
  static const ImU32 colors[2] = {gmslab::ui::palette(0), gmslab::ui::palette(1)};
  for (int k = 0; k < 4; ++k) {
    if (k % 2) ImGui::SameLine();
    ImGui::PushID(k);
    if (gmslab::ui::BeginPlot("##p", cell)) {
      gmslab::ui::SetupAxesSI("t", "s", "F", "N");
      gmslab::ui::SeriesStyle st;
      st.x_sorted = true;
      st.classes = tr.cls.data();
      st.class_colors = colors;
      st.n_classes = 2;
      gmslab::ui::PlotLine("1e6 samples", tr.t.data(), tr.y.data(), tr.t.size(), st);
      gmslab::ui::EndPlot();
    }
    ImGui::PopID();
  }
  ImGui::End();
}
}  // namespace

static void BM_HeadlessFrame1600x1000_FourPlotsOf1e6Samples(benchmark::State& state) {
  trace();
  gmslab::app::Offscreen off(1600, 1000);
  off.render(draw_plots, 2);  // warm up: fonts, layout
  for (auto _ : state) benchmark::DoNotOptimize(off.render(draw_plots, 1).data());
  state.counters["samples_per_frame"] = 4e6;
}
BENCHMARK(BM_HeadlessFrame1600x1000_FourPlotsOf1e6Samples)->Unit(benchmark::kMillisecond)->MinTime(2.0);

static void BM_DecimateMinMax_1e6SamplesTo1600Columns(benchmark::State& state) {
  const auto& tr = trace();
  std::vector<std::size_t> out;
  for (auto _ : state) {
    gmslab::ui::decimate_minmax(tr.t.data(), tr.y.data(), tr.t.size(), 0.0, 25.0, 1600, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points_out"] = static_cast<double>(out.size());
  state.SetItemsProcessed(state.iterations() * static_cast<long>(tr.t.size()));
}
BENCHMARK(BM_DecimateMinMax_1e6SamplesTo1600Columns)->Unit(benchmark::kMicrosecond);

static void BM_DecimatePath_1e6SampleLoop(benchmark::State& state) {
  const auto& tr = trace();
  const gmslab::ui::PlotTransform t{0, 5.5, -0.1, 1.4, 0, 0, 800, 450};
  std::vector<std::size_t> out;
  for (auto _ : state) {
    // x = y-ish loop: plot y against the saw-tooth value itself (non-monotonic x).
    gmslab::ui::decimate_path(tr.y.data(), tr.y.data(), tr.y.size(), t, 0.75, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(tr.y.size()));
}
BENCHMARK(BM_DecimatePath_1e6SampleLoop)->Unit(benchmark::kMicrosecond);
