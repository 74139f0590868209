// The Plant panel's editing: hit-testing the schematic, adding, connecting and removing parts, the
// selected part's fields, undo and redo. Every edit is applied only when the edited plant
// validates.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>

#include "ui/param_editor.hpp"
#include "ui/plant/plant_internal.hpp"
#include "ui/plant/plant_view.hpp"

namespace gmslab::ui {

using plant_detail::body_dx;

const char* to_string(PartRef::Kind k) {
  switch (k) {
    case PartRef::Kind::None:
      return "none";
    case PartRef::Kind::Body:
      return "body";
    case PartRef::Kind::Spring:
      return "spring";
    case PartRef::Kind::Damper:
      return "damper";
    case PartRef::Kind::Contact:
      return "contact";
    case PartRef::Kind::Drive:
      return "drive";
  }
  return "?";
}

namespace {
float seg_dist(float px, float py, float ax, float ay, float bx, float by) {
  const float dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
  float t = len2 > 0.0f ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0f;
  t = std::clamp(t, 0.0f, 1.0f);
  const float qx = ax + t * dx - px, qy = ay + t * dy - py;
  return std::sqrt(qx * qx + qy * qy);
}
}  // namespace

float plant_detail::body_dx(const PlantLayout& l, const PlantPose& pose, double mag, int body) {
  if (body < 0) return 0.0f;
  const double d = pose.x[static_cast<std::size_t>(body)] * mag;
  return static_cast<float>(std::clamp(d, -0.45 * l.width, 0.45 * l.width));
}

PartRef hit_test(const PlantLayout& l, const Assembly& a, const PlantPose& pose, double mag,
                 float mx, float my) {
  auto dx = [&](int b) { return body_dx(l, pose, mag, b); };
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto& g = l.drives[i];
    const float x = g.x + dx(a.drives[i].body);
    if (std::hypot(mx - x, my - g.y) < 10.0f ||
        (a.drives[i].kind == DrivePart::Kind::Pull && seg_dist(mx, my, x, g.y, g.px, g.py) < 6.0f))
      return {PartRef::Kind::Drive, static_cast<int>(i)};
  }
  for (std::size_t j = 0; j < a.contacts.size(); ++j) {
    const Box& p = l.contacts[j];
    const float o = dx(a.contacts[j].a);
    if (mx >= p.x0 + o && mx <= p.x1 + o && my >= p.y0 && my <= p.y1)
      return {PartRef::Kind::Contact, static_cast<int>(j)};
  }
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const Box& b = l.bodies[i];
    const float o = dx(static_cast<int>(i));
    if (mx >= b.x0 + o && mx <= b.x1 + o && my >= b.y0 && my <= b.y1)
      return {PartRef::Kind::Body, static_cast<int>(i)};
  }
  auto near_link = [&](const PlantLayout::Link& k, int ia, int ib) {
    const float ax = k.ax + dx(ia), bx = k.bx + dx(ib);
    if (k.lift > 0.0f) return seg_dist(mx, my, ax, k.ay - k.lift, bx, k.by - k.lift) < 8.0f;
    return seg_dist(mx, my, ax, k.ay, bx, k.by) < 8.0f;
  };
  for (std::size_t i = 0; i < a.springs.size(); ++i)
    if (near_link(l.springs[i], a.springs[i].a, a.springs[i].b))
      return {PartRef::Kind::Spring, static_cast<int>(i)};
  for (std::size_t i = 0; i < a.dampers.size(); ++i)
    if (near_link(l.dampers[i], a.dampers[i].a, a.dampers[i].b))
      return {PartRef::Kind::Damper, static_cast<int>(i)};
  return {};
}

Assembly remove_part(const Assembly& a, PartRef p) {
  Assembly out = a;
  auto erase = [&](auto& v) {
    if (p.index >= 0 && p.index < static_cast<int>(v.size())) v.erase(v.begin() + p.index);
  };
  switch (p.kind) {
    case PartRef::Kind::None:
      break;
    case PartRef::Kind::Spring:
      erase(out.springs);
      break;
    case PartRef::Kind::Damper:
      erase(out.dampers);
      break;
    case PartRef::Kind::Contact:
      erase(out.contacts);
      break;
    case PartRef::Kind::Drive:
      erase(out.drives);
      break;
    case PartRef::Kind::Body: {
      if (p.index < 0 || p.index >= static_cast<int>(a.bodies.size())) break;
      erase(out.bodies);
      auto map = [&](int i) { return i == kGround ? kGround : i > p.index ? i - 1 : i; };
      auto keep = [&](auto& v) {
        std::erase_if(v, [&](const auto& x) { return x.a == p.index || x.b == p.index; });
        for (auto& x : v) x.a = map(x.a), x.b = map(x.b);
      };
      keep(out.springs);
      keep(out.dampers);
      keep(out.contacts);
      std::erase_if(out.drives, [&](const DrivePart& d) { return d.body == p.index; });
      for (auto& d : out.drives) d.body = map(d.body);
      break;
    }
  }
  return out;
}

namespace {
bool name_used(const Assembly& a, const std::string& n) {
  for (const auto& x : a.bodies)
    if (x.name == n) return true;
  for (const auto& x : a.springs)
    if (x.name == n) return true;
  for (const auto& x : a.dampers)
    if (x.name == n) return true;
  for (const auto& x : a.contacts)
    if (x.name == n) return true;
  for (const auto& x : a.drives)
    if (x.name == n) return true;
  return false;
}
std::string fresh_name(const Assembly& a, const std::string& base) {
  for (int n = 1;; ++n)
    if (!name_used(a, base + std::to_string(n))) return base + std::to_string(n);
}
// A spring, damper or contact from a to b with the palette's default values; its ref.
PartRef add_link(Assembly& a, PartRef::Kind kind, int ia, int ib) {
  switch (kind) {
    case PartRef::Kind::Spring:
      a.springs.push_back({fresh_name(a, "spring"), ia, ib, 1000.0});  // [N/m]
      return {kind, static_cast<int>(a.springs.size()) - 1};
    case PartRef::Kind::Damper:
      a.dampers.push_back({fresh_name(a, "damper"), ia, ib, 1.0});  // [N s/m]
      return {kind, static_cast<int>(a.dampers.size()) - 1};
    case PartRef::Kind::Contact:
      a.contacts.push_back({fresh_name(a, "contact"), ia, ib, model_info("gms").defaults()});
      return {kind, static_cast<int>(a.contacts.size()) - 1};
    default:
      return {};
  }
}
}  // namespace

PartRef add_part(Assembly& a, PartRef::Kind kind, int at) {
  if (at < 0 || at >= static_cast<int>(a.bodies.size())) at = a.bodies.empty() ? kGround : 0;
  switch (kind) {
    case PartRef::Kind::None:
      return {};
    case PartRef::Kind::Body: {
      a.bodies.push_back({fresh_name(a, "body"), 1.0});
      const int i = static_cast<int>(a.bodies.size()) - 1;
      a.springs.push_back({fresh_name(a, "spring"), i, at, 1000.0});
      return {kind, i};
    }
    case PartRef::Kind::Spring:
    case PartRef::Kind::Damper:
    case PartRef::Kind::Contact:
      return add_link(a, kind, at, kGround);
    case PartRef::Kind::Drive:
      a.drives.push_back(
          {fresh_name(a, "drive"), DrivePart::Kind::Force, at, Signal::constant(1.0)});
      return {kind, static_cast<int>(a.drives.size()) - 1};
  }
  return {};
}

int attachment_at(const PlantLayout& l, const Assembly& a, const PlantPose& pose, double mag,
                  float mx, float my) {
  if (!(mx >= 0.0f && my >= 0.0f && mx <= l.width && my <= l.height))
    return kNoEnd;  // off the schematic
  const float reach = 8.0f;
  for (std::size_t i = 0; i < a.bodies.size() && i < l.bodies.size(); ++i) {
    const Box& b = l.bodies[i];
    const float o = body_dx(l, pose, mag, static_cast<int>(i));
    if (mx >= b.x0 + o - reach && mx <= b.x1 + o + reach && my >= b.y0 - reach &&
        my <= b.y1 + reach)
      return static_cast<int>(i);
  }
  if (my >= l.floor_y - 2.0f) return kGround;
  if (l.wall && mx <= l.wall_x + 2.0f && my >= 0.22f * l.height) return kGround;
  return kNoEnd;
}

PartRef connect_parts(Assembly& a, PartRef::Kind kind, int from, int to) {
  const int nb = static_cast<int>(a.bodies.size());
  auto ok = [&](int e) { return e == kGround || (e >= 0 && e < nb); };
  if (!ok(from) || !ok(to) || from == to) return {};
  if (kind != PartRef::Kind::Spring && kind != PartRef::Kind::Damper &&
      kind != PartRef::Kind::Contact)
    return {};
  if (from == kGround) std::swap(from, to);
  return add_link(a, kind, from, to);
}

bool apply_plant_edit(PlantPanelState& st, const AssemblyScenario& edited) {
  try {
    auto sim =
        std::make_unique<AssemblySimulation>(edited, TraceOptions{.max_bytes = st.history_bytes});
    if (st.scenario) st.undo.push_back(*st.scenario);
    st.redo.clear();
    st.scenario = std::make_unique<AssemblyScenario>(edited);
    st.sim = std::move(sim);
    st.running = false;
    st.plotted.assign(st.sim->trace().channels.size(), 1);
    st.edit_msg.clear();
    return true;
  } catch (const std::exception& e) {
    st.edit_msg = e.what();
    return false;
  }
}

namespace {
void swap_to(PlantPanelState& st, std::vector<AssemblyScenario>& from,
             std::vector<AssemblyScenario>& to) {
  if (from.empty() || !st.scenario) return;
  AssemblyScenario s = std::move(from.back());
  from.pop_back();
  to.push_back(*st.scenario);
  st.scenario = std::make_unique<AssemblyScenario>(s);
  st.sim = std::make_unique<AssemblySimulation>(
      s, TraceOptions{.max_bytes = st.history_bytes});  // was valid when pushed
  st.running = false;
  st.plotted.assign(st.sim->trace().channels.size(), 1);
  st.selected = {};
  st.edit_msg.clear();
}
}  // namespace

void plant_detail::part_editor(PlantPanelState& st) {
  AssemblyScenario ed = *st.scenario;
  Assembly& a = ed.plant;
  const PartRef sel = st.selected;
  bool changed = false;
  std::vector<std::string> ends{"ground"};
  for (const auto& b : a.bodies) ends.push_back(b.name);
  auto end_combo = [&](const char* label, int& idx, bool ground_ok) {
    int k = idx + 1;
    ImGui::SetNextItemWidth(-80);
    if (ImGui::BeginCombo(
            label,
            ends[static_cast<std::size_t>(std::clamp(k, 0, static_cast<int>(ends.size()) - 1))]
                .c_str())) {
      for (std::size_t i = ground_ok ? 0 : 1; i < ends.size(); ++i)
        if (ImGui::Selectable(ends[i].c_str(), k == static_cast<int>(i)))
          idx = static_cast<int>(i) - 1, changed = true;
      ImGui::EndCombo();
    }
  };
  auto number = [&](const char* label, double& v, const char* tip) {
    ImGui::SetNextItemWidth(-80);
    if (ImGui::InputDouble(label, &v, 0, 0, "%.6g", ImGuiInputTextFlags_EnterReturnsTrue))
      changed = true;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tip);
  };
  auto name = [&](std::string& n) {
    ImGui::SetNextItemWidth(-80);
    if (ImGui::InputText("name", &n, ImGuiInputTextFlags_EnterReturnsTrue)) changed = true;
  };
  ImGui::Text("Selected %s", to_string(sel.kind));
  ImGui::PushID("part");
  switch (sel.kind) {
    case PartRef::Kind::None:
      ImGui::TextUnformatted("(click a part of the schematic)");
      break;
    case PartRef::Kind::Body: {
      auto& b = a.bodies[static_cast<std::size_t>(sel.index)];
      name(b.name);
      number("mass [kg]", b.mass, "Mass of the body [kg], (0, 1e9]");
      break;
    }
    case PartRef::Kind::Spring: {
      auto& x = a.springs[static_cast<std::size_t>(sel.index)];
      name(x.name);
      end_combo("a", x.a, false);
      end_combo("b", x.b, true);
      number("k [N/m]", x.stiffness, "Stiffness [N/m], [0, 1e12]; force on a: -k (x_a - x_b)");
      break;
    }
    case PartRef::Kind::Damper: {
      auto& x = a.dampers[static_cast<std::size_t>(sel.index)];
      name(x.name);
      end_combo("a", x.a, false);
      end_combo("b", x.b, true);
      number("c [N s/m]", x.damping, "Damping [N s/m], [0, 1e12]; force on a: -c (v_a - v_b)");
      break;
    }
    case PartRef::Kind::Contact: {
      auto& x = a.contacts[static_cast<std::size_t>(sel.index)];
      name(x.name);
      end_combo("a", x.a, false);
      end_combo("b", x.b, true);
      if (edit_model_choice("model", x.friction)) changed = true;
      if (edit_model_params("##contact_params", x.friction)) changed = true;
      break;
    }
    case PartRef::Kind::Drive: {
      auto& d = a.drives[static_cast<std::size_t>(sel.index)];
      name(d.name);
      end_combo("body", d.body, false);
      if (d.kind == DrivePart::Kind::Pull) {
        number("k_p [N/m]", d.pull_spring,
               "Spring from the drive point to the body [N/m], (0, 1e12]");
        number("c_p [N s/m]", d.pull_damper,
               "Damper from the drive point to the body [N s/m], [0, 1e12]");
      }
      if (d.signal.kind == Signal::Kind::Constant)
        number("value", d.signal.value, "Constant drive value (N, m or m/s by kind)");
      if (d.signal.kind == Signal::Kind::Sine) {
        number("amplitude", d.signal.amplitude, "Sine amplitude (N, m or m/s by kind)");
        number("frequency [Hz]", d.signal.frequency, "Sine frequency [Hz]");
      }
      if (d.signal.kind == Signal::Kind::Ramp)
        number("slope", d.signal.slope, "Ramp slope (per s)");
      break;
    }
  }
  ImGui::PopID();
  if (changed) apply_plant_edit(st, ed);
}

void plant_undo(PlantPanelState& st) { swap_to(st, st.undo, st.redo); }
void plant_redo(PlantPanelState& st) { swap_to(st, st.redo, st.undo); }

}  // namespace gmslab::ui
