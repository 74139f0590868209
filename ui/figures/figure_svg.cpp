#include "ui/figures/figure_svg.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/io/atomic_file.hpp"
#include "ui/figures/figure_view.hpp"
#include "ui/plot/plot.hpp"
#include "ui/plot/ticks.hpp"

namespace gmslab::ui {

namespace {
std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// "um" in a label is micrometres: written as µm, as in the window.
std::string units(std::string s) {
  for (std::size_t i = 0; (i = s.find("[um]", i)) != std::string::npos; i += 4) s.replace(i, 4, "[\xC2\xB5m]");
  return s;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

std::string rgb(int i) {
  const ImU32 c = palette(i);
  char b[16];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", static_cast<unsigned>(c & 0xff), static_cast<unsigned>((c >> 8) & 0xff),
                static_cast<unsigned>((c >> 16) & 0xff));
  return b;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  void pad() {
    if (!(hi >= lo)) lo = 0, hi = 1;
    if (hi - lo <= 1e-300 * std::max(1.0, std::fabs(lo))) {
      const double d = lo == 0 ? 1.0 : 0.05 * std::fabs(lo);
      lo -= d, hi += d;
    }
    const double m = 0.04 * (hi - lo);
    lo -= m, hi += m;
  }
};
}  // namespace

std::string figure_svg(const Figure& f, int width, int height) {
  const double W = width, H = height, font = std::clamp(H / 60.0, 10.0, 22.0);
  std::string o;
  o += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" +
       std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
       "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"" + num(font) + "\">\n";
  o += "<title>" + esc(f.title) + "</title>\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o += "<text x=\"" + num(W / 2) + "\" y=\"" + num(1.6 * font) + "\" text-anchor=\"middle\" font-size=\"" +
       num(1.15 * font) + "\">" + esc(f.title) + "</text>\n";
  const std::size_t n = std::max<std::size_t>(1, f.panels.size());
  const double top = 3.2 * font, cell_w = W / static_cast<double>(n);
  for (std::size_t k = 0; k < f.panels.size(); ++k) {
    const Panel& p = f.panels[k];
    // Legend rows under the plot: as many as the labels need at this width.
    const double px0 = k * cell_w + 5.0 * font, px1 = (k + 1) * cell_w - 1.2 * font;
    // Legend entries flow left to right and wrap; each as wide as its label needs (text width
    // estimated at 0.62 em per character, the sample line 1.8 em, a 1.5 em gap).
    std::vector<std::pair<double, int>> entry_at;  // x offset and row of each labelled series
    {
      double x = 0;
      int row = 0;
      for (const auto& s : p.series) {
        if (s.label.empty()) continue;
        const double wd = (2.3 + 0.62 * static_cast<double>(s.label.size()) + 1.5) * font;
        if (x > 0 && x + wd > px1 - px0) x = 0, ++row;
        entry_at.push_back({x, row});
        x += wd;
      }
    }
    const int legend_rows = entry_at.empty() ? 0 : entry_at.back().second + 1;
    const double py0 = top + 2.2 * font, py1 = H - 3.2 * font - legend_rows * 1.4 * font;
    Range xr, yr;
    for (const auto& s : p.series)
      for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
        if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) xr.add(s.x[i]), yr.add(s.y[i]);
    if (const auto shared = shared_y_range(f)) yr.add(shared->lo), yr.add(shared->hi);
    xr.pad();
    yr.pad();
    auto X = [&](double v) { return px0 + (v - xr.lo) / (xr.hi - xr.lo) * (px1 - px0); };
    auto Y = [&](double v) { return py1 - (v - yr.lo) / (yr.hi - yr.lo) * (py1 - py0); };
    char attrs[512];
    std::snprintf(attrs, sizeof attrs,
                  " data-x0=\"%.17g\" data-x1=\"%.17g\" data-y0=\"%.17g\" data-y1=\"%.17g\" data-px0=\"%.17g\""
                  " data-px1=\"%.17g\" data-py0=\"%.17g\" data-py1=\"%.17g\"",
                  xr.lo, xr.hi, yr.lo, yr.hi, px0, px1, py0, py1);
    o += "<g class=\"panel\" id=\"panel" + std::to_string(k) + "\"" + attrs + ">\n";
    std::string head = p.letter.empty() ? p.title : p.title.empty() ? p.letter : p.letter + "  " + p.title;
    if (!head.empty())
      o += "<text x=\"" + num(px0) + "\" y=\"" + num(top + 0.8 * font) + "\" font-weight=\"bold\">" + esc(head) + "</text>\n";
    // Grid and ticks.
    const Ticks tx = nice_ticks(xr.lo, xr.hi, std::max(3, static_cast<int>((px1 - px0) / (7.0 * font))));
    const Ticks ty = nice_ticks(yr.lo, yr.hi, std::max(3, static_cast<int>((py1 - py0) / (3.0 * font))));
    double mx = 0, my = 0;
    for (double v : tx.values) mx = std::max(mx, std::fabs(v));
    for (double v : ty.values) my = std::max(my, std::fabs(v));
    o += "<g class=\"grid\" stroke=\"#dddddd\" stroke-width=\"1\">\n";
    for (double v : tx.values) o += "<line x1=\"" + num(X(v)) + "\" y1=\"" + num(py0) + "\" x2=\"" + num(X(v)) + "\" y2=\"" + num(py1) + "\"/>\n";
    for (double v : ty.values) o += "<line x1=\"" + num(px0) + "\" y1=\"" + num(Y(v)) + "\" x2=\"" + num(px1) + "\" y2=\"" + num(Y(v)) + "\"/>\n";
    o += "</g>\n<g class=\"ticks\" fill=\"#222222\">\n";
    for (double v : tx.values)
      o += "<text x=\"" + num(X(v)) + "\" y=\"" + num(py1 + 1.2 * font) + "\" text-anchor=\"middle\">" +
           esc(format_tick(v, tx.step, mx)) + "</text>\n";
    for (double v : ty.values)
      o += "<text x=\"" + num(px0 - 0.4 * font) + "\" y=\"" + num(Y(v) + 0.35 * font) + "\" text-anchor=\"end\">" +
           esc(format_tick(v, ty.step, my)) + "</text>\n";
    o += "</g>\n";
    o += "<rect x=\"" + num(px0) + "\" y=\"" + num(py0) + "\" width=\"" + num(px1 - px0) + "\" height=\"" +
         num(py1 - py0) + "\" fill=\"none\" stroke=\"#333333\"/>\n";
    o += "<text class=\"xlabel\" x=\"" + num(0.5 * (px0 + px1)) + "\" y=\"" + num(py1 + 2.4 * font) +
         "\" text-anchor=\"middle\">" + esc(units(p.x_label)) + "</text>\n";
    o += "<text class=\"ylabel\" transform=\"translate(" + num(px0 - 3.9 * font) + "," + num(0.5 * (py0 + py1)) +
         ") rotate(-90)\" text-anchor=\"middle\">" + esc(units(p.y_label)) + "</text>\n";
    // Series, clipped to the plot box.
    o += "<clipPath id=\"clip" + std::to_string(k) + "\"><rect x=\"" + num(px0) + "\" y=\"" + num(py0) +
         "\" width=\"" + num(px1 - px0) + "\" height=\"" + num(py1 - py0) + "\"/></clipPath>\n";
    o += "<g clip-path=\"url(#clip" + std::to_string(k) + ")\" fill=\"none\" stroke-width=\"1.6\" stroke-linejoin=\"round\">\n";
    int legend_i = 0;
    std::string legend;
    for (std::size_t si = 0; si < p.series.size(); ++si) {
      const Series& s = p.series[si];
      const std::string col = rgb(s.color >= 0 ? s.color : static_cast<int>(si));
      const char* dash = s.style == Series::Style::Dashed ? " stroke-dasharray=\"7 4\""
                         : s.style == Series::Style::Dotted ? " stroke-dasharray=\"1.5 3\""
                                                            : "";
      std::string pts;
      pts.reserve(s.x.size() * 16);
      for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        pts += num(X(s.x[i])) + "," + num(Y(s.y[i])) + " ";
      }
      o += "<polyline data-series=\"" + esc(s.label) + "\" stroke=\"" + col + "\"" + dash + " points=\"" + pts + "\"/>\n";
      if (s.label.empty()) continue;
      const double lx = px0 + entry_at[legend_i].first;
      const double ly = py1 + 3.6 * font + entry_at[legend_i].second * 1.4 * font;
      legend += "<line x1=\"" + num(lx) + "\" y1=\"" + num(ly - 0.35 * font) + "\" x2=\"" + num(lx + 1.8 * font) +
                "\" y2=\"" + num(ly - 0.35 * font) + "\" stroke=\"" + col + "\" stroke-width=\"2\"" + dash + "/>\n";
      legend += "<text x=\"" + num(lx + 2.3 * font) + "\" y=\"" + num(ly) + "\">" + esc(s.label) + "</text>\n";
      ++legend_i;
    }
    o += "</g>\n<g class=\"legend\">\n" + legend + "</g>\n</g>\n";
  }
  o += "</svg>\n";
  return o;
}

void write_figure_svg(const Figure& f, int width, int height, const std::string& path) {
  write_file_atomic(path, figure_svg(f, width, height));
}

}  // namespace gmslab::ui
