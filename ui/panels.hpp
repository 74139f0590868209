// gmslab ui: the panels (tabs) of the main window.
//
// To add a panel:
//   1. write ui/panel_<name>.cpp (+ .hpp) with `void draw_<name>_panel(YourState& st, ...)` (one
//      file per panel): its state is a struct in ui/panel_state.hpp, held by AppState as a typed
//      member; pass it only what it needs of the app (the scenario, a pending request to fill -
//      never change s.main directly while drawing). The panel does not include the app;
//   2. add one line to the list in ui/panels.cpp (a lambda from AppState to those arguments).
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

}  // namespace gmslab::ui
