// gmslab ui: the Identify panel. Load a measured CSV (and optionally a validation CSV), pick the
// base model and element count, run the fit and the residual loop on a worker thread (progress bar,
// cancel), see the fit over the data and the residual round by round (the report figure) and the
// rounds table, and send the identified model to the plant of the Simulation panel.
#pragma once

#include "ui/app.hpp"

namespace gmslab::ui {

void draw_identify_panel(AppState& s);

}  // namespace gmslab::ui
