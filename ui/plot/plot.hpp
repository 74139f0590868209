// gmslab ui: a small plot widget on ImDrawList (ImPlot's shape, a fraction of its size).
//
//   if (ui::BeginPlot("##force", {-1, 300})) {
//     ui::SetupAxes("t [s]", "F [N]");          // labels carry their units
//     ui::PlotLine("friction", t, f, n, {.x_sorted = true});
//     ui::EndPlot();                            // lays out, handles input, draws
//   }
//
// View state (limits, autoscale) is kept per plot ID between frames, in the current PlotContext. Interaction: mouse wheel
// zooms about the cursor (Shift: x only, Ctrl: y only), left drag pans, double-click returns to
// autoscale (the view then follows the data as it grows). Hovering shows the nearest drawn sample.
// Data pointers must stay valid until EndPlot (the data is not copied; labels are). Long traces are decimated per
// pixel column (ui/plot/decimate.hpp), so 10^6 samples draw in well under a frame.
#pragma once

#include <imgui.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ui/figures/figure_export.hpp"
#include "ui/plot/plot_transform.hpp"

namespace gmslab::ui {

enum class LineStyle { Solid, Dashed, Dotted };

// Colour-blind-safe palette (Okabe-Ito order: blue, vermillion, green, purple, orange, sky blue,
// black, yellow); i wraps around.
ImU32 palette(int i);

struct SeriesStyle {
  int color = -1;                // palette index; -1: by the series' position in the plot
  LineStyle line = LineStyle::Solid;
  float thickness = 2.0f;        // [px]; integers draw cheapest (textured anti-aliased lines)
  bool x_sorted = false;         // x non-decreasing (time axes): min/max decimation per column
  // Optional per-sample class (e.g. 0 = stick, 1 = slip): the segment ending at sample k is drawn
  // in class_colors[classes[k]] (classes >= n_classes fall back to the series colour).
  const std::uint8_t* classes = nullptr;
  const ImU32* class_colors = nullptr;
  int n_classes = 0;
};

struct PlotOptions {
  const char* title = nullptr;   // drawn above the plot area
  const char* letter = nullptr;  // panel letter (paper figures), drawn bold before the title
  bool legend = true;
  bool interactive = true;       // zoom, pan, hover
  bool paper = false;            // paper look: black frame, ticks inside, lighter grid
};

// The widget's state (each plot's view limits and autoscale by ID, the plot being built, the
// last transform) lives in a PlotContext owned by the caller, as ImPlot's: a host creates one
// beside its ImGui context and makes it current for its frames, so two windows or renders never
// share view state. BeginPlot without a current context draws nothing (asserts in debug builds).
struct PlotContext;
PlotContext* CreatePlotContext();
void DestroyPlotContext(PlotContext* ctx);  // clears the current context if it is this one
void SetCurrentPlotContext(PlotContext* ctx);
PlotContext* GetCurrentPlotContext();

// Owns a context and makes it current (creation order = the usual ImGui::CreateContext order).
class ScopedPlotContext {
 public:
  ScopedPlotContext();
  ~ScopedPlotContext();
  ScopedPlotContext(const ScopedPlotContext&) = delete;
  ScopedPlotContext& operator=(const ScopedPlotContext&) = delete;
  PlotContext* get() const { return ctx_; }
  void make_current() const { SetCurrentPlotContext(ctx_); }

 private:
  PlotContext* ctx_;
};

bool BeginPlot(const char* id, ImVec2 size = ImVec2(-1, -1), const PlotOptions& opt = {});
// Fixed axis labels, e.g. "x [um]" (paper figures: the data is already in those units).
void SetupAxes(const char* x_label, const char* y_label);
// Axis names and SI units: the widget picks a prefix from the visible range so ticks stay short
// ("x [µm]" with ticks 0, 5, 10 instead of "x [m]" with 1e-05). Data stays in SI units.
// A unit of "" or "-" gets no prefix.
void SetupAxesSI(const char* x_name, const char* x_unit, const char* y_name, const char* y_unit);
// Limits of the first frame (or of every frame with always = true, which also disables autoscale).
void SetupAxisLimits(double x0, double x1, double y0, double y1, bool always = false);
// Autoscale covers at least [x0, x1] in x (e.g. [0, duration] for a trace that is still growing).
void SetupFitRangeX(double x0, double x1);
// Autoscale covers at least [y0, y1] in y (panels sharing one y scale).
void SetupFitRangeY(double y0, double y1);
void PlotLine(const char* label, const double* x, const double* y, std::size_t n,
              const SeriesStyle& style = {});
void EndPlot();

// Transform used by the last EndPlot (for tests and overlays).
PlotTransform LastPlotTransform();
// The legend of the last EndPlot (min x, min y, max x, max y in screen pixels; zero size when it
// was not drawn). Live plots put it in rows above the plot area; paper figures (or rows that do
// not fit) in a box inside, in the first of nine places (as matplotlib's "best") that hides no
// drawn segment, after making room above the data in a view that follows it. When every place
// inside hides data, the legend goes outside the plot area: rows above it, or a column on its
// right when more than two rows would be needed. Drag a box inside to move it (kept per plot, as
// a fraction of the plot area), double-click it to return to the automatic place.
ImVec4 LastLegendBox();
// Every legend drawn since the last call (taken once; for tests): the plot's title, the legend's
// box, and how many of the drawn (decimated) segments inside the plot area meet it.
struct LegendStat {
  std::string plot;
  ImVec4 box;
  std::size_t hidden = 0, segments = 0;
};
std::vector<LegendStat> TakeLegendStats();

// Export (right-click on an interactive plot: PNG, SVG, CSV of its series). The plot becomes a
// one-panel Figure in the units shown (ui/figures/figure_export.hpp writes it into export_dir()). The
// host provides how a Figure becomes a PNG (the window: gmslab-headless plot-figure; tests: their
// own); without one, PNG is not offered. The message of the last export ("wrote PATH" or the
// error) is taken once by TakePlotMessage (the app puts it on the status line).
// Requests the export of the plot titled `title` at its next EndPlot (as the menu does; tests).
void RequestPlotExport(const char* title, ExportFormat format);
// The current context's PNG writer (a Figure and a path; throws on failure).
void SetPlotPngWriter(PngWriter writer);
const PngWriter& GetPlotPngWriter();  // empty without a context or writer
void PostPlotMessage(std::string message);
std::string TakePlotMessage();

}  // namespace gmslab::ui
