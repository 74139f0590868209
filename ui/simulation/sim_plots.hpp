// gmslab ui: the live plots of the Simulation panel, 2 x 2 in the current region:
//   forces against time (friction F_f and the drive force), position against time,
//   friction force against displacement (hysteresis), velocity against time.
// The overlay model (if any) is drawn dashed in the same plots. With view.color_phases the main
// model's time traces are blue while sticking and orange while slipping.
#pragma once

#include "ui/app.hpp"

namespace gmslab::ui {

void draw_simulation_plots(AppState& s);

}  // namespace gmslab::ui
