// gmslab ui: each panel's state, held by AppState as typed members (ui/app.hpp) - no string-keyed
// slots. A panel's settings that a session saves are one struct each (DesignSettings:
// core/control/design_settings.hpp; IdentifySettings: core/io/session_io.hpp), shared by the panel, the session file and the headless
// renderer. Pure data: no ImGui, no app.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/control/design_session.hpp"
#include "core/error.hpp"
#include "ui/param_editor.hpp"
#include "core/figures/figure.hpp"
#include "core/ident/dataset.hpp"
#include "core/ident/loop.hpp"
#include "core/io/session_io.hpp"
#include "core/sim/scenario.hpp"
#include "ui/plot/plot_transform.hpp"

namespace gmslab::ui {

// The window's panels, as errors name them (AppState::report: an error shows in its panel and on
// the one status line).
enum class Panel { Simulation, Figures, Design, Identify };
inline constexpr int kPanelCount = 4;
inline const char* to_string(Panel p) {
  switch (p) {
    case Panel::Simulation: return "Simulation";
    case Panel::Figures: return "Figures";
    case Panel::Design: return "Design";
    case Panel::Identify: return "Identify";
  }
  return "?";
}
// The kind of a caught exception: its ErrorKind for a gmslab::Error, else Internal (a bug).
inline ErrorKind error_kind_of(const std::exception& e) {
  const auto* t = dynamic_cast<const Error*>(&e);
  return t ? t->kind() : ErrorKind::Internal;
}

// The Simulation panel: a scratch copy of the scenario being edited (a valid edit becomes a
// pending request; an invalid one stays here with its message shown inline).
struct SimPanelState {
  int generation = -1;
  std::string path;
  ModelParams friction, compare;
  Plant plant;
  Drive drive;
  RunSettings run;
  std::string friction_msg, plant_msg, drive_msg, compare_msg;
  FieldMarks marks;  // the rejected field, if any (shows the value in force and why)
};

// The Figures panel.
struct FiguresState {
  std::string id;       // figure shown
  Figure figure;        // its data
  std::string error;    // why it could not be built
  ErrorKind error_kind = ErrorKind::Internal;
};

// The Design view's hunting map (core/control/limit_cycles.hpp through compute_design: periodic
// orbits of the loop without compensation and their branch over the gain scale), computed on a
// worker thread so that dragging stays smooth. One job at a time: a design that changes while a
// job runs is queued (only the latest) and started when that job ends, whose result, superseded,
// is dropped. The worker writes `out` and then sets done.
struct HuntingMapJob {
  std::atomic<bool> done{false};
  int generation = 0;          // the design generation it computes
  control::DesignOutputs out;  // the worker's result (read once done)
  std::string error;           // an exception the job did not catch as a typed error
  std::thread thread;
  ~HuntingMapJob() {
    if (thread.joinable()) thread.join();
  }
};
struct HuntingMapState {
  int generation = 0;                           // bumped by each recomputation of the design
  std::optional<control::DesignInputs> queued;  // the latest design's inputs, not yet started
  int queued_generation = 0;
  std::shared_ptr<HuntingMapJob> job;         // the running job (null: none)
  std::optional<control::DesignOutputs> out;  // the map of the current design (null: computing)
  std::string error;                          // why there is none ("" when computing or shown)
};

// The Design panel (root-locus design view, ui/design/design_view.hpp).
struct DesignViewState {
  DesignSettings settings;           // what the user chose (the panel edits it; the session saves it)
  int generation = -1;               // scenario generation the inputs were taken from
  // What the design is computed from: the scenario, the dragged compensator and the locus zoom
  // (in.manual, in.locus_view) are the panel's own; every other field is derived from `settings`
  // (control::set_design_inputs) before each computation.
  control::DesignInputs in;
  control::DesignOutputs out;        // the last computation
  bool dirty = true;
  double compute_ms = 0.0;           // wall time of the last computation [ms]
  // Root-locus canvas
  // The user's zoom of the canvas is in.locus_view (none: fit the computed locus), kept once.
  enum class Drag { None, Root, Zero, Pole, Pan } drag = Drag::None;
  int drag_section = 0;              // which compensator section's zero / pole is dragged (0, 1)
  bool picked = false;               // a clicked point of a branch
  double picked_k = 0.0;
  control::cplx picked_s;
  std::vector<control::cplx> picked_poles;
  PlotTransform canvas;              // data <-> pixel map of the canvas in the last frame
  bool harmonic_balance = false;     // the Nyquist canvas shows H(jw) and -1/N (describing function)
  // Typed plant fields: the text being edited (the value in force, settings.plant.num / den, when
  // not being edited) and why the last edit was rejected ("" when it was not).
  std::string num_edit, den_edit, num_error, den_error;
  bool z_plane = true;               // with a sample time: the locus canvas shows the z-plane locus
  PlotTransform z_canvas;            // data <-> pixel map of the z-plane canvas (zoom: in.z_locus_view)
  HuntingMapState hunting_map;       // the hunting map beside the Nyquist plot (background job)
};

// The Identify panel (ui/identify/identify_panel.hpp).
struct IdentifyResult {
  ident::IdentReport report;
  ident::Dataset train, val;
  Figure figure;
};

// The worker: runs identify() on its own copies, reports progress under a mutex.
struct IdentifyJob {
  std::atomic<bool> cancel{false};
  std::atomic<bool> done{false};
  std::mutex m;
  ident::FitProgress progress;     // guarded by m
  std::string error;               // guarded by m
  ErrorKind error_kind = ErrorKind::Internal;  // guarded by m
  std::unique_ptr<IdentifyResult> result;  // guarded by m
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  std::thread thread;
  ~IdentifyJob() {
    cancel = true;
    if (thread.joinable()) thread.join();
  }
};

// The records as loaded for the preview (before a run), or why they could not be loaded.
struct IdentifyPreview {
  std::string key;  // the inputs it was loaded from
  ident::Dataset train, val;
  std::string error;
  ErrorKind error_kind = ErrorKind::Input;
  std::vector<std::string> notes;
};

struct IdentifyState : IdentifySettings {  // the fields are the session's settings
  std::unique_ptr<IdentifyJob> job;
  std::unique_ptr<IdentifyResult> result;
  IdentifyPreview preview;
  std::string error, status;
  ErrorKind error_kind = ErrorKind::Internal;  // of `error`
};

// Each panel's settings as a session saves them, and back. The app builds and restores the
// session through these alone (it includes no panel). Defaults agree:
// design_settings(DesignViewState{}) == DesignSettings{}. Applying design settings drops a
// dragged compensator, derives the inputs and marks the design dirty; applying identify settings
// leaves a run in progress (and its fields) alone.
inline const DesignSettings& design_settings(const DesignViewState& d) { return d.settings; }
void apply_design_settings(DesignViewState& d, const DesignSettings& s);
IdentifySettings identify_settings(const IdentifyState& st);
void apply_identify_settings(IdentifyState& st, const IdentifySettings& s);

}  // namespace gmslab::ui
