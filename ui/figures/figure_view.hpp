// gmslab ui: draws a paper-style figure (core/figures/figure.hpp) with the plot widget: the
// figure title and caption on top, the panels side by side, each with its letter, title, axis
// labels with units, legend and the series' line styles (solid / dashed / dotted).
#pragma once

#include <optional>

#include "core/figures/figure.hpp"

namespace gmslab::ui {

// The y range every panel of a shared_y figure shows: the union of the panels' finite data (none
// for other figures or without data). The window's PNG and the SVG use the same range.
struct YRange {
  double lo, hi;
};
std::optional<YRange> shared_y_range(const Figure& f);

// Fills the current window's remaining content region. interactive = false for headless PNGs.
void draw_figure(const Figure& f, bool interactive = false);

}  // namespace gmslab::ui
