// gmslab ui: writing a Figure (a plot of the window, a Figures-tab figure) as PNG, SVG or CSV
// into the export folder, never over an existing file (name-2.svg, name-3.svg, ...).
#pragma once

#include <functional>
#include <string>

#include "core/figures/figure.hpp"

namespace gmslab::ui {

enum class ExportFormat { Png, Svg, Csv };
// How a host turns a Figure into a PNG file (throws on failure).
using PngWriter = std::function<void(const Figure&, const std::string& path)>;

// $GMSLAB_EXPORT_DIR, else ~/gmslab-exports.
std::string export_dir();
// A path in export_dir() for `name` (sanitised) + extension that does not exist yet.
std::string fresh_export_path(const std::string& name, const std::string& extension);
// Writes the figure; returns "wrote PATH" or "export failed: why" (never throws). PNG needs
// `png` (else the message says so). Size of PNG / SVG: 1600x1000.
std::string export_figure(const Figure& f, ExportFormat format, const PngWriter& png);

}  // namespace gmslab::ui
