// gmslab ui: a Figure (core/figures/figure.hpp) as an SVG document - the vector twin of the PNG
// the headless renderer draws from the same data: the same panels left to right, the same
// palette, line styles, nice ticks, axis labels with units; text as <text>, every series as one
// unbroken <polyline> of all its points, the legend under each panel (never over the data).
// Each panel's <g> carries its data ranges (data-x0, data-x1, data-y0, data-y1) and plot box
// (data-px0, data-px1, data-py0, data-py1) so the drawing can be checked against the data.
#pragma once

#include <string>

#include "core/figures/figure.hpp"

namespace gmslab::ui {

std::string figure_svg(const Figure& f, int width, int height);
// Writes figure_svg atomically (core/io/atomic_file.hpp).
void write_figure_svg(const Figure& f, int width, int height, const std::string& path);

}  // namespace gmslab::ui
