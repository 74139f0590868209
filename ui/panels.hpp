// gmslab ui: the panels (tabs) of the main window.
//
// To add a panel:
//   1. write ui/panel_<name>.cpp with `void draw_<name>_panel(AppState& s)` (one file per panel);
//      keep its own state as a typed member of AppState (its struct in ui/panel_state.hpp) and
//      record changes to the simulation
//      as `s.pending` requests (never change s.main directly while drawing);
//   2. declare the function below;
//   3. add one line to the list in ui/panels.cpp.
// `gmslab render --view NAME` selects a panel by its name (case-insensitive; "auto" = the first).
#pragma once

#include <vector>

#include "ui/app.hpp"

namespace gmslab::ui {

struct PanelEntry {
  const char* name;           // tab label and --view name, e.g. "Simulation"
  const char* tooltip;        // one line shown when hovering the tab
  void (*draw)(AppState& s);  // draws the tab's content (the full remaining region)
};

// The panels, in tab order.
const std::vector<PanelEntry>& panels();
// The panel whose name matches `view` (case-insensitive; "auto" or "": the first). nullptr if none.
const PanelEntry* find_panel(const char* view);

void draw_simulation_panel(AppState& s);
void draw_figures_panel(AppState& s);
void draw_design_panel(AppState& s);

}  // namespace gmslab::ui
