// gmslab ui: the Identify panel. Load a measured CSV (and optionally a validation CSV), pick the
// base model and element count, run the fit and the residual loop on a worker thread (progress bar,
// cancel), see the fit over the data and the residual round by round (the report figure) and the
// rounds table, and send the identified model to the plant of the Simulation panel.
#pragma once

#include <optional>
#include <string>

#include "core/ident/loop.hpp"
#include "core/io/session_io.hpp"
#include "ui/panel_state.hpp"

namespace gmslab::ui {

struct AppState;

// The panel: its own state; "Send model to plant" puts the identified scenario into
// plant_request (the app passes its pending scenario request). Knows nothing else of the app.
void draw_identify_panel(IdentifyState& st, std::optional<Scenario>& plant_request);

// What the panel's fields hold: the session's IdentifySettings (core/io/session_io.hpp), so the
// window saves and restores exactly what the panel shows.
using IdentifyInputs = IdentifySettings;

// The panel's actions without drawing (scripted use and tests): start a run on the worker
// thread; busy() also collects a finished run; the report of the last finished run (nullptr if
// none); the last run's error ("cancelled" after cancel()); send the identified model to the plant
// (a pending scenario request, applied by apply_pending like any UI edit).
void identify_start(AppState& s, const IdentifyInputs& in);
// The panel's fields (defaults when the panel was never shown); the session saves them.
IdentifySettings identify_settings(const AppState& s);
// Fills the panel's fields without running (the records are loaded and shown on the next frame);
// a run in progress is left alone. The session restores the fields with it.
void identify_set_inputs(AppState& s, const IdentifyInputs& in);
// The EMPS benchmark's files when ../shared/data/emps (or $GMSLAB_SHARED/data/emps) has them:
// training DATA_EMPS.csv, validation DATA_EMPS_PULSES.csv; nullopt otherwise.
std::optional<IdentifyInputs> emps_example();
bool identify_busy(AppState& s);
void identify_cancel(AppState& s);
const ident::IdentReport* identify_report(AppState& s);
std::string identify_error(AppState& s);
void identify_send_to_plant(AppState& s);

}  // namespace gmslab::ui
