// gmslab ui: the application frame, shared by the GLFW window and the OSMesa headless renderer.
//
// The UI is a function of AppState, re-run every frame by draw_frame(). Widgets never change the
// simulation directly: they record PendingRequests, and apply_pending() applies them all at one
// point of the frame (MuJoCo's simulate/ pattern), after which the running simulation advances by
// view.speed simulated seconds per wall-clock second. The frame function knows nothing of GLFW or
// OSMesa: the host calls ImGui::NewFrame(), draw_frame(), ImGui::Render().
//
// Panels (tabs) are listed in ui/panels.cpp; see ui/panels.hpp for how to add one.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/io/session_io.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/phases.hpp"
#include "core/sim/scenario.hpp"
#include "ui/frame_policy.hpp"
#include "ui/panel_state.hpp"
#include "ui/plant/plant_view.hpp"

namespace gmslab::ui {

// What the user chose to see; saved in sessions (core/io/session_io.hpp).
using gmslab::ViewSettings;

// UI edits waiting to be applied (apply_pending). Each field is one request.
struct PendingRequests {
  std::optional<Scenario> scenario;     // replace the scenario (drive, run: restarts the run)
  std::optional<ModelParams> friction;  // live friction edit (keeps the run going)
  std::optional<Plant> plant;           // live plant edit
  std::optional<ModelParams> compare;   // set or edit the overlay model
  bool clear_compare = false;           // remove the overlay
  bool reset = false;                   // back to t = 0
  bool run = false, pause = false;
  std::string load_path;                // non-empty: load this scenario file
  std::string save_path;                // non-empty: save the scenario (atomic)
  bool save_confirmed = false;          // the user agreed to replace an existing save_path
  bool undo = false, redo = false;      // one step back / forward in the edit history
  bool rerun = false;                   // back to t = 0 and run (F5)
  bool from_history = false;            // these requests are an undo / redo (not recorded again)
};

// What an edit changes, for undo / redo (ui/app_files.hpp).
struct EditSnapshot {
  Scenario scenario;
  std::string scenario_path;
  std::optional<ModelParams> compare;
  bool operator==(const EditSnapshot&) const = default;
};
struct EditHistory {
  std::vector<EditSnapshot> undo, redo;
  bool gesture_open = false;  // an active widget's edits are already recorded as one step
  static constexpr std::size_t kMaxSteps = 200;
};

// Native key codes the host maps for shortcuts ImGui 1.86 has no named key for (GLFW codes in
// the window; tests pick their own). -1: not mapped.
struct ShortcutKeys {
  int s = -1, f5 = -1;
};

// The built-in file browser (File > Open..., Save as...).
struct FileBrowserState {
  bool open_request = false;  // open the popup next frame
  bool saving = false;        // Save as (else Open)
  std::string dir;            // folder listed
  std::string name;           // file name typed or picked
  std::string error;          // why the folder could not be listed
};

// A one-body simulation plus the stick / slip phases of its trace (computed in core from the whole
// trace).
struct LiveRun {
  std::unique_ptr<AssemblySimulation> sim;  // a one-body run (one_body_simulation)
  PhaseSeries phase_series;
  // The phase (0 = stick, 1 = slip) of every sample of sim->trace() for this threshold; a new
  // threshold reclassifies the whole trace. Empty without a simulation.
  std::span<const std::uint8_t> phases(double slip_velocity);
};

struct AppState {
  std::string scenario_path;        // the path field (load / save)
  Scenario scenario;                // the scenario as edited: what "save" writes
  LiveRun main;                     // the live run of `scenario`
  std::optional<ModelParams> compare;  // overlay model driven by the same input
  // The overlay takes the main model's shared parameters (F_s, F_c, V_s, where both models have
  // them) whenever the main model changes, so two models compare at the same Stribeck curve.
  bool overlay_follows_shared = false;
  LiveRun overlay;                  // its run (sim null when compare is empty)
  bool running = false;
  bool sim_limited = false;         // the step budget per frame capped the speed
  ViewSettings view;
  // The one status line (under every tab, when not empty): the last error reported, named by its
  // panel and kind ("Simulation: error: load failed: ..."), or the last note ("saved PATH").
  std::string status;
  std::optional<ErrorKind> status_kind;  // the kind of the error on the status line; none: a note
  std::optional<Panel> status_panel;     // the panel of that error
  // The Simulation panel's error: a rejected load, save or edit, or why the run stopped.
  std::string error;
  double frame_dt = 1.0 / 60.0;     // wall-clock seconds of this frame (host sets it)
  // What the window measures of itself (the host sets it; 0: not measured, nothing shown): the
  // time to build and draw the last frame [ms] and the frames drawn in the last wall second. Shown
  // at the right of the status line.
  struct FramePerf {
    double frame_ms = 0.0;
    int fps = 0;
  } perf;
  std::size_t max_steps_per_frame = 400000;  // keeps the window responsive
  // Memory bound of each live run's trace (main and overlay) [bytes]: a longer run is kept as
  // min/max per time bucket (TraceOptions, core/sim/simulation.hpp). Set before loading.
  std::size_t history_bytes = kHistoryBytes;
  static constexpr std::size_t kHistoryBytes = std::size_t{64} << 20;
  PendingRequests pending;
  int generation = 0;               // bumped when the scenario is replaced (editors resync)
  int select_tab = 2;               // frames left to force view.tab as the selected tab
  // The scenario as last loaded or saved, and the file written last: unsaved changes and
  // "replace?" questions are judged against them (ui/app_files.hpp).
  Scenario clean_scenario;
  std::string clean_path, last_saved_path;
  std::string confirm_replace;      // non-empty: ask whether to replace this file
  EditHistory history;
  ShortcutKeys keys;
  FileBrowserState browser;

  // Each panel's state (ui/panel_state.hpp), typed.
  SimPanelState sim_panel;
  FiguresState figures;
  DesignViewState design;
  IdentifyState identify;
  PlantPanelState plant;  // the Plant panel's own assembled plant and run (ui/plant/plant_view.hpp)

  // Errors reach the user in one place: every failure is reported here, with its panel. The
  // error is shown in that panel (its error field) and on the status line.
  void report(Panel p, ErrorKind k, const std::string& what);
  // The kind of `e` (Internal unless a gmslab::Error); the message is "context: what".
  void report(Panel p, const std::exception& e, const std::string& context);
  void note(const std::string& text);  // a status message that is not an error
  void clear_error(Panel p);           // the panel's error is gone (and from the status line)
  // Puts a panel's own error field (set by a panel that does not take the app: Figures, Design,
  // Identify) on the status line when it changed; the panel table calls it after each draw.
  void forward_error(Panel p);

 private:
  std::array<std::string, kPanelCount> on_status_{};  // per panel, the error last put on the line
};

// Folder of the preset files (gmslab::presets_dir, core/io/preset_io.hpp): env GMSLAB_PRESETS,
// else the source tree's presets/ when it exists, else the installed PREFIX/share/gmslab/presets.
std::string presets_dir();
// Builds the state for a scenario (validated: throws InputError). path may be empty.
void load_scenario_into(AppState& s, const Scenario& sc, const std::string& path);
// The overlay's parameters with the keys it shares with `main` among F_s, F_c, V_s copied over.
ModelParams with_shared_parameters(const ModelParams& overlay, const ModelParams& main);
// The scenario as it is now counts as saved (after a load or a save).
void mark_clean(AppState& s);
// Applies every pending request (errors go to s.status / s.error, never thrown).
void apply_pending(AppState& s);
// Advances the running simulation(s) by s.view.speed * s.frame_dt simulated seconds.
void advance(AppState& s);
// Runs both simulations up to simulated time t (t < 0: to the end). Throws SimulationError.
void run_until(AppState& s, double t);
// The session of the current state, and the state restored from a session (throws InputError
// when its scenario or overlay model is invalid; nothing changes then).
Session make_session(const AppState& s);
void restore_session(AppState& s, const Session& session);
// One frame: draws the main window with its panels (full display), then apply_pending + advance.
void draw_frame(AppState& s);

// What changes in the next frame without input, for the frame policy (ui/frame_policy.hpp): the
// Simulation run, the Plant run while its tab is shown, an identification at work (collecting a
// finished one), a design waiting for its computation or a tab being selected (animating), a text
// field with the keyboard (ImGui's io, when there is a context).
FrameActivity frame_activity(AppState& s);

// The run the active tab shows: the Plant tab's on the Plant tab, else the Simulation tab's.
struct ActiveRun {
  bool running = false;
  double time_s = 0.0;  // its simulated time (0 without a run)
};
ActiveRun active_run(const AppState& s);
// One line of the window's status report (GMSLAB_UI_STATUS): {"frames": N, "tab": "plant",
// "running": true, "run_time_s": T} - frames drawn so far, the active tab (lower case), the active
// run (active_run) - without the newline.
std::string ui_status_json(const AppState& s, long long frames);

// What `gmslab --open PRESET [--tab TAB] [--run]` asks of the window.
struct LaunchRequest {
  std::string preset;  // a path, or a shipped preset's name ("two_mass_drive" or "two_mass_drive.json")
  std::string tab;     // simulation | design | plant | identify (any case); "": the preset's own tab
  bool run = false;    // start the run of that tab (Simulation or Plant)
};
// The preset's file (gmslab::resolve_preset): `preset` when it exists, else
// presets_dir()/preset[.json]. Throws InputError naming --open, the path tried, the closest shipped
// preset and all of them.
std::string resolve_preset(const std::string& preset);
// Checks the request without a window (throws InputError naming what is wrong and how to fix it):
// the preset loads; the tab is one of the four; an assembled plant (schema_version 2) opens in the
// Plant or Design tab; --run goes with the Simulation or Plant tab. Returns the request with the
// preset's path resolved and the tab named as in the tab bar ("Plant"; default: Plant for an
// assembled plant, else Simulation).
LaunchRequest check_launch(const LaunchRequest& r);
// Opens a checked request: a one-body scenario becomes the Simulation tab's scenario (and the
// Plant tab's plant when that tab is asked for), an assembled plant the Plant tab's; selects the
// tab; starts its run when asked. Throws InputError when the preset does not load.
void apply_launch(AppState& s, const LaunchRequest& checked);

}  // namespace gmslab::ui
