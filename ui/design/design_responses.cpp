// gmslab ui: the design view's linked responses (see ui/design/design_view.hpp): the linear closed-loop
// step response and the loop simulated with the scenario's friction, without and with
// compensation, against the reference.
#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"

namespace gmslab::ui {

namespace {
void metrics_table(const DesignViewState& d) {
  const auto& a = d.out.plain().metrics;
  const auto& b = d.out.compensated().metrics;
  ImGui::TextUnformatted("Loop metrics");
  if (d.out.plain().trace.t.empty() && d.out.compensated().trace.t.empty()) {
    // Nothing was simulated (no compensator, or the loops are switched off): no numbers to show.
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("no loop simulated: %s",
                        d.out.source == control::PlantSource::Typed ? "typed plant (no friction)"
                        : d.out.compensator                         ? "loops are off"
                                                                    : "no compensator (see the design)");
    ImGui::PopTextWrapPos();
    return;
  }
  if (!ImGui::BeginTable("##metrics", 3, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) return;
  ImGui::TableSetupColumn("metric");
  ImGui::TableSetupColumn("none");
  ImGui::TableSetupColumn(control::to_string(d.in.compensation));
  ImGui::TableHeadersRow();
  auto row = [](const char* name, double x, double y, double scale, const char* unit, const char* help) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::Text("%s [%s]", name, unit);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", help);
    for (double v : {x, y}) {
      ImGui::TableNextColumn();
      if (std::isfinite(v)) ImGui::Text("%.3g", v * scale);
      else ImGui::TextUnformatted("-");
    }
  };
  row("e_ss", a.steady_state_error, b.steady_state_error, 1e3, "mm", "mean error over the last 20 % of the run");
  row("max |e| tail", a.tail_max_error, b.tail_max_error, 1e3, "mm",
      "largest |r - x| over the last 20 % of the run (for ramps and sines: the error at reversals)");
  row("RMS e", a.rms_error, b.rms_error, 1e3, "mm", "root-mean-square tracking error over the run");
  row("overshoot", a.overshoot, b.overshoot, 1.0, "%", "step references only");
  row("settling", a.settling_time, b.settling_time, 1e3, "ms", "2 % band around the final value (step only)");
  // A limit cycle's numbers only mean something when the loop hunts: "-" otherwise.
  const auto if_hunting = [](const control::LoopMetrics& m, double v) { return m.hunting ? v : NAN; };
  row("cycle ampl.", if_hunting(a, a.cycle_amplitude), if_hunting(b, b.cycle_amplitude), 1e3, "mm",
      "limit cycle (hunting) half peak-to-peak; '-': the loop does not hunt");
  row("cycle period", if_hunting(a, a.cycle_period), if_hunting(b, b.cycle_period), 1e3, "ms",
      "limit cycle period; '-': the loop does not hunt");
  // Describing-function predictions beside the simulated cycle: the stick-slip hunting of an
  // integrating compensator (hunting.hpp; loop without compensation), and the velocity DF's cycle
  // of each loop (for a loop with integral action an unstable amplitude threshold; the compensated
  // loop's with F - F_hat when the feedforward is driven by the measured velocity).
  const control::HuntingCycle* hc = d.out.hunting ? d.out.hunting->hunting() : nullptr;
  row("DF ampl.", hc ? hc->amplitude : NAN, NAN, 1e3, "mm",
      "predicted hunting (stick-slip limit cycle) of the loop without compensation: describing function of the mass "
      "with its friction and the controller's fast part, driven by the integral force (triangle); half "
      "peak-to-peak of x, as 'cycle ampl.'. '-': no integrator, or no cycle predicted");
  row("DF period", hc ? hc->period : NAN, NAN, 1e3, "ms", "period of the predicted hunting; '-': none");
  const auto predicted = [](const std::optional<control::LimitCycleReport>& r) {
    const control::LimitCycle* p = nullptr;
    if (r)
      for (const auto& c : r->cycles)
        if (!p || (c.stable && !p->stable)) p = &c;
    return p;
  };
  const control::LimitCycle* pc = predicted(d.out.limit_cycles);
  const control::LimitCycle* pk = predicted(d.out.compensated().limit_cycles);
  const char* help = "velocity describing function of the friction, harmonic balance 1 + H(jw) N(a, w) = 0 with "
                     "H = s G / (1 + Gc G): a sinusoidal velocity never sticks, so this is the threshold cycle "
                     "(larger motions grow) rather than the hunting; with compensation driven by the measured "
                     "velocity N is that of F - F_hat (by the reference velocity: the friction's, the feedforward "
                     "being 0 at a constant set point); '-': no cycle predicted";
  const bool threshold = (pc && !pc->stable) || (pk && !pk->stable);
  row(threshold ? "DF threshold" : "DF vel. ampl.", pc ? pc->amplitude : NAN, pk ? pk->amplitude : NAN, 1e3, "mm", help);
  row(threshold ? "DF thr. period" : "DF vel. period", pc ? pc->period : NAN, pk ? pk->period : NAN, 1e3, "ms", help);
  ImGui::EndTable();
  ImGui::PushTextWrapPos(0.0f);  // the column is narrow: wrap, never clip
  if (hc) {
    ImGui::TextDisabled("DF hunting: %s", hc->valid ? "valid" : "OUTSIDE its validity");
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("integral force amplitude %.3g N, phase residual %.1f deg (limit %.0f), waveform error %.3f "
                        "(limit %.2f)",
                        hc->force_amplitude, hc->phase_residual * 57.29578, control::kHuntingPhaseLimit * 57.29578,
                        hc->waveform_error, control::kHuntingWaveformLimit);
  } else if (d.out.hunting) {
    ImGui::TextDisabled("DF hunting: none predicted");
  }
  if (pc)
    ImGui::TextDisabled("DF velocity: %s cycle%s", pc->stable ? "stable" : "unstable (amplitude threshold)",
                        pc->stable ? "" : ": larger motions grow");
  else if (d.out.limit_cycles)
    ImGui::TextDisabled("DF velocity: no cycle predicted");
  if (d.in.feedforward_source == control::FeedforwardSource::Measured && d.out.compensated().limit_cycles)
    ImGui::TextDisabled("DF with %s driven by the measured v (F - F_hat): %s", control::to_string(d.in.compensation),
                        !pk ? "no cycle predicted" : pk->stable ? "stable cycle" : "unstable (threshold) cycle");
  ImGui::PopTextWrapPos();
  if (d.out.source == control::PlantSource::Assembly && !d.out.loop_note.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("%s", d.out.loop_note.c_str());
    ImGui::PopTextWrapPos();
  }
}

// A typed plant has no friction to simulate: the loop plots' place says so (instead of empty axes).
bool typed_plant_note(const DesignViewState& d, ImVec2 size) {
  if (d.out.source != control::PlantSource::Typed) return false;
  ImGui::BeginChild("##typed_note", size, true);
  ImGui::TextUnformatted("Loop with friction: not simulated");
  ImGui::Separator();
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextUnformatted(
      "The plant is typed as num/den: a linear G(s) without friction and without a scenario, so there is no "
      "nonlinear loop to simulate (and no describing function). The linear closed-loop step at the left is "
      "this G(s) with the compensator.");
  ImGui::Spacing();
  ImGui::TextDisabled("For the loop with friction choose the plant source 'scenario (one body)' or 'assembled plant' (the "
                      "Plant tab's).");
  ImGui::PopTextWrapPos();
  ImGui::EndChild();
  return true;
}
}  // namespace

void draw_design_responses(const DesignViewState& d, ImVec2 size) {
  const control::DesignOutputs& o = d.out;
  const float table_w = ImGui::GetFontSize() * 17.0f;
  const float w = 0.5f * (size.x - table_w - 2 * ImGui::GetStyle().ItemSpacing.x);
  PlotOptions lin;
  lin.title = "Linear closed loop: unit step response";
  if (BeginPlot("##design_step", ImVec2(w, size.y), lin)) {
    SetupAxesSI("t", "s", "y / r", "-");
    if (!o.step.t.empty()) SetupFitRangeX(0.0, o.step.t.back());
    PlotLine("linear loop", o.step.t.data(), o.step.y.data(), o.step.t.size(), {.color = 0, .x_sorted = true});
    EndPlot();
  }
  ImGui::SameLine();
  if (typed_plant_note(d, ImVec2(w, size.y))) {
    ImGui::SameLine();
    ImGui::BeginChild("##design_metrics", ImVec2(0, size.y), false);
    metrics_table(d);
    ImGui::EndChild();
    return;
  }
  static char title[200];
  if (o.source == control::PlantSource::Assembly)
    std::snprintf(title, sizeof title, "Assembled plant: %s vs reference", o.port.output.c_str());
  else
    std::snprintf(title, sizeof title, "With friction (%s): position vs reference",
                  d.in.scenario.friction.model.c_str());
  PlotOptions nl;
  nl.title = title;
  const control::LoopUnits units = control::loop_units(o.source, o.port);
  const float gap = ImGui::GetStyle().ItemSpacing.y;
  const float h_pos = std::floor(0.55f * (size.y - gap));
  const auto& a = o.plain().trace;
  const auto& b = o.compensated().trace;
  const std::string comp = std::string(control::to_string(d.in.compensation)) + " feedforward" +
                           (d.in.feedforward_source == control::FeedforwardSource::Measured ? " (measured v)" : "");
  ImGui::BeginGroup();
  if (BeginPlot("##design_nonlinear", ImVec2(w, h_pos), nl)) {
    SetupAxesSI("t", "s", units.output == "m/s" ? "v" : "x", units.output.c_str());
    PlotLine("reference", a.t.data(), a.r.data(), a.t.size(), {.color = 6, .line = LineStyle::Dashed, .x_sorted = true});
    PlotLine("no compensation", a.t.data(), a.x.data(), a.t.size(), {.color = 1, .x_sorted = true});
    PlotLine(comp.c_str(), b.t.data(), b.x.data(), b.t.size(), {.color = 2, .x_sorted = true});
    EndPlot();
  }
  // The tracking error tells the compensations apart where the positions overlap.
  PlotOptions ne;
  ne.title = "Tracking error e = r - x";
  ne.legend = false;
  if (BeginPlot("##design_error", ImVec2(w, size.y - h_pos - gap), ne)) {
    SetupAxesSI("t", "s", "e", units.output.c_str());
    PlotLine("no compensation", a.t.data(), o.plain().error.data(), a.t.size(), {.color = 1, .x_sorted = true});
    PlotLine(comp.c_str(), b.t.data(), o.compensated().error.data(), b.t.size(), {.color = 2, .x_sorted = true});
    EndPlot();
  }
  ImGui::EndGroup();
  ImGui::SameLine();
  ImGui::BeginChild("##design_metrics", ImVec2(0, size.y), false);
  metrics_table(d);
  ImGui::EndChild();
}

}  // namespace gmslab::ui
