// gmslab core: the figure set that `gmslab figures` renders. Each figure is built by running its
// preset(s) (presets/*.json) and extracting the series the paper plots.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "core/figures/figure.hpp"

namespace gmslab {

// Ids of every figure, in display order (e.g. "fig2a_presliding").
std::vector<std::string> figure_ids();
// Builds one figure; presets are read from `preset_dir`. Throws InputError for an unknown id.
Figure make_figure(const std::string& id, const std::string& preset_dir);
// All series of a figure in long form: panel,series,x,y with the axis labels (units) in a comment
// header line per panel.
void write_figure_csv(const Figure& f, std::ostream& out);

}  // namespace gmslab
