// gmslab ui: plot widget. Index:
//   [SECTION] state      per-plot view state kept by ID, the plot being built
//   [SECTION] data       bounds of the series, autoscale
//   [SECTION] lines      decimation to pixels, solid / dashed / dotted polylines, class colours
//   [SECTION] axes       grid, ticks, tick labels, axis labels, title, legend
//   [SECTION] input      zoom, pan, autoscale, hover readout
//   [SECTION] api        BeginPlot / SetupAxes / PlotLine / EndPlot
#include "ui/plot/plot.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

#include <imgui_internal.h>

#include "ui/plot/decimate.hpp"
#include "ui/figures/figure_export.hpp"
#include "ui/plot/ticks.hpp"

namespace gmslab::ui {

// [SECTION] state ---------------------------------------------------------------------------------
namespace {

struct View {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  bool auto_fit = true;     // follow the data
  bool initialized = false;
  // A boxed legend dragged by the user: its top-left as a fraction of the plot area (kept when
  // the plot resizes); double-click on it returns to the automatic place.
  bool legend_placed = false, legend_drag = false;
  float legend_fx = 0.0f, legend_fy = 0.0f;
  ImRect legend_box;        // where the boxed legend was drawn last frame (empty: none)
  void set_limits(double a, double b, double c, double d) { x0 = a, x1 = b, y0 = c, y1 = d, auto_fit = false, initialized = true; }
};

struct SeriesRef {
  std::string label;               // copied: callers may pass temporaries
  const double* x;
  const double* y;
  std::size_t n;
  SeriesStyle style;
  int index;                       // position in the plot (default colour)
  std::vector<std::size_t> drawn;  // decimated sample indices of this frame
};

struct Axis {
  std::string label;           // fixed label, or name when unit is set
  std::string unit;            // SI unit; non-empty: automatic prefix
  double scale = 1.0;          // displayed value = data / scale
  std::string shown;           // label as drawn, with the chosen prefix
};

struct Building {
  ImGuiID id = 0;
  ImVec2 size;
  PlotOptions opt;
  Axis ax, ay;
  bool has_limits = false, limits_always = false;
  bool has_hint = false;
  double hx0 = 0, hx1 = 1;  // autoscale covers at least this x range
  bool has_hint_y = false;
  double hy0 = 0, hy1 = 1;  // ... and this y range
  double lx0 = 0, lx1 = 1, ly0 = 0, ly1 = 1;
  std::vector<SeriesRef> series;
  // Every place inside the plot area would hide data: the legend goes outside it (rows above, or a
  // column on the right when the rows would be more than two), for paper figures too.
  bool legend_outside = false;
};

}  // namespace

// Everything the widget keeps between calls; owned by the caller (CreatePlotContext).
struct PlotContext {
  std::unordered_map<ImGuiID, View> views;  // per-plot view state, by ID
  std::unordered_map<std::string, ExportFormat> export_requests;  // by plot key, done at its EndPlot
  PngWriter png_writer;                     // the host's (may be empty: no PNG export)
  std::string message;                      // of the last export
  Building plot;                            // the plot between BeginPlot and EndPlot
  bool open = false;
  PlotTransform last;                       // of the last EndPlot
  ImRect last_legend;                       // its boxed legend
  std::vector<LegendStat> legend_stats;     // boxed legends drawn since the last TakeLegendStats
};

namespace {
// The current context (not owned), as ImGui's and ImPlot's: set by the host for its frame.
thread_local PlotContext* g_ctx = nullptr;

struct Colors {
  ImU32 bg, frame, grid, text, axis;
};
Colors colors(bool paper) {
  return {IM_COL32(255, 255, 255, 255), paper ? IM_COL32(0, 0, 0, 255) : IM_COL32(120, 120, 120, 255),
          paper ? IM_COL32(235, 235, 235, 255) : IM_COL32(225, 225, 228, 255),
          IM_COL32(20, 20, 20, 255), IM_COL32(60, 60, 60, 255)};
}

// [SECTION] data ----------------------------------------------------------------------------------
struct Bounds {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  bool valid() const { return x1 >= x0 && y1 >= y0; }
};

// Infinite values (a diverging run) are left out too, so the view stays usable.
void add_bounds(const SeriesRef& s, Bounds& b) {
  if (s.n == 0) return;
  double x0, x1, y0, y1;
  if (s.style.x_sorted) {
    x0 = s.x[0];
    x1 = s.x[s.n - 1];
  } else {
    value_range(s.x, s.n, x0, x1);
  }
  value_range(s.y, s.n, y0, y1);
  if (std::isfinite(x0)) b.x0 = std::min(b.x0, x0);
  if (std::isfinite(x1)) b.x1 = std::max(b.x1, x1);
  if (std::isfinite(y0)) b.y0 = std::min(b.y0, y0);
  if (std::isfinite(y1)) b.y1 = std::max(b.y1, y1);
}

// Pads a range by `frac` on each side; widens a degenerate one.
void pad(double& lo, double& hi, double frac) {
  if (!(hi > lo)) {
    const double m = lo == 0.0 ? 1.0 : 0.1 * std::fabs(lo);  // a flat trace sits mid-plot
    lo -= m;
    hi += m;
    return;
  }
  const double d = (hi - lo) * frac;
  lo -= d;
  hi += d;
}

void fit(View& v, const Building& p) {
  Bounds b;
  bool all_sorted = true;
  for (const auto& s : p.series) {
    add_bounds(s, b);
    all_sorted = all_sorted && s.style.x_sorted;
  }
  if (!b.valid()) b = {0, 1, 0, 1};
  if (p.has_hint) {
    b.x0 = std::min(b.x0, p.hx0);
    b.x1 = std::max(b.x1, p.hx1);
  }
  if (p.has_hint_y) {
    b.y0 = std::min(b.y0, p.hy0);
    b.y1 = std::max(b.y1, p.hy1);
  }
  pad(b.x0, b.x1, all_sorted || p.has_hint ? 0.0 : 0.04);
  pad(b.y0, b.y1, 0.06);
  v.x0 = b.x0;
  v.x1 = b.x1;
  v.y0 = b.y0;
  v.y1 = b.y1;
}

// Picks the SI prefix for an axis from its visible range.
void choose_prefix(Axis& a, double lo, double hi) {
  a.scale = 1.0;
  a.shown = a.label;
  if (a.unit.empty()) return;
  if (a.unit != "-") {
    const double m = std::max(std::fabs(lo), std::fabs(hi));
    static const struct { double f; const char* p; } k[] = {
        {1e3, "k"}, {1.0, ""}, {1e-3, "m"}, {1e-6, "\xC2\xB5"}, {1e-9, "n"}};
    if (m > 0.0 && std::isfinite(m)) {
      a.scale = 1e-9;
      for (const auto& e : k)
        if (m >= e.f * 0.999) {
          a.scale = e.f;
          break;
        }
      if (m < 1e4 && a.scale == 1e3) a.scale = 1.0;  // keep 1000-9999 plain
    }
    const char* p = "";
    for (const auto& e : k)
      if (e.f == a.scale) p = e.p;
    a.shown = a.label + " [" + p + a.unit + "]";
  } else {
    a.shown = a.label + " [-]";
  }
}

// [SECTION] lines ---------------------------------------------------------------------------------
void decimate(SeriesRef& s, const PlotTransform& t) {
  if (s.style.x_sorted)
    decimate_minmax(s.x, s.y, s.n, t.x0, t.x1, std::max(1, static_cast<int>(t.px1 - t.px0)),
                    s.drawn);
  else
    decimate_path(s.x, s.y, s.n, t, 0.75, s.drawn);
}

// Polyline with a dash pattern (on, off pixels); a phase carries across calls.
void dashed_polyline(ImDrawList* dl, const ImVec2* p, int n, ImU32 col, float th, float on,
                     float off, float& phase) {
  const float period = on + off;
  for (int i = 0; i + 1 < n; ++i) {
    const ImVec2 a = p[i], b = p[i + 1];
    const float len = std::hypot(b.x - a.x, b.y - a.y);
    float s = 0.0f;
    while (s < len) {
      const float in = std::fmod(phase, period);
      const bool drawing = in < on;
      const float step = std::min(len - s, drawing ? on - in : period - in);
      if (drawing && len > 0.0f) {
        const float u0 = s / len, u1 = (s + step) / len;
        dl->AddLine(ImVec2(a.x + (b.x - a.x) * u0, a.y + (b.y - a.y) * u0),
                    ImVec2(a.x + (b.x - a.x) * u1, a.y + (b.y - a.y) * u1), col, th);
      }
      s += step;
      phase += step;
    }
  }
}

// A solid polyline, unbroken at any slope: ImGui joins consecutive segments with the average of
// their normals, which vanishes where the path turns back (min/max decimation draws steep
// stretches as up-down runs within a pixel column), thinning the line to nothing there. The path
// is split at every turn sharper than 120 degrees into runs that are stroked separately and
// overlap at the turning point.
void solid_polyline(ImDrawList* dl, const ImVec2* p, int n, ImU32 col, float th) {
  int start = 0;
  for (int i = 1; i + 1 < n; ++i) {
    const ImVec2 a(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y), b(p[i + 1].x - p[i].x, p[i + 1].y - p[i].y);
    const float dot = a.x * b.x + a.y * b.y;
    const float la = a.x * a.x + a.y * a.y, lb = b.x * b.x + b.y * b.y;
    if (dot < -0.5f * std::sqrt(la * lb)) {
      dl->AddPolyline(p + start, i - start + 1, col, 0, th);
      start = i;
    }
  }
  if (n - start >= 2) dl->AddPolyline(p + start, n - start, col, 0, th);
}

void stroke(ImDrawList* dl, const std::vector<ImVec2>& p, std::size_t from, std::size_t to,
            ImU32 col, const SeriesStyle& st, float& phase) {
  const int n = static_cast<int>(to - from);
  if (n < 2) return;
  switch (st.line) {
    case LineStyle::Solid: solid_polyline(dl, &p[from], n, col, st.thickness); break;
    case LineStyle::Dashed: dashed_polyline(dl, &p[from], n, col, st.thickness, 9.f, 5.f, phase); break;
    case LineStyle::Dotted: dashed_polyline(dl, &p[from], n, col, st.thickness, 2.f, 3.5f, phase); break;
  }
}

ImU32 series_color(const SeriesRef& s) { return palette(s.style.color >= 0 ? s.style.color : s.index); }

void draw_series(ImDrawList* dl, const SeriesRef& s, const PlotTransform& t) {
  std::vector<ImVec2> p;
  p.reserve(s.drawn.size());
  for (const std::size_t i : s.drawn)
    p.emplace_back(static_cast<float>(t.to_px_x(s.x[i])), static_cast<float>(t.to_px_y(s.y[i])));
  float phase = 0.0f;
  const ImU32 base = series_color(s);
  if (!s.style.classes) {
    stroke(dl, p, 0, p.size(), base, s.style, phase);
    return;
  }
  auto color_of = [&](std::size_t k) {
    const int c = s.style.classes[s.drawn[k]];
    return c < s.style.n_classes ? s.style.class_colors[c] : base;
  };
  std::size_t start = 0;  // runs of segments with the colour of their end sample
  for (std::size_t k = 1; k < p.size(); ++k) {
    const bool last = k + 1 == p.size();
    if (last || color_of(k + 1) != color_of(k)) {
      stroke(dl, p, start, k + 1, color_of(k), s.style, phase);
      start = k;
    }
  }
}

// [SECTION] axes ----------------------------------------------------------------------------------
struct Layout {
  ImRect frame, area;  // whole widget, plot area
  Ticks xt, yt;
  std::vector<std::string> xl, yl;  // tick labels
  // Live plots: the legend's rows above the plot area, the first series of each (empty: a boxed
  // legend, or none).
  std::vector<std::size_t> legend_rows;
  bool legend_column = false;  // the boxed legend stands right of the plot area
};

float legend_entry(ImDrawList* dl, const SeriesRef& s, ImVec2 at, bool draw);

// Live plots' legends go in rows above the plot area, right-aligned: one row beside the y label
// when it fits there, else two, the upper as wide as the plot area, the lower beside the y label
// (the plot gives up a line of height); more would eat the plot, so then the legend is a box
// inside it (empty result). Paper figures: a box inside, unless every place there hides data.
std::vector<std::size_t> legend_row_starts(const Building& b, float area_w) {
  if ((b.opt.paper && !b.legend_outside) || !b.opt.legend || b.series.empty()) return {};
  const float fh = ImGui::GetFontSize(), gap = 1.2f * fh;
  const float beside = area_w - ImGui::CalcTextSize(b.ay.shown.c_str()).x - 2.0f * fh;  // the y label's row
  std::vector<float> w;
  float total = 0.0f;
  for (const auto& s : b.series) w.push_back(legend_entry(nullptr, s, {}, false)), total += w.back() + gap;
  if (total - gap <= beside) return {0};
  // Two rows: the fewest entries in the lower row that let the upper one fit.
  for (std::size_t split = w.size() - 1; split >= 1; --split) {
    float upper = 0.0f, lower = 0.0f;
    for (std::size_t i = 0; i < w.size(); ++i) (i < split ? upper : lower) += w[i] + gap;
    if (upper - gap > area_w - fh) continue;
    if (lower - gap <= beside) return {0, split};
    return {};
  }
  return {};
}

// Rows for a legend outside the plot area that a column on the right would crowd (more than a
// third of the frame's width): as few rows as fit, filled from the last, which shares its line
// with the y label; at most kMaxLegendRows, else none (the column).
constexpr std::size_t kMaxLegendRows = 4;
std::vector<std::size_t> legend_row_starts_many(const Building& b, float area_w) {
  const float fh = ImGui::GetFontSize(), gap = 1.2f * fh;
  const float beside = area_w - ImGui::CalcTextSize(b.ay.shown.c_str()).x - 2.0f * fh;
  std::vector<std::size_t> starts;  // from the last row up
  std::size_t end = b.series.size();
  while (end > 0 && starts.size() < kMaxLegendRows) {
    const float room = starts.empty() ? beside : area_w - fh;
    std::size_t i = end;
    float row = 0.0f;
    while (i > 0) {
      const float w = legend_entry(nullptr, b.series[i - 1], {}, false);
      if (i < end && row + w > room) break;
      row += w + gap;
      --i;
    }
    if (row - gap > room && !starts.empty()) return {};  // one entry wider than a row
    if (row - gap > room) {  // the last entry does not fit beside the y label: a row above it
      starts.push_back(end);
      continue;
    }
    starts.push_back(i);
    end = i;
  }
  if (end > 0) return {};
  return {starts.rbegin(), starts.rend()};
}

std::vector<std::string> labels(const Ticks& t) {
  double mag = 0.0;
  for (const double v : t.values) mag = std::max(mag, std::fabs(v));
  std::vector<std::string> out;
  for (const double v : t.values) out.push_back(format_tick(v, t.step, mag));
  return out;
}

// The width a legend column right of the plot area takes: the box and a gap on each side.
float legend_column_width(const Building& b) {
  const float fh = ImGui::GetFontSize();
  float w = 0.0f;
  for (const auto& s : b.series) w = std::max(w, legend_entry(nullptr, s, {}, false));
  return w + 0.8f * fh + 0.6f * fh;
}

Layout layout(const Building& b, const View& v, ImRect frame, int extra_rows = -1, float column = 0.0f) {
  if (extra_rows < 0) {  // as many rows as the legend takes at the plot's width
    Layout one = layout(b, v, frame, 0);
    one.legend_rows = legend_row_starts(b, one.area.GetWidth());
    if (one.legend_rows.empty() && b.legend_outside && b.opt.legend && !b.series.empty()) {
      const float column = legend_column_width(b);
      if (column > frame.GetWidth() / 3.0f)
        one.legend_rows = legend_row_starts_many(b, one.area.GetWidth());
      // more than two rows, and rows would be many or the column narrow: a column on the right
      if (one.legend_rows.empty()) return layout(b, v, frame, 0, column);
    }
    if (one.legend_rows.size() <= 1) return one;
    Layout two = layout(b, v, frame, static_cast<int>(one.legend_rows.size()) - 1);
    two.legend_rows = one.legend_rows;
    return two;
  }
  Layout L;
  L.frame = frame;
  const float fh = ImGui::GetFontSize();
  // title + y label line (+ the legend's extra rows)
  const float top = fh * (b.opt.title || b.opt.letter ? 2.6f : 1.5f) + 1.3f * fh * static_cast<float>(extra_rows);
  const float bottom = fh * (b.ax.shown.empty() ? 1.6f : 2.9f);
  const float plot_h = std::max(10.0f, frame.GetHeight() - top - bottom);
  const double sy = b.ay.scale, sx = b.ax.scale;
  L.yt = nice_ticks(v.y0 / sy, v.y1 / sy, std::clamp(static_cast<int>(plot_h / (2.6f * fh)), 2, 10));
  L.yl = labels(L.yt);
  float wmax = 0.0f;
  for (const auto& s : L.yl) wmax = std::max(wmax, ImGui::CalcTextSize(s.c_str()).x);
  const float left = wmax + fh * 0.9f;
  const float right = fh * 1.2f + column;
  L.legend_column = column > 0.0f;
  L.area = ImRect(ImVec2(frame.Min.x + left, frame.Min.y + top),
                  ImVec2(std::max(frame.Min.x + left + 10, frame.Max.x - right),
                         frame.Min.y + top + plot_h));
  // As many x ticks as fit with a gap of one character between their labels.
  for (int target = std::clamp(static_cast<int>(L.area.GetWidth() / (4.5f * fh)), 3, 12); target >= 2; --target) {
    L.xt = nice_ticks(v.x0 / sx, v.x1 / sx, target);
    L.xl = labels(L.xt);
    float widest = 0.0f;
    for (const auto& s : L.xl) widest = std::max(widest, ImGui::CalcTextSize(s.c_str()).x);
    const double spacing = L.xt.step * sx / (v.x1 - v.x0) * L.area.GetWidth();
    if (widest + fh <= spacing) break;
  }
  return L;
}

void draw_axes(ImDrawList* dl, const Building& b, const Layout& L, const PlotTransform& t) {
  const Colors c = colors(b.opt.paper);
  const float fh = ImGui::GetFontSize();
  dl->AddRectFilled(L.area.Min, L.area.Max, c.bg);
  for (std::size_t i = 0; i < L.xt.values.size(); ++i) {
    const float x = std::round(static_cast<float>(t.to_px_x(L.xt.values[i] * b.ax.scale)));
    dl->AddLine(ImVec2(x, L.area.Min.y), ImVec2(x, L.area.Max.y), c.grid);
    dl->AddLine(ImVec2(x, L.area.Max.y), ImVec2(x, L.area.Max.y - 5), c.axis);
    const ImVec2 ts = ImGui::CalcTextSize(L.xl[i].c_str());
    dl->AddText(ImVec2(x - ts.x * 0.5f, L.area.Max.y + 0.25f * fh), c.text, L.xl[i].c_str());
  }
  for (std::size_t i = 0; i < L.yt.values.size(); ++i) {
    const float y = std::round(static_cast<float>(t.to_px_y(L.yt.values[i] * b.ay.scale)));
    dl->AddLine(ImVec2(L.area.Min.x, y), ImVec2(L.area.Max.x, y), c.grid);
    dl->AddLine(ImVec2(L.area.Min.x, y), ImVec2(L.area.Min.x + 5, y), c.axis);
    const ImVec2 ts = ImGui::CalcTextSize(L.yl[i].c_str());
    dl->AddText(ImVec2(L.area.Min.x - ts.x - 0.4f * fh, y - ts.y * 0.5f), c.text, L.yl[i].c_str());
  }
  // Zero lines help reading signed forces and velocities.
  if (t.y0 < 0 && t.y1 > 0) {
    const float y = std::round(static_cast<float>(t.to_px_y(0.0)));
    dl->AddLine(ImVec2(L.area.Min.x, y), ImVec2(L.area.Max.x, y), IM_COL32(170, 170, 175, 255));
  }
  const ImVec2 xs = ImGui::CalcTextSize(b.ax.shown.c_str());
  dl->AddText(ImVec2(L.area.GetCenter().x - xs.x * 0.5f, L.area.Max.y + 1.45f * fh), c.text,
              b.ax.shown.c_str());
  dl->AddText(ImVec2(L.frame.Min.x + 0.2f * fh, L.area.Min.y - 1.3f * fh), c.text, b.ay.shown.c_str());
  if (b.opt.title || b.opt.letter) {
    float x = L.area.Min.x;
    const float y = L.frame.Min.y + 0.1f * fh;
    if (b.opt.letter) {
      // Bold by double-strike.
      dl->AddText(ImVec2(L.frame.Min.x + 0.2f * fh, y), c.text, b.opt.letter);
      dl->AddText(ImVec2(L.frame.Min.x + 0.2f * fh + 1, y), c.text, b.opt.letter);
      x = std::max(x, L.frame.Min.x + 0.4f * fh + ImGui::CalcTextSize(b.opt.letter).x + fh);
    }
    if (b.opt.title) dl->AddText(ImVec2(x, y), c.text, b.opt.title);
  }
}

void draw_frame_border(ImDrawList* dl, const Building& b, const Layout& L) {
  dl->AddRect(L.area.Min, L.area.Max, colors(b.opt.paper).frame, 0.0f, 0, b.opt.paper ? 1.2f : 1.0f);
}

// Where a legend box hides the fewest drawn segments, as matplotlib's loc="best": nine places
// (corners, edge middles, centre), tried in matplotlib's order of preference (upper right, upper
// left, lower left, lower right, right, centre left, centre right, lower centre, upper centre,
// centre); the first with the fewest wins.
ImVec2 legend_best(const Building& b, const Layout& L, ImVec2 box, const PlotTransform& t,
                   std::size_t* hidden = nullptr) {
  const float m = 0.5f * ImGui::GetFontSize();
  const float xl = L.area.Min.x + m, xr = L.area.Max.x - m - box.x, xc = L.area.GetCenter().x - 0.5f * box.x;
  const float yt = L.area.Min.y + m, yb = L.area.Max.y - m - box.y, yc = L.area.GetCenter().y - 0.5f * box.y;
  const ImVec2 c[] = {ImVec2(xr, yt), ImVec2(xl, yt), ImVec2(xl, yb), ImVec2(xr, yb), ImVec2(xr, yc),
                      ImVec2(xl, yc), ImVec2(xc, yb), ImVec2(xc, yt), ImVec2(xc, yc)};
  constexpr int kN = sizeof c / sizeof c[0];
  std::size_t count[kN] = {};
  const float e = 0.3f * ImGui::GetFontSize();  // a line's width and a little air around the box
  for (const auto& s : b.series)  // segments whose bounding box meets the legend box (grown by e)
    for (std::size_t j = 1; j < s.drawn.size(); ++j) {
      const std::size_t i0 = s.drawn[j - 1], i1 = s.drawn[j];
      const double ax = t.to_px_x(s.x[i0]), ay = t.to_px_y(s.y[i0]);
      const double bx = t.to_px_x(s.x[i1]), by = t.to_px_y(s.y[i1]);
      for (int k = 0; k < kN; ++k)
        if (std::max(ax, bx) >= c[k].x - e && std::min(ax, bx) <= c[k].x + box.x + e &&
            std::max(ay, by) >= c[k].y - e && std::min(ay, by) <= c[k].y + box.y + e)
          ++count[k];
    }
  int best = 0;
  for (int k = 1; k < kN; ++k)
    if (count[k] < count[best]) best = k;
  if (hidden) *hidden = count[best];
  return c[best];
}

// One legend entry (line sample + label) with its top-left at `at`; returns its width.
float legend_entry(ImDrawList* dl, const SeriesRef& s, ImVec2 at, bool draw) {
  const float fh = ImGui::GetFontSize();
  const float sample = 2.2f * fh;
  const char* label = s.label.c_str();
  const char* end = ImGui::FindRenderedTextEnd(label);
  const float width = sample + 0.4f * fh + ImGui::CalcTextSize(label, end).x;
  if (!draw) return width;
  const float cy = at.y + 0.5f * fh + 1.0f;
  std::vector<ImVec2> p = {ImVec2(at.x, cy), ImVec2(at.x + sample, cy)};
  float phase = 0.0f;
  SeriesStyle st = s.style;
  st.thickness = std::max(st.thickness, 2.0f);
  if (s.style.classes && s.style.n_classes >= 2) {  // show both class colours, half each
    const ImVec2 mid(0.5f * (p[0].x + p[1].x), cy);
    dl->AddLine(p[0], mid, s.style.class_colors[0], st.thickness);
    dl->AddLine(mid, p[1], s.style.class_colors[1], st.thickness);
  } else {
    stroke(dl, p, 0, 2, series_color(s), st, phase);
  }
  dl->AddText(ImVec2(p[1].x + 0.4f * fh, at.y), colors(false).text, label, end);
  return width;
}

// Live plots: the legend goes in rows above the plot area (Layout::legend_rows), so it never
// hides data. Paper figures (or when it does not fit): a box in a place inside that hides no data,
// else outside the plot area (Building::legend_outside).
bool legend_in_row(const Building&, const Layout& L) { return !L.legend_rows.empty(); }

// The boxed legend's size; zero when there is none (no legend, or it goes in the row above).
ImVec2 legend_box_size(const Building& b, const Layout& L) {
  if (!b.opt.legend || b.series.empty() || legend_in_row(b, L)) return ImVec2(0, 0);
  const float fh = ImGui::GetFontSize();
  float w = 0.0f;
  for (const auto& s : b.series) w = std::max(w, legend_entry(nullptr, s, {}, false));
  return ImVec2(w + 0.8f * fh, fh * 1.25f * static_cast<float>(b.series.size()) + 0.5f * fh);
}

// What a legend drawn at [min, end] hides, for the tests: of the drawn segments inside the plot
// area, those that meet it (bounded if nobody takes them).
void record_legend(const Building& b, const Layout& L, const PlotTransform& t, ImVec2 min, ImVec2 end) {
  if (g_ctx->legend_stats.size() >= 256) return;
  LegendStat st{b.opt.title ? b.opt.title : "", ImVec4(min.x, min.y, end.x, end.y), 0, 0};
  for (const auto& s : b.series)
    for (std::size_t j = 1; j < s.drawn.size(); ++j) {
      const double ax = t.to_px_x(s.x[s.drawn[j - 1]]), ay = t.to_px_y(s.y[s.drawn[j - 1]]);
      const double bx = t.to_px_x(s.x[s.drawn[j]]), by = t.to_px_y(s.y[s.drawn[j]]);
      if (!std::isfinite(ax + ay + bx + by)) continue;
      // only segments inside the plot area count (a zoomed view clips the others)
      if (std::max(ax, bx) < L.area.Min.x || std::min(ax, bx) > L.area.Max.x || std::max(ay, by) < L.area.Min.y ||
          std::min(ay, by) > L.area.Max.y)
        continue;
      ++st.segments;
      st.hidden += std::max(ax, bx) >= min.x && std::min(ax, bx) <= end.x && std::max(ay, by) >= min.y &&
                   std::min(ay, by) <= end.y;
    }
  g_ctx->legend_stats.push_back(std::move(st));
}

void draw_legend(ImDrawList* dl, const Building& b, const Layout& L, const PlotTransform& t, View& v) {
  v.legend_box = ImRect();
  if (!b.opt.legend || b.series.empty()) return;
  const float fh = ImGui::GetFontSize();
  const float gap = 1.2f * fh;
  if (legend_in_row(b, L)) {
    const std::size_t rows = L.legend_rows.size();
    ImRect all(ImVec2(FLT_MAX, FLT_MAX), ImVec2(-FLT_MAX, -FLT_MAX));
    for (std::size_t r = 0; r < rows; ++r) {
      const std::size_t i0 = L.legend_rows[r], i1 = r + 1 < rows ? L.legend_rows[r + 1] : b.series.size();
      if (i0 == i1) continue;  // the y label's line left empty (its entry did not fit beside it)
      float total = 0.0f;
      for (std::size_t i = i0; i < i1; ++i) total += legend_entry(dl, b.series[i], {}, false) + gap;
      float x = L.area.Max.x - (total - gap);
      const float y = L.area.Min.y - 1.3f * fh * static_cast<float>(rows - r);
      all.Add(ImRect(ImVec2(x, y), ImVec2(L.area.Max.x, y + fh)));
      for (std::size_t i = i0; i < i1; ++i) x += legend_entry(dl, b.series[i], ImVec2(x, y), true) + gap;
    }
    v.legend_box = all;
    record_legend(b, L, t, all.Min, all.Max);
    return;
  }
  const float line_h = fh * 1.25f;
  const ImVec2 box = legend_box_size(b, L);
  ImVec2 min = legend_best(b, L, box, t);
  if (L.legend_column)  // right of the plot area, level with its top
    min = ImVec2(L.area.Max.x + 0.6f * fh, L.area.Min.y);
  else if (v.legend_placed)  // where the user put it, kept inside the plot area
    min = ImVec2(std::clamp(L.area.Min.x + v.legend_fx * L.area.GetWidth(), L.area.Min.x, std::max(L.area.Min.x, L.area.Max.x - box.x)),
                 std::clamp(L.area.Min.y + v.legend_fy * L.area.GetHeight(), L.area.Min.y, std::max(L.area.Min.y, L.area.Max.y - box.y)));
  const ImVec2 end(min.x + box.x, min.y + box.y);
  v.legend_box = ImRect(min, end);
  record_legend(b, L, t, min, end);
  dl->AddRectFilled(min, end, IM_COL32(255, 255, 255, 235));
  dl->AddRect(min, end, IM_COL32(150, 150, 150, 255));
  float y = min.y + 0.25f * fh + 0.125f * fh;
  for (const auto& s : b.series) {
    legend_entry(dl, s, ImVec2(min.x + 0.4f * fh, y), true);
    y += line_h;
  }
}

// [SECTION] input ---------------------------------------------------------------------------------
void handle_input(View& v, const Layout& L, const PlotTransform& t, bool hovered, bool active) {
  ImGuiIO& io = ImGui::GetIO();
  if (hovered && io.MouseWheel != 0.0f) {
    const double f = std::pow(0.85, io.MouseWheel);
    const double fx = io.KeyCtrl ? 1.0 : f, fy = io.KeyShift ? 1.0 : f;
    const PlotTransform z = t.zoomed(io.MousePos.x, io.MousePos.y, fx, fy);
    v.set_limits(z.x0, z.x1, z.y0, z.y1);
  }
  // A press on the boxed legend drags the legend, not the view.
  if (active && ImGui::IsMouseClicked(ImGuiMouseButton_Left) && v.legend_box.Contains(io.MousePos)) v.legend_drag = true;
  if (v.legend_drag) {
    if (!io.MouseDown[ImGuiMouseButton_Left]) {
      v.legend_drag = false;
    } else if (io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f) {
      const ImVec2 sz = L.area.GetSize();
      const ImVec2 at = v.legend_placed ? ImVec2(L.area.Min.x + v.legend_fx * sz.x, L.area.Min.y + v.legend_fy * sz.y)
                                        : v.legend_box.Min;
      v.legend_fx = (at.x + io.MouseDelta.x - L.area.Min.x) / std::max(1.0f, sz.x);
      v.legend_fy = (at.y + io.MouseDelta.y - L.area.Min.y) / std::max(1.0f, sz.y);
      v.legend_placed = true;
    }
    if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) v.legend_placed = false, v.legend_drag = false;
    return;
  }
  if (active && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 1.0f)) {
    const PlotTransform p = t.panned(io.MouseDelta.x, io.MouseDelta.y);
    v.set_limits(p.x0, p.x1, p.y0, p.y1);
  }
  if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) v.auto_fit = true;
}

void hover_readout(ImDrawList* dl, const Building& b, const PlotTransform& t) {
  const ImVec2 m = ImGui::GetIO().MousePos;
  double best = 25.0 * 25.0;
  const SeriesRef* hit = nullptr;
  std::size_t hit_i = 0;
  for (const auto& s : b.series)
    for (const std::size_t i : s.drawn) {
      const double dx = t.to_px_x(s.x[i]) - m.x, dy = t.to_px_y(s.y[i]) - m.y;
      if (dx * dx + dy * dy < best) {
        best = dx * dx + dy * dy;
        hit = &s;
        hit_i = i;
      }
    }
  if (!hit) return;
  const ImVec2 p(static_cast<float>(t.to_px_x(hit->x[hit_i])), static_cast<float>(t.to_px_y(hit->y[hit_i])));
  ImU32 col = series_color(*hit);
  if (hit->style.classes && hit->style.classes[hit_i] < hit->style.n_classes)
    col = hit->style.class_colors[hit->style.classes[hit_i]];
  dl->AddCircle(p, 5.0f, col, 12, 2.0f);
  ImGui::BeginTooltip();
  ImGui::TextUnformatted(hit->label.c_str(), ImGui::FindRenderedTextEnd(hit->label.c_str()));
  ImGui::Text("%s = %.6g", b.ax.shown.c_str(), hit->x[hit_i] / b.ax.scale);
  ImGui::Text("%s = %.6g", b.ay.shown.c_str(), hit->y[hit_i] / b.ay.scale);
  ImGui::TextDisabled("sample %zu", hit_i);
  ImGui::EndTooltip();
}

}  // namespace

ImU32 palette(int i) {
  static const ImU32 k[] = {IM_COL32(0, 114, 178, 255),   IM_COL32(213, 94, 0, 255),
                            IM_COL32(0, 158, 115, 255),   IM_COL32(204, 121, 167, 255),
                            IM_COL32(230, 159, 0, 255),   IM_COL32(86, 180, 233, 255),
                            IM_COL32(0, 0, 0, 255),       IM_COL32(240, 228, 66, 255)};
  const int n = static_cast<int>(sizeof k / sizeof k[0]);
  return k[((i % n) + n) % n];
}

// [SECTION] api -----------------------------------------------------------------------------------
PlotContext* CreatePlotContext() { return new PlotContext(); }

void DestroyPlotContext(PlotContext* ctx) {
  if (g_ctx == ctx) g_ctx = nullptr;
  delete ctx;
}

void SetCurrentPlotContext(PlotContext* ctx) { g_ctx = ctx; }
PlotContext* GetCurrentPlotContext() { return g_ctx; }

ScopedPlotContext::ScopedPlotContext() : ctx_(CreatePlotContext()) { SetCurrentPlotContext(ctx_); }
ScopedPlotContext::~ScopedPlotContext() { DestroyPlotContext(ctx_); }

bool BeginPlot(const char* id, ImVec2 size, const PlotOptions& opt) {
  IM_ASSERT(g_ctx && "no current plot context: CreatePlotContext() + SetCurrentPlotContext()");
  if (!g_ctx) return false;  // nothing is drawn (release builds)
  IM_ASSERT(!g_ctx->open && "BeginPlot without EndPlot");
  // Each plot is a child window: its own draw list (16-bit indices) and its own wheel input.
  if (!ImGui::BeginChild(id, size, false, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse)) {
    ImGui::EndChild();
    return false;
  }
  g_ctx->plot = Building{};
  g_ctx->plot.id = ImGui::GetID("##plotview");
  g_ctx->plot.opt = opt;
  g_ctx->open = true;
  return true;
}

void SetupAxes(const char* x_label, const char* y_label) {
  g_ctx->plot.ax = {x_label ? x_label : "", "", 1.0, x_label ? x_label : ""};
  g_ctx->plot.ay = {y_label ? y_label : "", "", 1.0, y_label ? y_label : ""};
}

void SetupAxesSI(const char* x_name, const char* x_unit, const char* y_name, const char* y_unit) {
  g_ctx->plot.ax = {x_name, x_unit ? x_unit : "", 1.0, x_name};
  g_ctx->plot.ay = {y_name, y_unit ? y_unit : "", 1.0, y_name};
}

void SetupAxisLimits(double x0, double x1, double y0, double y1, bool always) {
  g_ctx->plot.has_limits = true;
  g_ctx->plot.limits_always = always;
  g_ctx->plot.lx0 = x0;
  g_ctx->plot.lx1 = x1;
  g_ctx->plot.ly0 = y0;
  g_ctx->plot.ly1 = y1;
}

void SetupFitRangeX(double x0, double x1) {
  g_ctx->plot.has_hint = x1 > x0;
  g_ctx->plot.hx0 = x0;
  g_ctx->plot.hx1 = x1;
}

void SetupFitRangeY(double y0, double y1) {
  g_ctx->plot.has_hint_y = y1 >= y0;
  g_ctx->plot.hy0 = y0;
  g_ctx->plot.hy1 = y1;
}

void PlotLine(const char* label, const double* x, const double* y, std::size_t n,
              const SeriesStyle& style) {
  const int index = static_cast<int>(g_ctx->plot.series.size());
  g_ctx->plot.series.push_back({label ? label : "", x, y, n, style, index, {}});
}

namespace {
// The plot as a one-panel Figure, in the units its axes show.
Figure plot_figure(const Building& b) {
  Figure f;
  const std::string title = b.opt.title ? b.opt.title : "plot";
  f.id = title;
  f.title = title;
  // The title once: the figure's (the panel's own title stays empty).
  Panel p{b.opt.letter ? b.opt.letter : "", "", b.ax.shown, b.ay.shown, {}};
  for (const auto& s : b.series) {
    Series out;
    out.label = s.label;
    out.style = s.style.line == LineStyle::Dashed ? Series::Style::Dashed
                : s.style.line == LineStyle::Dotted ? Series::Style::Dotted : Series::Style::Solid;
    out.color = s.style.color >= 0 ? s.style.color : s.index;
    out.x.resize(s.n);
    out.y.resize(s.n);
    for (std::size_t i = 0; i < s.n; ++i) out.x[i] = s.x[i] / b.ax.scale, out.y[i] = s.y[i] / b.ay.scale;
    p.series.push_back(std::move(out));
  }
  f.panels.push_back(std::move(p));
  return f;
}

std::string plot_key(const Building& b) { return b.opt.title ? b.opt.title : std::to_string(b.id); }

void export_menu(const Building& b) {
  if (!ImGui::BeginPopupContextItem("##export")) return;
  ImGui::TextDisabled("Export this plot to %s", export_dir().c_str());
  if (ImGui::MenuItem("PNG image", nullptr, false, static_cast<bool>(g_ctx->png_writer))) g_ctx->export_requests[plot_key(b)] = ExportFormat::Png;
  if (ImGui::MenuItem("SVG (vector)")) g_ctx->export_requests[plot_key(b)] = ExportFormat::Svg;
  if (ImGui::MenuItem("CSV of its series")) g_ctx->export_requests[plot_key(b)] = ExportFormat::Csv;
  ImGui::EndPopup();
}
}  // namespace

void RequestPlotExport(const char* title, ExportFormat format) {
  if (g_ctx) g_ctx->export_requests[title] = format;
}

void SetPlotPngWriter(PngWriter writer) {
  if (g_ctx) g_ctx->png_writer = std::move(writer);
}

const PngWriter& GetPlotPngWriter() {
  static const PngWriter none;
  return g_ctx ? g_ctx->png_writer : none;
}

void PostPlotMessage(std::string message) {
  if (g_ctx) g_ctx->message = std::move(message);
}

std::string TakePlotMessage() {
  if (!g_ctx) return "";
  std::string m = std::move(g_ctx->message);
  g_ctx->message.clear();
  return m;
}

void EndPlot() {
  IM_ASSERT(g_ctx && g_ctx->open);
  Building& b = g_ctx->plot;
  View& v = g_ctx->views[b.id];
  if (b.has_limits && (b.limits_always || !v.initialized))
    v.set_limits(b.lx0, b.lx1, b.ly0, b.ly1);
  if (v.auto_fit && !(b.has_limits && b.limits_always)) fit(v, b);
  v.initialized = true;
  choose_prefix(b.ax, v.x0, v.x1);
  choose_prefix(b.ay, v.y0, v.y1);

  const ImVec2 pos = ImGui::GetCursorScreenPos();
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const Layout L = layout(b, v, ImRect(pos, ImVec2(pos.x + avail.x, pos.y + avail.y)));
  PlotTransform t{v.x0, v.x1, v.y0, v.y1, L.area.Min.x, L.area.Min.y, L.area.Max.x, L.area.Max.y};

  bool hovered = false, active = false;
  if (b.opt.interactive) {
    ImGui::SetCursorScreenPos(L.area.Min);
    ImGui::InvisibleButton("##plotarea", L.area.GetSize());
    hovered = ImGui::IsItemHovered();
    active = ImGui::IsItemActive();
    export_menu(b);
    handle_input(v, L, t, hovered, active);
    t = {v.x0, v.x1, v.y0, v.y1, L.area.Min.x, L.area.Min.y, L.area.Max.x, L.area.Max.y};
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  choose_prefix(b.ax, v.x0, v.x1);  // limits may have changed with the input
  choose_prefix(b.ay, v.y0, v.y1);
  Layout L2 = layout(b, v, L.frame);
  t = {v.x0, v.x1, v.y0, v.y1, L2.area.Min.x, L2.area.Min.y, L2.area.Max.x, L2.area.Max.y};
  // A view that follows the data, whose boxed legend would hide some of it wherever it goes: the
  // y range grows upwards by the legend's height, so the legend sits above the data and hides none.
  // Panels sharing a y range (SetupFitRangeY) always grow, so their scales stay the same.
  if (v.auto_fit && !(b.has_limits && b.limits_always) && !v.legend_placed) {
    const ImVec2 box = legend_box_size(b, L2);
    const float band = box.y + ImGui::GetFontSize();  // the legend, its margin above and a gap below
    const float H = L2.area.GetHeight();
    if (box.y > 0.0f && band < 0.6f * H) {
      for (auto& s : b.series) decimate(s, t);
      std::size_t hidden = 0;
      legend_best(b, L2, box, t, &hidden);
      if (hidden > 0 || b.has_hint_y) {  // panels sharing one y scale all take it, so they stay alike
        v.y1 = v.y0 + (v.y1 - v.y0) * H / (H - band);
        choose_prefix(b.ay, v.y0, v.y1);
        L2 = layout(b, v, L.frame);
        t = {v.x0, v.x1, v.y0, v.y1, L2.area.Min.x, L2.area.Min.y, L2.area.Max.x, L2.area.Max.y};
      }
    }
  }
  // A boxed legend that would hide data wherever it goes inside the plot area (fixed limits, a
  // legend too tall for the room above the data, data up to the top): it goes outside the area.
  if (!v.legend_placed) {
    const ImVec2 box = legend_box_size(b, L2);
    if (box.y > 0.0f) {
      for (auto& s : b.series) decimate(s, t);
      std::size_t hidden = 0;
      legend_best(b, L2, box, t, &hidden);
      if (hidden > 0) {
        b.legend_outside = true;
        L2 = layout(b, v, L.frame);
        t = {v.x0, v.x1, v.y0, v.y1, L2.area.Min.x, L2.area.Min.y, L2.area.Max.x, L2.area.Max.y};
      }
    }
  }
  draw_axes(dl, b, L2, t);
  dl->PushClipRect(L2.area.Min, L2.area.Max, true);
  for (auto& s : b.series) {
    decimate(s, t);
    draw_series(dl, s, t);
  }
  dl->PopClipRect();
  draw_legend(dl, b, L2, t, v);
  if (b.opt.interactive && !v.auto_fit) {  // tell how to get back to the whole trace
    const char* hint = "zoomed: double-click to fit";
    // Inside the plot area's bottom-right corner, on a backing (the x-axis label stays clear).
    const ImVec2 hs = ImGui::CalcTextSize(hint);
    const float m = 0.25f * ImGui::GetFontSize();
    const ImVec2 at(L2.area.Max.x - hs.x - 2 * m, L2.area.Max.y - hs.y - 2 * m);
    dl->AddRectFilled(ImVec2(at.x - m, at.y - m), ImVec2(at.x + hs.x + m, at.y + hs.y + m), IM_COL32(255, 255, 255, 220));
    dl->AddText(at, IM_COL32(120, 120, 130, 255), hint);
  }
  if (hovered) hover_readout(dl, b, t);
  draw_frame_border(dl, b, L2);
  if (auto it = g_ctx->export_requests.find(plot_key(b)); it != g_ctx->export_requests.end()) {
    g_ctx->message = export_figure(plot_figure(b), it->second, g_ctx->png_writer);
    g_ctx->export_requests.erase(it);
  }
  g_ctx->last = t;
  g_ctx->last_legend = v.legend_box;
  g_ctx->open = false;
  ImGui::EndChild();
}

PlotTransform LastPlotTransform() { return g_ctx ? g_ctx->last : PlotTransform{}; }

std::vector<LegendStat> TakeLegendStats() {
  if (!g_ctx) return {};
  std::vector<LegendStat> out = std::move(g_ctx->legend_stats);
  g_ctx->legend_stats.clear();
  return out;
}

ImVec4 LastLegendBox() {
  if (!g_ctx) return ImVec4(0, 0, 0, 0);
  const ImRect& r = g_ctx->last_legend;
  return ImVec4(r.Min.x, r.Min.y, r.Max.x, r.Max.y);
}

}  // namespace gmslab::ui
