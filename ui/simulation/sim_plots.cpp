#include "ui/simulation/sim_plots.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "ui/plot/plot.hpp"

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
    d.thickness = 1.0f;
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

void hysteresis_plot(const Runs& r, const AppState& s, ImVec2 size) {
  const bool vel = s.view.friction_against == "velocity" ||
                   (s.view.friction_against == "auto" && s.scenario.drive.kind == Drive::Kind::Velocity);
  const std::vector<double> Trace::*xf = vel ? &Trace::v : &Trace::x;
  PlotOptions o;
  o.title = vel ? "Friction force against velocity" : "Friction force against displacement";
  if (!BeginPlot("##hyst", size, o)) return;
  SetupAxesSI(vel ? "v" : "x", vel ? "m/s" : "m", "F_f", "N");
  SeriesStyle st;
  st.color = kStick;
  PlotLine(r.main_name.c_str(), (r.main->*xf).data(), r.main->friction.data(), r.main->size(), st);
  if (r.overlay)
    PlotLine(r.overlay_name.c_str(), (r.overlay->*xf).data(), r.overlay->friction.data(), r.overlay->size(),
             overlay_style(false));
  EndPlot();
}

// A strip of bars, one per friction element: its force F_i (up or down from the centre line,
// scaled to the largest |F_i|) in blue while it sticks and orange while it slips.
void element_strip(const AssemblySimulation& sim, ImVec2 size) {
  const FrictionModel& m = sim.contact_model(0);
  const std::size_t n = m.element_count();
  ImGui::BeginChild("##elements", size, false, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  const float fh = ImGui::GetFontSize();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  std::vector<ElementState> st(n);
  double fmax = 1e-12;
  std::size_t slipping = 0;
  for (std::size_t i = 0; i < n; ++i) {
    st[i] = m.element(sim.contact_state(0), i);
    fmax = std::max(fmax, std::fabs(st[i].force));
    slipping += st[i].slipping;
  }
  char head[160];
  std::snprintf(head, sizeof head, "Elements: force F_i (largest |F_i| = %.4g N), %zu of %zu slipping", fmax, slipping, n);
  dl->AddText(p0, IM_COL32(20, 20, 20, 255), head);
  const float left = p0.x + 0.2f * fh, right = p0.x + size.x - 0.2f * fh;
  const float top = p0.y + 1.4f * fh, bottom = p0.y + size.y - 0.2f * fh;
  const float mid = 0.5f * (top + bottom), half = 0.5f * (bottom - top);
  dl->AddRectFilled(ImVec2(left, top), ImVec2(right, bottom), IM_COL32(255, 255, 255, 255));
  dl->AddLine(ImVec2(left, mid), ImVec2(right, mid), IM_COL32(170, 170, 175, 255));
  const float w = (right - left) / static_cast<float>(std::max<std::size_t>(n, 1));
  for (std::size_t i = 0; i < n; ++i) {
    const float x0 = left + w * static_cast<float>(i) + (w > 4 ? 1.0f : 0.0f);
    const float x1 = left + w * static_cast<float>(i + 1) - (w > 4 ? 1.0f : 0.0f);
    const float y = mid - static_cast<float>(st[i].force / fmax) * half;
    dl->AddRectFilled(ImVec2(x0, std::min(y, mid)), ImVec2(std::max(x1, x0 + 1), std::max(y, mid)),
                      st[i].slipping ? kPhaseColors[kSlip] : kPhaseColors[kStick]);
    if (w > 9.0f * fh) {  // room for the value
      char v[64];
      std::snprintf(v, sizeof v, "F_%zu = %+.4g N, %s", i + 1, st[i].force, st[i].slipping ? "slip" : "stick");
      const float ty = st[i].force >= 0 ? mid + 0.1f * fh : mid - 1.1f * fh;
      dl->AddText(ImVec2(x0 + 0.3f * fh, ty), IM_COL32(40, 40, 40, 255), v);
    }
  }
  dl->AddRect(ImVec2(left, top), ImVec2(right, bottom), IM_COL32(120, 120, 120, 255));
  ImGui::Dummy(size);
  if (ImGui::IsItemHovered() && n > 0) {
    const float mx = ImGui::GetIO().MousePos.x;
    const std::size_t i = std::min(n - 1, static_cast<std::size_t>(std::max(0.0f, (mx - left) / w)));
    ImGui::SetTooltip("element %zu: F_%zu = %+.6g N, %s", i + 1, i + 1, st[i].force,
                      st[i].slipping ? "slipping" : "sticking");
  }
  ImGui::EndChild();
}
}  // namespace

void draw_simulation_plots(AppState& s) {
  if (!s.main.sim) {
    ImGui::TextUnformatted("No scenario loaded: enter a preset path on the left and press Load.");
    return;
  }
  Runs r;
  r.main = &s.main.sim->one_body_trace();
  r.phase = s.main.phases(s.view.slip_velocity).data();
  r.main_name = short_name(model_info(s.scenario.friction.model).name);
  if (s.overlay.sim) {
    r.overlay = &s.overlay.sim->one_body_trace();
    r.overlay_name = short_name(model_info(s.compare->model).name) + " (overlay)";
    if (r.overlay_name == r.main_name + " (overlay)") r.overlay_name = r.main_name + " (overlay, own parameters)";
  }
  const bool strip = s.main.sim->contact_model(0).element_count() > 0;
  const float strip_h = ImGui::GetFontSize() * 4.6f;
  ImVec2 c = cell(2, 2);
  if (strip) c.y -= 0.5f * (strip_h + ImGui::GetStyle().ItemSpacing.y);
  force_plot(r, s, c);
  ImGui::SameLine();
  time_plot("##pos", "Position against time", "x", "m", &Trace::x, r, s, c);
  hysteresis_plot(r, s, c);
  ImGui::SameLine();
  time_plot("##vel", "Velocity against time", "v", "m/s", &Trace::v, r, s, c);
  if (strip) element_strip(*s.main.sim, ImVec2(ImGui::GetContentRegionAvail().x, strip_h));
}

}  // namespace gmslab::ui
