// gmslab ui: where scenarios are saved, the edit history (undo / redo), keyboard shortcuts, the
// menu bar (File, Presets, Edit, Help) and a small built-in file browser.
//
// Shipped presets (presets_dir()) are never written: Save goes to the user's own folder
// (user_scenarios_dir()) unless the user picked a path there or elsewhere with "Save as...", and
// replacing an existing file asks first (except the file this window saved last).
#pragma once

#include <string>
#include <vector>

#include "ui/app.hpp"

namespace gmslab::ui {

// $GMSLAB_USER_DIR, else $XDG_CONFIG_HOME/gmslab/scenarios, else ~/.config/gmslab/scenarios.
std::string user_scenarios_dir();
// True when `path` lies inside presets_dir() (a shipped preset, never overwritten).
bool is_shipped_preset(const std::string& path);
// Where Save writes: the scenario's own file unless it is empty or a shipped preset; then
// user_scenarios_dir()/<file name of the preset, or the scenario name>.json.
std::string save_target(const AppState& s);
// The scenario differs from the file it was loaded from or last saved to.
bool has_unsaved_changes(const AppState& s);
// "gmslab - NAME * (PATH)": the star marks unsaved changes. On the Plant tab, and on the Design
// tab designing on the assembled plant, it names that plant (its name and path), not the other
// tabs' scenario.
std::string window_title(const AppState& s);

// The state an edit can go back to: the scenario, its file and the overlay model.
EditSnapshot snapshot(const AppState& s);
// Records the state before an edit (one record per drag gesture: consecutive edits while a widget
// stays active are one step). Clears the redo list.
void record_edit(AppState& s);
// Back / forward one edit; false when there is nothing to undo / redo. A friction or plant
// change keeps the run going; a drive, run-settings or file change restarts it.
bool undo(AppState& s);
bool redo(AppState& s);

// Space run/pause, Ctrl+S save, Ctrl+Z undo, Ctrl+Shift+Z / Ctrl+Y redo, F5 rerun from t = 0.
// Ignored while a text field has the keyboard. Records requests in s.pending.
void handle_shortcuts(AppState& s);
// The menu bar of the main window, the file browser and the "replace?" confirmation.
void draw_menu_bar(AppState& s);
void draw_file_dialogs(AppState& s);

// A preset found on disk: its file, name and description (from the JSON); shipped or the user's.
struct PresetEntry {
  std::string path, name, description;
  bool shipped = false;
  bool plant = false;  // schema 2: an assembled plant, opened in the Plant tab
};
// Shipped presets then the user's saved scenarios, each in preset_before order. Unreadable files
// are listed with the reason as their description.
std::vector<PresetEntry> list_presets();
// The menu's order: by the figure a preset's name starts with ("Fig. 2A: ...": figure 2, panel A;
// a comparison "... protocol ..." after the figure's own preset), then presets that name no
// figure; ties by file name with numbers compared as numbers (x1, x16, x100).
bool preset_before(const PresetEntry& a, const PresetEntry& b);

}  // namespace gmslab::ui
