// gmslab ui: the design view's linked responses (see ui/design_view.hpp): the linear closed-loop
// step response and the loop simulated with the scenario's friction, without and with
// compensation, against the reference.
#include <imgui.h>

#include <cstdio>

#include "ui/design_view.hpp"
#include "ui/plot.hpp"

namespace gmslab::ui {

void draw_design_responses(const DesignViewState& d, ImVec2 size) {
  const control::DesignOutputs& o = d.out;
  const float w = 0.5f * (size.x - ImGui::GetStyle().ItemSpacing.x);
  PlotOptions lin;
  lin.title = "Linear closed loop: unit step response";
  if (BeginPlot("##design_step", ImVec2(w, size.y), lin)) {
    SetupAxesSI("t", "s", "y / r", "-");
    if (!o.step.t.empty()) SetupFitRangeX(0.0, o.step.t.back());
    PlotLine("linear loop", o.step.t.data(), o.step.y.data(), o.step.t.size(), {.color = 0, .x_sorted = true});
    EndPlot();
  }
  ImGui::SameLine();
  static char title[160];
  std::snprintf(title, sizeof title, "With friction (%s): position vs reference",
                d.in.scenario.friction.model.c_str());
  PlotOptions nl;
  nl.title = title;
  if (BeginPlot("##design_nonlinear", ImVec2(w, size.y), nl)) {
    SetupAxesSI("t", "s", "x", "m");
    const auto& a = o.loop_plain;
    const auto& b = o.loop_compensated;
    PlotLine("reference", a.t.data(), a.r.data(), a.t.size(), {.color = 6, .line = LineStyle::Dashed, .x_sorted = true});
    PlotLine("no compensation", a.t.data(), a.x.data(), a.t.size(), {.color = 1, .x_sorted = true});
    const std::string comp = std::string(control::to_string(d.in.compensation)) + " feedforward";
    PlotLine(comp.c_str(), b.t.data(), b.x.data(), b.t.size(), {.color = 2, .x_sorted = true});
    EndPlot();
  }
}

}  // namespace gmslab::ui
