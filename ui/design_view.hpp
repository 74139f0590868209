// gmslab ui: the root-locus design view (the "Design" panel). State and the widgets it is made of:
//   design_panel.cpp      the panel: controls (plant regime, desired roots, K, requirements,
//                         compensator, simulation) and the layout
//   design_locus.cpp      the root-locus canvas: zeta/wn grid, requirement shading, asymptotes,
//                         branches, poles (x) / zeros (o), draggable s_d, zero and pole, click a
//                         branch to read its gain, damping and all closed-loop poles
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
#include "ui/app.hpp"
#include "ui/plot_transform.hpp"

namespace gmslab::ui {

struct DesignViewState {
  int generation = -1;               // scenario generation the inputs were taken from
  control::DesignInputs in;          // what the design is computed from
  control::DesignOutputs out;        // the last computation
  bool dirty = true;
  double compute_ms = 0.0;           // wall time of the last computation [ms]
  bool use_K = false;                // target a desired error constant (else the usable maximum)
  double K = 1000.0;                 // desired error constant
  int reference = 2;                 // 0 step, 1 ramp, 2 sine
  double amplitude = 0.01;           // step height / sine amplitude [m]
  double slope = 0.01;               // ramp velocity [m/s]
  double frequency = 2.0;            // sine frequency [Hz]
  double max_overshoot = 10.0;       // requirement [%] -> zeta_min
  double settling_time = 0.15;       // requirement (2 % band) [s] -> sigma_min = 4 / Ts
  // Root-locus canvas
  std::optional<control::ViewBox> view;  // user zoom (none: fit the computed locus)
  enum class Drag { None, Root, Zero, Pole, Pan } drag = Drag::None;
  bool picked = false;               // a clicked point of a branch
  double picked_k = 0.0;
  control::cplx picked_s;
  std::vector<control::cplx> picked_poles;
  PlotTransform canvas;              // data <-> pixel map of the canvas in the last frame
};

// The view's settings as saved in a session, and back (marks the design dirty). Defaults agree:
// design_settings(DesignViewState{}) == DesignSettings{}.
DesignSettings design_settings(const DesignViewState& d);
void apply_design_settings(DesignViewState& d, const DesignSettings& s);

// zeta_min of an overshoot requirement [%]: OS = exp(-pi zeta / sqrt(1 - zeta^2)).
double zeta_for_overshoot(double overshoot_percent);

void draw_design_locus(DesignViewState& d, ImVec2 size);
void draw_design_responses(const DesignViewState& d, ImVec2 size);

}  // namespace gmslab::ui
