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

// The panel: its own state; "Send model to plant" puts the identified scenario into
// plant_request (the app passes its pending scenario request). Knows nothing else of the app.
void draw_identify_panel(IdentifyState& st, std::optional<Scenario>& plant_request);

// What the panel's fields hold: the session's IdentifySettings (core/io/session_io.hpp), so the
// window saves and restores exactly what the panel shows.
using IdentifyInputs = IdentifySettings;

// The panel's actions without drawing (scripted use and tests), on the panel's own state only:
// start a run on the worker thread; busy() also collects a finished run; the report of the last
// finished run (nullptr if none); the last run's error ("cancelled" after cancel()); send the
// identified model to the plant (into plant_request: the app's pending scenario request, applied
// by apply_pending like any UI edit).
void identify_start(IdentifyState& st, const IdentifyInputs& in);
// The panel's fields are read and set (without running: the records are loaded and shown on the
// next frame; a run in progress is left alone) by identify_settings / apply_identify_settings
// (ui/panel_state.hpp), as the session does.
// The EMPS benchmark's files when ../shared/data/emps (or $GMSLAB_SHARED/data/emps) has them:
// training DATA_EMPS.csv, validation DATA_EMPS_PULSES.csv, mask edges pulse_code:0.005:0.060 (the
// README's command); nullopt otherwise.
std::optional<IdentifyInputs> emps_example();
bool identify_busy(IdentifyState& st);
void identify_cancel(IdentifyState& st);
const ident::IdentReport* identify_report(const IdentifyState& st);
std::string identify_error(const IdentifyState& st);
void identify_send_to_plant(IdentifyState& st, std::optional<Scenario>& plant_request);

}  // namespace gmslab::ui
