// gmslab ui: draws a paper-style figure (core/figures/figure.hpp) with the plot widget: the
// figure title and caption on top, the panels side by side, each with its letter, title, axis
// labels with units, legend and the series' line styles (solid / dashed / dotted).
#pragma once

#include "core/figures/figure.hpp"

namespace gmslab::ui {

// Fills the current window's remaining content region. interactive = false for headless PNGs.
void draw_figure(const Figure& f, bool interactive = false);

}  // namespace gmslab::ui
