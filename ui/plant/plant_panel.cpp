// The Plant panel: file row, run controls, palette, the part editor, the plant's summary and linear
// plant, the schematic with its click-and-drag editing, and the plots of the chosen outputs.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/control/assembly_plant.hpp"
#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "ui/param_editor.hpp"
#include "ui/plant/plant_internal.hpp"
#include "ui/plant/plant_view.hpp"
#include "ui/plot/plot.hpp"
#include "ui/text_wrap.hpp"

namespace gmslab::ui {

using namespace plant_detail;

namespace {
std::string printf_string(const char* fmt, double a, double b = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}
}  // namespace

void load_plant(PlantPanelState& st, const AssemblyScenario& s, const std::string& path) {
  auto sim = std::make_unique<AssemblySimulation>(
      s, TraceOptions{.max_bytes = st.history_bytes});  // validates first
  st.scenario = std::make_unique<AssemblyScenario>(s);
  st.sim = std::move(sim);
  st.path = path;
  st.running = false;
  st.error.clear();
  st.selected = {};
  st.undo.clear();
  st.redo.clear();
  st.edit_msg.clear();
  st.plotted.assign(st.sim->trace().channels.size(), 0);
  // Plot the positions by default.
  for (std::size_t c = 0; c < st.plotted.size(); ++c)
    st.plotted[c] = st.sim->trace().channels[c].kind == Channel::Kind::Position ||
                    st.sim->trace().channels[c].kind == Channel::Kind::ContactForce;
}

PlantTabSettings plant_tab_settings(const PlantPanelState& st) {
  PlantTabSettings t{st.path, *st.scenario, st.speed, static_cast<double>(st.magnification),
                     {},      "",           "",       st.tf_sliding};
  const Assembly& a = st.scenario->plant;
  if (st.sim) {
    const auto& ch = st.sim->trace().channels;
    for (std::size_t c = 0; c < ch.size() && c < st.plotted.size(); ++c)
      if (st.plotted[c]) t.plotted.push_back(ch[c].name);
  }
  if (!a.drives.empty())
    t.tf_drive = a.drives[static_cast<std::size_t>(
                              std::clamp(st.tf_drive, 0, static_cast<int>(a.drives.size()) - 1))]
                     .name;
  t.tf_output = a.bodies[static_cast<std::size_t>(
                             std::clamp(st.tf_output, 0, static_cast<int>(a.bodies.size()) - 1))]
                    .name;
  return t;
}

void apply_plant_tab_settings(PlantPanelState& st, const PlantTabSettings& t) {
  load_plant(st, t.scenario, t.path);
  st.speed = t.speed;
  st.magnification = static_cast<float>(t.magnification);
  const auto& ch = st.sim->trace().channels;
  for (std::size_t c = 0; c < ch.size() && c < st.plotted.size(); ++c)
    st.plotted[c] = std::find(t.plotted.begin(), t.plotted.end(), ch[c].name) != t.plotted.end();
  const Assembly& a = st.scenario->plant;
  for (std::size_t i = 0; i < a.drives.size(); ++i)
    if (a.drives[i].name == t.tf_drive) st.tf_drive = static_cast<int>(i);
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (a.bodies[i].name == t.tf_output) st.tf_output = static_cast<int>(i);
  st.tf_sliding = t.tf_sliding;
}

void plant_run_until(PlantPanelState& st, double t) {
  if (!st.sim) return;
  const double dt = st.scenario->run.dt;
  while (!st.sim->finished() && (t < 0.0 || st.sim->time() + 0.5 * dt < t)) {
    const auto left =
        t < 0.0
            ? std::size_t{1} << 20
            : static_cast<std::size_t>(std::max(1.0, std::ceil((t - st.sim->time()) / dt - 0.5)));
    st.sim->advance(std::min<std::size_t>(left, std::size_t{1} << 20));
  }
}

namespace {
// The linear plant from a chosen drive to a chosen body's position: its poles and zeros [Hz].
void linear_plant_section(PlantPanelState& st) {
  const Assembly& a = st.scenario->plant;
  ImGui::TextUnformatted("Linear plant G(s) = x / u");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "From a force drive (u = F [N]) or pull drive (u = x_p [m]) to a body's position x [m], "
        "with every "
        "contact stuck (springs sum k_i, micro-damping) or sliding at v0 = 10 Vs (damping "
        "dF_ss/dv)");
  auto combo = [](const char* id, int& sel, const std::vector<std::string>& items) {
    sel = std::clamp(sel, 0, std::max(0, static_cast<int>(items.size()) - 1));
    ImGui::SetNextItemWidth(-1);
    if (ImGui::BeginCombo(id, items.empty() ? "" : items[static_cast<std::size_t>(sel)].c_str())) {
      for (std::size_t i = 0; i < items.size(); ++i)
        if (ImGui::Selectable(items[i].c_str(), sel == static_cast<int>(i)))
          sel = static_cast<int>(i);
      ImGui::EndCombo();
    }
  };
  std::vector<std::string> drives, outputs;
  for (const auto& d : a.drives)
    drives.push_back("from " + d.name + " (" + to_string(d.kind) + ")");
  for (const auto& b : a.bodies) outputs.push_back("to x." + b.name);
  combo("##tf_drive", st.tf_drive, drives);
  combo("##tf_output", st.tf_output, outputs);
  ImGui::Checkbox("contacts sliding", &st.tf_sliding);
  if (drives.empty()) return;
  try {
    const auto g = control::assembly_transfer_function(
        a, static_cast<std::size_t>(st.tf_drive),
        "x." + a.bodies[static_cast<std::size_t>(st.tf_output)].name,
        st.tf_sliding ? control::Regime::Sliding : control::Regime::Presliding);
    auto list = [](std::vector<control::cplx> r) {
      std::string s;
      std::sort(r.begin(), r.end(), [](auto p, auto q) { return std::abs(p) < std::abs(q); });
      for (const auto& z : r) {
        if (z.imag() < 0.0) continue;  // one of each conjugate pair
        char b[64];
        if (z.imag() > 0.0)
          std::snprintf(b, sizeof b, "%s%.3g Hz (zeta %.2g)", s.empty() ? "" : ", ",
                        std::abs(z) / (2 * M_PI), -z.real() / std::abs(z));
        else
          std::snprintf(b, sizeof b, "%s%.3g rad/s", s.empty() ? "" : ", ", z.real());
        s += b;
      }
      return s.empty() ? std::string("none") : s;
    };
    TextWrappedAtSpaces("poles: " + list(g.poles()));
    TextWrappedAtSpaces("zeros: " + list(g.zeros()));
  } catch (const std::exception& e) {
    TextWrappedAtSpaces(e.what());
  }
}
}  // namespace

namespace {
void show_colored(const std::string& text, ImVec4 color) {
  ImGui::PushStyleColor(ImGuiCol_Text, color);
  TextWrappedAtSpaces(text);
  ImGui::PopStyleColor();
}
const ImVec4 kErrorText(0.75f, 0.10f, 0.10f, 1.0f);

void load_into(PlantPanelState& st, const std::string& path) {
  try {
    load_plant(st, load_assembly_scenario(path), path);
  } catch (const std::exception& e) {
    st.error = std::string("load failed: ") + e.what();
  }
}

// The preset combo, the path field and Load.
void file_row(PlantPanelState& st, const std::function<std::vector<PresetChoice>()>& presets) {
  ImGui::TextUnformatted("Assembled plant preset");
  if (presets) {  // the presets, listed when the combo opens
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    if (ImGui::BeginCombo("##plant_presets", "presets")) {
      for (const PresetChoice& c : presets())
        if (ImGui::Selectable(c.label.c_str(), c.path == st.path)) load_into(st, c.path);
      ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Open a shipped or saved preset in this tab (assembled plants first)");
  }
  ImGui::SetNextItemWidth(-1);
  ImGui::InputText("##plant_path", &st.path);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Preset file (JSON): schema_version 2 (assembled plant) or 1 (one body), e.g. "
        "presets/two_mass_drive.json");
  if (ImGui::Button("Load")) load_into(st, st.path);
}

// Save, Run / Pause, Reset, the speed and the schematic's magnification.
void run_controls(PlantPanelState& st) {
  ImGui::SameLine();
  if (ImGui::Button("Save")) {
    try {
      save_assembly_scenario(*st.scenario, st.path);
      st.error.clear();
    } catch (const std::exception& e) {
      st.error = std::string("save failed: ") + e.what();
    }
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Write the plant as edited to the path above (schema_version 2, atomic)");
  ImGui::SameLine();
  if (ImGui::Button(st.running ? "Pause" : "Run")) st.running = !st.running;
  ImGui::SameLine();
  if (ImGui::Button("Reset")) {
    st.sim->reset();
    st.running = false;
  }
  ImGui::SetNextItemWidth(-1);
  float sp = static_cast<float>(st.speed);
  if (ImGui::SliderFloat("##speed", &sp, 0.01f, 10.0f, "speed %.2f x",
                         ImGuiSliderFlags_Logarithmic))
    st.speed = sp;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Simulated seconds per wall-clock second");
  ImGui::SetNextItemWidth(-1);
  ImGui::SliderFloat("##mag", &st.magnification, 0.0f, 1000.0f,
                     st.magnification == 0.0f ? "magnification auto" : "%.1f px/mm",
                     ImGuiSliderFlags_Logarithmic);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Displacement magnification of the schematic [px per mm of displacement]; 0 = auto (the "
        "largest "
        "displacement so far spans half the narrowest body)");
}

// Add a part at the selected body (or the first), the kind a drag connects, delete, undo / redo.
void palette(PlantPanelState& st) {
  const int at = st.selected.kind == PartRef::Kind::Body ? st.selected.index : 0;
  const PartRef::Kind kinds[] = {PartRef::Kind::Body, PartRef::Kind::Spring, PartRef::Kind::Damper,
                                 PartRef::Kind::Contact, PartRef::Kind::Drive};
  for (auto k : kinds) {
    if (k != PartRef::Kind::Body && k != PartRef::Kind::Contact) ImGui::SameLine();
    const std::string label = std::string("+") + to_string(k);
    if (ImGui::SmallButton(label.c_str())) {
      AssemblyScenario ed = *st.scenario;
      const PartRef added = add_part(ed.plant, k, at);
      if (apply_plant_edit(st, ed)) st.selected = added;
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Add a %s at the selected body (to ground); then edit it below",
                        to_string(k));
  }
  ImGui::TextUnformatted("Drag from a body to another adds a");
  for (auto k : {PartRef::Kind::Spring, PartRef::Kind::Damper, PartRef::Kind::Contact}) {
    if (k != PartRef::Kind::Spring) ImGui::SameLine();
    if (ImGui::RadioButton(to_string(k), st.connect_kind == k)) st.connect_kind = k;
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "Dragging from a body (or the ground) to another body in the schematic adds a %s between "
          "them (%s)",
          to_string(k),
          k == PartRef::Kind::Spring   ? "1000 N/m"
          : k == PartRef::Kind::Damper ? "1 N s/m"
                                       : "GMS, default parameters");
  }
  if (!st.hint.empty()) show_colored(st.hint, ImVec4(0.55f, 0.35f, 0.0f, 1.0f));
  ImGui::BeginDisabled(st.selected.kind == PartRef::Kind::None);
  if (ImGui::SmallButton("delete")) {
    AssemblyScenario ed = *st.scenario;
    ed.plant = remove_part(ed.plant, st.selected);
    if (apply_plant_edit(st, ed)) st.selected = {};
  }
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(st.undo.empty());
  if (ImGui::SmallButton("undo")) plant_undo(st);
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(st.redo.empty());
  if (ImGui::SmallButton("redo")) plant_redo(st);
  ImGui::EndDisabled();
}

// The plant's name and description, its modes with every contact stuck, the step limit.
void plant_summary(const AssemblyScenario& sc) {
  TextWrappedAtSpaces(sc.name);
  show_colored(sc.description, ImVec4(0.35f, 0.35f, 0.38f, 1.0f));
  const auto w = modal_frequencies(sc.plant, true);
  std::string modes;
  for (double wi : w) {
    char b[32];
    std::snprintf(b, sizeof b, "%s%.3g", modes.empty() ? "" : ", ", wi / (2 * M_PI));
    modes += b;
  }
  if (modes.empty())
    TextWrappedAtSpaces("Modes: none (every body's motion is prescribed)");
  else
    TextWrappedAtSpaces("Modes, contacts stuck: " + modes + " Hz");
  const double lim = stability_limit_dt(sc.plant);
  if (std::isfinite(lim))
    TextWrappedAtSpaces(printf_string("Step limit: dt < %.3g s (run.dt = %.3g s)", lim, sc.run.dt));
  else
    TextWrappedAtSpaces(
        printf_string("Step limit: none (nothing free and stiff; run.dt = %.3g s)", sc.run.dt));
}

void plotted_outputs(PlantPanelState& st) {
  ImGui::TextUnformatted("Plotted outputs");
  const auto& ch = st.sim->trace().channels;
  for (std::size_t c = 0; c < ch.size() && c < st.plotted.size(); ++c) {
    bool on = st.plotted[c];
    const std::string label = ch[c].name + " [" + ch[c].unit + "]";
    if (ImGui::Checkbox(label.c_str(), &on)) st.plotted[c] = on;
  }
}

// The left column: file, run, palette, the selected part, the plant's summary, outputs, errors.
void controls_column(PlantPanelState& st,
                     const std::function<std::vector<PresetChoice>()>& presets) {
  const float left_w = std::min(340.0f, ImGui::GetContentRegionAvail().x * 0.28f);
  ImGui::BeginChild("##plant_controls", ImVec2(left_w, 0), true);
  file_row(st, presets);
  if (st.sim) {
    run_controls(st);
    ImGui::Separator();
    palette(st);
    part_editor(st);
    if (!st.edit_msg.empty()) show_colored("Not applied: " + st.edit_msg, kErrorText);
    ImGui::Separator();
    plant_summary(*st.scenario);
    ImGui::Separator();
    linear_plant_section(st);
    ImGui::Separator();
    plotted_outputs(st);
  }
  if (!st.error.empty()) show_colored(st.error, kErrorText);
  ImGui::EndChild();
}

// Where the schematic is on screen, and how it is drawn this frame.
struct Canvas {
  ImVec2 origin;
  PlantLayout l;
  PlantPose pose;
  double mag;
  ImDrawList* dl;
};

void outline(const Canvas& c, const Box& b, float o, ImU32 col) {
  c.dl->AddRect({c.origin.x + b.x0 + o - 4, c.origin.y + b.y0 - 4},
                {c.origin.x + b.x1 + o + 4, c.origin.y + b.y1 + 4}, col, 3.0f, 0, 2.5f);
}

// While dragging from a body (or the ground): the rubber band, the target outlined, a tooltip.
void drag_feedback(PlantPanelState& st, const Canvas& c, ImVec2 m, float mx, float my) {
  const Assembly& a = st.scenario->plant;
  const char* kind = to_string(st.connect_kind);
  const int to = attachment_at(c.l, a, c.pose, c.mag, mx, my);
  const bool can =
      to != kNoEnd && to != st.drag_from && !(to == kGround && st.drag_from == kGround);
  c.dl->AddLine({c.origin.x + st.drag_x, c.origin.y + st.drag_y}, m, can ? kDrive : kDimInk, 2.5f);
  c.dl->AddCircleFilled({c.origin.x + st.drag_x, c.origin.y + st.drag_y}, 4.5f, kDrive);
  const std::string from =
      st.drag_from == kGround ? "ground" : a.bodies[static_cast<std::size_t>(st.drag_from)].name;
  if (can && to >= 0)  // the body it would connect to, outlined
    outline(c, c.l.bodies[static_cast<std::size_t>(to)], body_dx(c.l, c.pose, c.mag, to), kDrive);
  if (can) {
    const std::string target =
        to == kGround ? "ground" : a.bodies[static_cast<std::size_t>(to)].name;
    ImGui::SetTooltip("Release to connect %s and %s with a %s", from.c_str(), target.c_str(), kind);
  } else {
    ImGui::SetTooltip("Drag to another body or the ground to connect %s with a %s", from.c_str(),
                      kind);
  }
}

// A drag released: connect its two ends, or say why nothing was connected.
void finish_drag(PlantPanelState& st, const Canvas& c, float mx, float my) {
  const int from = st.drag_from, to = attachment_at(c.l, st.scenario->plant, c.pose, c.mag, mx, my);
  st.drag_from = kNoEnd;
  AssemblyScenario ed = *st.scenario;
  const PartRef added = connect_parts(ed.plant, st.connect_kind, from, to);
  if (added.kind == PartRef::Kind::None) {
    st.hint =
        to == kNoEnd
            ? std::string("Nothing connected: release the drag on another body or on the ground")
            : std::string("Nothing connected: a ") + to_string(st.connect_kind) +
                  " needs two different ends (a body and another body or the ground)";
  } else if (apply_plant_edit(st, ed)) {
    st.selected = added;
  }
}

// Hovering: the attachment points, and the hint on the schematic's own header row (after the
// stick / slip key), not as a tooltip that would cover the plots' legends below.
void hover_marks(const PlantPanelState& st, const Canvas& c) {
  for (std::size_t i = 0; i < c.l.bodies.size(); ++i) {
    const Box& b = c.l.bodies[i];
    const float o = body_dx(c.l, c.pose, c.mag, static_cast<int>(i));
    c.dl->AddCircle({c.origin.x + b.x0 + o, c.origin.y + b.cy()}, 4.0f, kDrive, 0, 2.0f);
    c.dl->AddCircle({c.origin.x + b.x1 + o, c.origin.y + b.cy()}, 4.0f, kDrive, 0, 2.0f);
  }
  const std::string hint =
      std::string("click a part to edit it; drag from a body or the ground to another body: a ") +
      to_string(st.connect_kind);
  c.dl->AddText({c.origin.x + 130.0f, c.origin.y + 8.0f + ImGui::GetTextLineHeight()}, kDimInk,
                hint.c_str());
}

// Click: select a part; drag from a body (or ground) to another: connect them.
void canvas_input(PlantPanelState& st, const Canvas& c) {
  const Assembly& a = st.scenario->plant;
  const ImVec2 m = ImGui::GetMousePos();
  const float mx = m.x - c.origin.x, my = m.y - c.origin.y;
  if (ImGui::IsItemActivated()) {
    st.selected = hit_test(c.l, a, c.pose, c.mag, mx, my);
    st.drag_from = attachment_at(c.l, a, c.pose, c.mag, mx, my);
    st.drag_x = mx, st.drag_y = my;
    st.hint.clear();
  }
  const bool moved = std::hypot(mx - st.drag_x, my - st.drag_y) >= 5.0f;
  if (ImGui::IsItemActive() && st.drag_from != kNoEnd && moved) drag_feedback(st, c, m, mx, my);
  if (ImGui::IsItemDeactivated() && st.drag_from != kNoEnd && moved) finish_drag(st, c, mx, my);
  if (ImGui::IsItemDeactivated()) st.drag_from = kNoEnd;
  if (ImGui::IsItemHovered() && !ImGui::IsItemActive()) hover_marks(st, c);
}

void selection_outline(const PlantPanelState& st, const Canvas& c) {  // the selected block or pad
  const auto& sel = st.selected;
  const Box* b = nullptr;
  int body = -1;
  if (sel.kind == PartRef::Kind::Body && sel.index < static_cast<int>(c.l.bodies.size()))
    b = &c.l.bodies[sel.index], body = sel.index;
  if (sel.kind == PartRef::Kind::Contact && sel.index < static_cast<int>(c.l.contacts.size()))
    b = &c.l.contacts[sel.index], body = st.scenario->plant.contacts[sel.index].a;
  if (b) outline(c, *b, body_dx(c.l, c.pose, c.mag, body), IM_COL32(204, 121, 167, 255));
}

// The schematic on a white canvas, with its click-and-drag editing.
void schematic(PlantPanelState& st) {
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float canvas_h = std::max(220.0f, avail.y * 0.52f);
  const Assembly& a = st.scenario->plant;
  Canvas c{ImGui::GetCursorScreenPos(), layout_plant(a, avail.x, canvas_h), pose_of(*st.sim), 0.0,
           ImGui::GetWindowDrawList()};
  c.dl->AddRectFilled(c.origin, {c.origin.x + avail.x, c.origin.y + canvas_h},
                      IM_COL32(255, 255, 255, 255));
  c.mag =
      st.magnification > 0.0f ? st.magnification * 1e3 : auto_magnification(c.l, st.sim->trace());
  st.canvas_drawn = draw_plant(c.dl, c.origin.x, c.origin.y, c.l, a, c.pose, c.mag);
  st.canvas_x = c.origin.x, st.canvas_y = c.origin.y, st.canvas_layout = c.l,
  st.canvas_pose = c.pose, st.canvas_mag = c.mag;
  ImGui::InvisibleButton("##plant_canvas", ImVec2(avail.x, canvas_h));
  canvas_input(st, c);
  selection_outline(st, c);
}

// Plots of the chosen outputs: lengths, velocities and forces on separate axes.
void output_plots(const PlantPanelState& st) {
  const auto& tr = st.sim->trace();
  struct Group {
    const char* id;
    const char* name;
    const char* unit;
    std::vector<Channel::Kind> kinds;
  };
  const Group groups[] = {{"##plant_x", "x", "m", {Channel::Kind::Position}},
                          {"##plant_v", "v", "m/s", {Channel::Kind::Velocity}},
                          {"##plant_f",
                           "F",
                           "N",
                           {Channel::Kind::ContactForce, Channel::Kind::SpringForce,
                            Channel::Kind::DamperForce, Channel::Kind::DriveForce}}};
  auto in_group = [&](const Group& g, std::size_t c) {
    return c < st.plotted.size() && st.plotted[c] &&
           std::find(g.kinds.begin(), g.kinds.end(), tr.channels[c].kind) != g.kinds.end();
  };
  std::vector<const Group*> shown;
  for (const auto& g : groups)
    for (std::size_t c = 0; c < tr.channels.size(); ++c)
      if (in_group(g, c)) {
        shown.push_back(&g);
        break;
      }
  std::vector<std::vector<double>> series(tr.channels.size());  // per channel, alive until EndPlot
  const float ph =
      shown.empty() ? 0.0f
                    : (ImGui::GetContentRegionAvail().y - 4.0f) / static_cast<float>(shown.size());
  for (const Group* g : shown) {
    if (!BeginPlot(g->id, ImVec2(-1, ph))) continue;
    SetupAxesSI("t", "s", g->name, g->unit);
    SetupFitRangeX(0.0, st.scenario->run.duration);
    int color = 0;
    for (std::size_t c = 0; c < tr.channels.size(); ++c) {
      if (!in_group(*g, c)) continue;
      series[c] = tr.series(tr.channels[c].name);
      SeriesStyle s;
      s.color = color++;
      s.x_sorted = true;
      PlotLine(tr.channels[c].name.c_str(), tr.t.data(), series[c].data(), tr.size(), s);
    }
    EndPlot();
  }
}

// Runs the plant on by speed x the frame's duration; an error stops the run and is shown.
void advance(PlantPanelState& st, double frame_dt) {
  if (!st.running) return;
  try {
    plant_run_until(st, st.sim->time() + st.speed * frame_dt);
    if (st.sim->finished()) st.running = false;
  } catch (const std::exception& e) {
    st.running = false;
    st.error = std::string("run stopped: ") + e.what();
  }
}
}  // namespace

void draw_plant_panel(PlantPanelState& st, double frame_dt,
                      const std::function<std::vector<PresetChoice>()>& presets) {
  controls_column(st, presets);
  ImGui::SameLine();
  ImGui::BeginChild("##plant_view", ImVec2(0, 0), false);
  if (!st.sim) {
    ImGui::TextUnformatted("No plant loaded: enter a preset path on the left and press Load.");
    ImGui::EndChild();
    return;
  }
  schematic(st);
  output_plots(st);
  ImGui::EndChild();
  advance(st, frame_dt);
}

}  // namespace gmslab::ui
