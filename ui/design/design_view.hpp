// gmslab ui: the root-locus design view (the "Design" panel). State and the widgets it is made of:
//   design_panel.cpp      the panel: controls (plant regime, desired roots, K, requirements,
//                         compensator, simulation) and the layout
//   design_locus.cpp      the root-locus canvas: zeta/wn grid, requirement shading, asymptotes,
//                         branches, poles (x) / zeros (o), draggable s_d, zero and pole, click a
//                         branch to read its gain, damping and all closed-loop poles
//   design_frequency.cpp  Bode (margins, crossovers, closed-loop magnitude) and Nyquist (critical
//                         point, encirclements) of the same loop, recomputed with the locus
//   design_hunting_map.cpp the hunting map: limit-cycle amplitude against the gain scale (stable
//                         solid, unstable dashed, fold), computed on a worker thread
//   design_responses.cpp  the linked responses: linear step response, nonlinear loop with the
//                         scenario's friction without and with compensation
// Every edit marks the state dirty; the panel recomputes everything (core/control/
// design_session.hpp: locus, design, step, both loops) once per frame when dirty.
#pragma once

#include <imgui.h>

#include <optional>
#include <string>
#include <vector>

#include "core/control/design_session.hpp"
#include "core/io/session_io.hpp"
#include "ui/panel_state.hpp"
#include "ui/plot/plot_transform.hpp"

namespace gmslab::ui {



// design_settings / apply_design_settings (the session's view of this state): ui/panel_state.hpp.

// zeta_min of an overshoot requirement [%]: OS = exp(-pi zeta / sqrt(1 - zeta^2)).
double zeta_for_overshoot(double overshoot_percent);

// The Design panel: its own state and the scenario it designs for (generation: the app's scenario
// generation; a new one resyncs the design's plant), and the Plant tab's assembled plant (null when
// none is loaded) for the plant source "assembly". Knows nothing of the app.
void draw_design_panel(DesignViewState& d, const Scenario& scenario, int generation,
                       const AssemblyScenario* assembly = nullptr);

// The end of an edit of the typed plant's numerator (den = false) or denominator: applied when the
// pair is valid (core/control/design_plant.hpp typed_plant), else d.num_error / d.den_error says
// why, naming the field, and the value in force stays (the field shows it). Returns whether applied.
bool apply_coefficient_edit(DesignViewState& d, bool den, const std::string& text);

void draw_design_locus(DesignViewState& d, ImVec2 size);
void draw_design_responses(const DesignViewState& d, ImVec2 size);
// Bode (open loop with margins, closed-loop magnitude) beside the Nyquist plot (ui/design/design_frequency.cpp).
void draw_design_frequency(DesignViewState& d, ImVec2 size);
void draw_design_nyquist(DesignViewState& d, ImVec2 size);
// The hunting map beside the Nyquist plot (ui/design/design_hunting_map.cpp): orbit amplitude
// against the controller gain scale, from a background job. hunting_map_request starts (or queues)
// the job for the design just computed; hunting_map_poll takes over a finished one and starts the
// queued one (true while one runs); hunting_map_busy: a job runs or waits.
void draw_design_hunting_map(DesignViewState& d, ImVec2 size);
void hunting_map_request(DesignViewState& d);
bool hunting_map_poll(DesignViewState& d);
bool hunting_map_busy(const DesignViewState& d);

}  // namespace gmslab::ui
