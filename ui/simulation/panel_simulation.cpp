// gmslab ui: the Simulation panel. Left: scenario file, run controls, plant, drive, run settings,
// friction model, overlay model, display options. Right: the live plots (ui/simulation/sim_plots.cpp).
//
// Edits go to a scratch copy (SimPanelState). A valid edit becomes a pending request; an invalid
// one stays in the scratch copy with its validation message shown inline and is not applied.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "ui/app_files.hpp"
#include "ui/simulation/drive_editor.hpp"
#include "ui/panels.hpp"
#include "ui/param_editor.hpp"
#include "ui/simulation/sim_plots.hpp"
#include "ui/text_wrap.hpp"

namespace gmslab::ui {

namespace {


const ImVec4 kErr(0.75f, 0.10f, 0.10f, 1.0f);
const ImVec4 kDim(0.35f, 0.35f, 0.38f, 1.0f);

void sync(AppState& s, SimPanelState& p) {
  if (p.generation == s.generation) return;
  p.generation = s.generation;
  p.path = s.scenario_path;
  p.friction = s.scenario.friction;
  p.plant = s.scenario.plant;
  p.drive = s.scenario.drive;
  p.run = s.scenario.run;
  p.compare = s.compare ? *s.compare : ModelParams{};
  p.friction_msg = p.plant_msg = p.drive_msg = p.compare_msg = "";
  p.marks.clear();
}

// "" when the scenario would run, else the validation message (names key and range).
std::string check(const Scenario& sc) {
  try {
    (void)one_body_simulation(
        sc, TraceOptions{.max_bytes = 0, .reserve_samples = 1});  // no trace memory
    return "";
  } catch (const InputError& e) {
    return e.what();
  }
}

void message(const std::string& msg) {
  if (msg.empty()) return;
  ImGui::PushStyleColor(ImGuiCol_Text, kErr);
  TextWrappedAtSpaces("Not applied: " + msg);
  ImGui::PopStyleColor();
}

void tip(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

void scenario_section(AppState& s, SimPanelState& p) {
  ImGui::SetNextItemWidth(-ImGui::GetFontSize() * 7.6f);
  ImGui::InputTextWithHint("##path", "scenario file (.json)", &p.path);
  tip("Path of a scenario preset (JSON, schema_version 1), e.g. presets/fig4_stick_slip.json");
  ImGui::SameLine();
  if (ImGui::Button("Load")) s.pending.load_path = p.path;
  tip("Load the scenario from this file (restarts the run)");
  ImGui::SameLine();
  // A path typed here is the user's pick; otherwise Save goes to save_target (never a shipped preset).
  const std::string target = !p.path.empty() && p.path != s.scenario_path ? p.path : save_target(s);
  if (ImGui::Button("Save")) s.pending.save_path = target;
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Save the scenario as edited to\n%s\n(shipped presets are never overwritten; an existing "
                      "file is replaced only after you confirm; File > Save as... picks another path)",
                      target.c_str());
  // The unsaved mark has a line of its own (one line, always there) and the window title's star:
  // an edit never moves the fields below.
  const bool edited = has_unsaved_changes(s);
  if (edited) {
    ImGui::TextColored(ImVec4(0.70f, 0.35f, 0.0f, 1.0f), "* unsaved changes (text below: as loaded)");
    tip("The scenario differs from its file; the name and description below are the file's. Ctrl+S saves "
        "(to your own folder for a shipped preset)");
  } else {
    ImGui::TextDisabled("no unsaved changes");
  }
  TextWrappedAtSpaces(s.scenario.name);
  if (!s.scenario.description.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kDim);
    TextWrappedAtSpaces(s.scenario.description);
    ImGui::PopStyleColor();
  }
}

void run_section(AppState& s) {
  const AssemblySimulation* sim = s.main.sim.get();
  const float bw = ImGui::GetFontSize() * 4.5f;
  if (s.running) {
    if (ImGui::Button("Pause", ImVec2(bw, 0))) s.pending.pause = true;
  } else if (ImGui::Button(sim && sim->finished() ? "Rerun" : "Run", ImVec2(bw, 0))) {
    s.pending.run = true;
  }
  tip("Run or pause the simulation (parameters stay editable while it runs)");
  ImGui::SameLine();
  if (ImGui::Button("Reset", ImVec2(bw, 0))) s.pending.reset = true;
  tip("Back to t = 0 with the friction in its virgin state");
  ImGui::SameLine();
  ImGui::TextUnformatted("speed [s/s]");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  static constexpr ParamSpec kSpeed{"speed", "speed", "s/s", "simulated seconds per wall-clock second",
                                    1e-3, 1e3, false, true};
  edit_param("##speed", kSpeed, s.view.speed, 1.0);
  if (sim) {
    const double dur = s.scenario.run.duration;
    char buf[96];
    std::snprintf(buf, sizeof buf, "t = %.4g s of %.4g s%s", sim->time(), dur,
                  s.sim_limited ? "  (CPU-limited)" : "");
    ImGui::ProgressBar(static_cast<float>(std::clamp(sim->time() / dur, 0.0, 1.0)), ImVec2(-1, 0), buf);
    tip("Simulated time. CPU-limited: the speed asked for needs more steps than one frame allows.");
  }
  if (!s.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErr);
    TextWrappedAtSpaces(s.error);
    ImGui::PopStyleColor();
  }
}

void plant_section(AppState& s, SimPanelState& p) {
  if (!ImGui::CollapsingHeader("Plant", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (s.scenario.drive.kind == Drive::Kind::Displacement || s.scenario.drive.kind == Drive::Kind::Velocity)
    ImGui::TextColored(kDim, "(the motion is prescribed: the plant does not act)");
  if (edit_plant(p.plant, &p.marks)) {
    Scenario sc = s.scenario;
    sc.plant = p.plant;
    p.plant_msg = check(sc);
    if (p.plant_msg.empty()) s.pending.plant = p.plant;
    else p.marks.reject(p.plant_msg), p.plant = s.scenario.plant;  // the field shows the value in force
  }
}

void drive_section(AppState& s, SimPanelState& p) {
  if (!ImGui::CollapsingHeader("Drive and run", ImGuiTreeNodeFlags_DefaultOpen)) return;
  bool c = edit_drive(p.drive, &p.marks);
  ImGui::Separator();
  c |= edit_run(p.run, &p.marks);
  if (c) {
    Scenario sc = s.scenario;
    sc.drive = p.drive;
    sc.run = p.run;
    p.drive_msg = check(sc);
    if (p.drive_msg.empty()) s.pending.scenario = sc;
    else p.marks.reject(p.drive_msg), p.drive = s.scenario.drive, p.run = s.scenario.run;
  }
  ImGui::TextColored(kDim, "Changing the drive or the run settings restarts the run.");
}

void friction_section(AppState& s, SimPanelState& p) {
  if (!ImGui::CollapsingHeader("Friction model", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::SetNextItemWidth(-1);
  bool c = edit_model_choice("##model", p.friction);
  const AssemblySimulation* sim = s.main.sim.get();
  const bool live = sim && sim->one_body()->friction.model == p.friction.model;
  c |= edit_model_params("friction", p.friction, live ? &sim->contact_model(0) : nullptr,
                         live ? sim->contact_state(0) : std::span<const double>{}, &p.marks);
  if (c) {
    Scenario sc = s.scenario;
    sc.friction = p.friction;
    p.friction_msg = check(sc);
    if (p.friction_msg.empty()) s.pending.friction = p.friction;
    else if (p.friction.model == s.scenario.friction.model) p.marks.reject(p.friction_msg), p.friction = s.scenario.friction;
  }
  if (p.friction.model != s.scenario.friction.model) message(p.friction_msg);
}

void compare_section(AppState& s, SimPanelState& p) {
  if (!ImGui::CollapsingHeader("Overlay a second model")) return;
  ImGui::TextColored(kDim, "Runs on the same plant and drive; drawn dashed in the plots.");
  bool on = s.compare.has_value();
  if (ImGui::Checkbox("overlay", &on)) {
    if (on) {
      if (p.compare.model.empty()) {
        const auto& reg = model_registry();
        const ModelInfo* pick = &reg.front();  // prefer a model other than the main one
        for (const auto& m : reg)
          if (m.tag != s.scenario.friction.model) {
            pick = &m;
            break;
          }
        p.compare = pick->defaults();
      }
      s.pending.compare = p.compare;
    } else {
      s.pending.clear_compare = true;
    }
  }
  tip("Simulate a second friction model on the same input and overlay it");
  if (!on) return;
  if (ImGui::Checkbox("follow the main model's F_s, F_c, V_s", &s.overlay_follows_shared) && s.overlay_follows_shared)
    s.pending.compare = with_shared_parameters(*s.compare, s.scenario.friction);
  tip("On: the overlay takes F_s, F_c and V_s from the main model (where both models have them) "
      "whenever the main model changes, so the two differ only in their dynamics");
  ImGui::SetNextItemWidth(-1);
  bool c = edit_model_choice("##cmpmodel", p.compare);
  const AssemblySimulation* sim = s.overlay.sim.get();
  const bool live = sim && sim->one_body()->friction.model == p.compare.model;
  c |= edit_model_params("compare", p.compare, live ? &sim->contact_model(0) : nullptr,
                         live ? sim->contact_state(0) : std::span<const double>{}, &p.marks);
  if (c) {
    Scenario sc = s.scenario;
    sc.friction = p.compare;
    p.compare_msg = check(sc);
    if (p.compare_msg.empty()) s.pending.compare = p.compare;
    else if (s.compare && s.compare->model == p.compare.model) p.marks.reject(p.compare_msg), p.compare = *s.compare;
  }
  if (!s.compare || s.compare->model != p.compare.model) message(p.compare_msg);
}

void display_section(AppState& s) {
  if (!ImGui::CollapsingHeader("Display")) return;
  ImGui::Checkbox("colour stick / slip phases", &s.view.color_phases);
  tip("Time plots: blue while the body sticks, orange while it slips (|v| above the threshold "
      "below, or every friction element slipping)");
  const ParamSpec th{"slip_velocity", "v_slip", "m/s", "|v| above which the body counts as slipping",
                     0, 1e3, true, true};
  ImGui::Text("slip threshold [m/s]");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  edit_param("##slipv", th, s.view.slip_velocity, 1e-4);
  static const char* against[] = {"auto", "displacement", "velocity"};
  int a = 0;
  for (int i = 0; i < 3; ++i)
    if (s.view.friction_against == against[i]) a = i;
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9.0f);
  if (ImGui::Combo("friction plot against", &a, against, 3)) s.view.friction_against = against[a];
  tip("x axis of the friction plot: displacement (presliding hysteresis) or velocity (frictional "
      "lag, Stribeck curve); auto picks velocity when the velocity is prescribed");
  ImGui::TextColored(kDim, "Plots: wheel zooms (Shift: x only, Ctrl: y only), drag pans,\n"
                           "double-click fits the data again.");
}

}  // namespace

void draw_simulation_panel(AppState& s) {
  auto& p = s.sim_panel;
  sync(s, p);
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float left = std::min(avail.x * 0.38f, ImGui::GetFontSize() * 31.0f);
  ImGui::BeginChild("##controls", ImVec2(left, avail.y), true);
  scenario_section(s, p);
  ImGui::Separator();
  run_section(s);
  plant_section(s, p);
  drive_section(s, p);
  friction_section(s, p);
  compare_section(s, p);
  display_section(s);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("##plots", ImVec2(0, avail.y), false,
                    ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  draw_simulation_plots(s);
  ImGui::EndChild();
}

}  // namespace gmslab::ui
