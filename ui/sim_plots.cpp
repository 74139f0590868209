#include "ui/sim_plots.hpp"

#include <imgui.h>

#include <string>

#include "ui/plot.hpp"

namespace gmslab::ui {

namespace {
constexpr int kStick = 0, kSlip = 1, kOverlay = 2, kDrive = 6;
const ImU32 kPhaseColors[2] = {palette(kStick), IM_COL32(230, 120, 0, 255)};

// "Generalized Maxwell-slip (GMS)" -> "GMS": the text in the last parentheses, else the name.
std::string short_name(std::string_view name) {
  const auto open = name.rfind('('), close = name.rfind(')');
  if (open != std::string_view::npos && close != std::string_view::npos && close > open + 1)
    return std::string(name.substr(open + 1, close - open - 1));
  return std::string(name);
}

struct Runs {
  const Trace* main = nullptr;
  const Trace* overlay = nullptr;
  const std::uint8_t* phase = nullptr;
  std::string main_name, overlay_name;
};

SeriesStyle time_style(const Runs& r, bool phases) {
  SeriesStyle st;
  st.color = kStick;
  st.x_sorted = true;
  if (phases && r.phase) {
    st.classes = r.phase;
    st.class_colors = kPhaseColors;
    st.n_classes = 2;
  }
  return st;
}

SeriesStyle overlay_style(bool sorted) {
  SeriesStyle st;
  st.color = kOverlay;
  st.line = LineStyle::Dashed;
  st.x_sorted = sorted;
  return st;
}

ImVec2 cell(int cols, int rows) {
  const ImVec2 a = ImGui::GetContentRegionAvail();
  const ImGuiStyle& st = ImGui::GetStyle();
  return ImVec2((a.x - st.ItemSpacing.x * (cols - 1)) / cols, (a.y - st.ItemSpacing.y * (rows - 1)) / rows);
}

void force_plot(const Runs& r, const AppState& s, ImVec2 size) {
  PlotOptions o;
  o.title = "Forces against time";
  if (!BeginPlot("##forces", size, o)) return;
  SetupAxesSI("t", "s", "F", "N");
  SetupFitRangeX(0.0, s.scenario.run.duration);
  const Trace& m = *r.main;
  const std::string ff = "friction F_f (" + r.main_name + ")";
  PlotLine(ff.c_str(), m.t.data(), m.friction.data(), m.size(), time_style(r, s.view.color_phases));
  const bool massive = s.scenario.drive.kind == Drive::Kind::Force || s.scenario.drive.kind == Drive::Kind::Pull;
  if (massive) {
    SeriesStyle d;
    d.color = kDrive;
    d.thickness = 1.2f;
    d.x_sorted = true;
    d.line = LineStyle::Dotted;
    PlotLine(s.scenario.drive.kind == Drive::Kind::Pull ? "pull spring force" : "applied force F(t)",
             m.t.data(), m.applied.data(), m.size(), d);
  }
  if (r.overlay) {
    const std::string of = "friction F_f (" + r.overlay_name + ")";
    PlotLine(of.c_str(), r.overlay->t.data(), r.overlay->friction.data(), r.overlay->size(), overlay_style(true));
  }
  EndPlot();
}

void time_plot(const char* id, const char* title, const char* name, const char* unit,
               const std::vector<double> Trace::*field, const Runs& r, const AppState& s, ImVec2 size) {
  PlotOptions o;
  o.title = title;
  if (!BeginPlot(id, size, o)) return;
  SetupAxesSI("t", "s", name, unit);
  SetupFitRangeX(0.0, s.scenario.run.duration);
  const Trace& m = *r.main;
  PlotLine(r.main_name.c_str(), m.t.data(), (m.*field).data(), m.size(), time_style(r, s.view.color_phases));
  if (r.overlay)
    PlotLine(r.overlay_name.c_str(), r.overlay->t.data(), (r.overlay->*field).data(), r.overlay->size(),
             overlay_style(true));
  EndPlot();
}

void hysteresis_plot(const Runs& r, ImVec2 size) {
  PlotOptions o;
  o.title = "Friction force against displacement";
  if (!BeginPlot("##hyst", size, o)) return;
  SetupAxesSI("x", "m", "F_f", "N");
  SeriesStyle st;
  st.color = kStick;
  PlotLine(r.main_name.c_str(), r.main->x.data(), r.main->friction.data(), r.main->size(), st);
  if (r.overlay)
    PlotLine(r.overlay_name.c_str(), r.overlay->x.data(), r.overlay->friction.data(), r.overlay->size(),
             overlay_style(false));
  EndPlot();
}
}  // namespace

void draw_simulation_plots(AppState& s) {
  if (!s.main.sim) {
    ImGui::TextUnformatted("No scenario loaded: enter a preset path on the left and press Load.");
    return;
  }
  s.main.update_phase(s.view.slip_velocity);
  Runs r;
  r.main = &s.main.sim->trace();
  r.phase = s.main.phase.data();
  r.main_name = short_name(model_info(s.scenario.friction.model).name);
  if (s.overlay.sim) {
    r.overlay = &s.overlay.sim->trace();
    r.overlay_name = short_name(model_info(s.compare->model).name) + " (overlay)";
    if (r.overlay_name == r.main_name + " (overlay)") r.overlay_name = r.main_name + " (overlay, own parameters)";
  }
  const ImVec2 c = cell(2, 2);
  force_plot(r, s, c);
  ImGui::SameLine();
  time_plot("##pos", "Position against time", "x", "m", &Trace::x, r, s, c);
  hysteresis_plot(r, c);
  ImGui::SameLine();
  time_plot("##vel", "Velocity against time", "v", "m/s", &Trace::v, r, s, c);
}

}  // namespace gmslab::ui
