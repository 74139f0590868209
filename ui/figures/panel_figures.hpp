// gmslab ui: the Figures panel - the seed paper's figures recomputed from the presets.
#pragma once

#include "ui/panel_state.hpp"

namespace gmslab::ui {

// presets: the folder the figures are recomputed from (the app passes presets_dir()).
void draw_figures_panel(FiguresState& f, const std::string& presets);

}  // namespace gmslab::ui
