// The Plant panel's schematic: ground, springs, dampers, contacts (coloured by stick / slip),
// bodies and drives, displaced to scale, with labels placed clear of the bodies and of each other.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ui/plant/plant_internal.hpp"
#include "ui/plant/plant_view.hpp"

namespace gmslab::ui {

using namespace plant_detail;

namespace {
bool prescribed_kind(DrivePart::Kind k) {
  return k == DrivePart::Kind::Displacement || k == DrivePart::Kind::Velocity;
}

std::string num(double v, const char* unit) {
  char buf[64];
  const double a = std::abs(v);
  if (a != 0.0 && (a < 1e-3 || a >= 1e5))
    std::snprintf(buf, sizeof buf, "%.3g %s", v, unit);
  else
    std::snprintf(buf, sizeof buf, "%.4g %s", v, unit);
  return buf;
}

void hatch(ImDrawList* dl, ImVec2 p0, ImVec2 p1, ImU32 col, float step = 7.0f) {
  dl->PushClipRect(p0, p1, true);
  const float h = p1.y - p0.y;
  for (float x = p0.x - h; x < p1.x; x += step) dl->AddLine({x, p1.y}, {x + h, p0.y}, col, 1.0f);
  dl->PopClipRect();
}

void text_centered(ImDrawList* dl, float cx, float y, ImU32 col, const std::string& s) {
  const ImVec2 sz = ImGui::CalcTextSize(s.c_str());
  dl->AddText({cx - 0.5f * sz.x, y}, col, s.c_str());
}

void zigzag(ImDrawList* dl, ImVec2 a, ImVec2 b, ImU32 col, float amp) {
  const float dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
  if (len < 1.0f) return;
  const float ux = dx / len, uy = dy / len, nx = -uy, ny = ux;
  const int n = 8;
  const float lead = std::min(10.0f, 0.15f * len);
  ImVec2 pts[n + 4];
  int k = 0;
  pts[k++] = a;
  pts[k++] = {a.x + ux * lead, a.y + uy * lead};
  for (int i = 0; i < n; ++i) {
    const float s =
        lead + (len - 2 * lead) * (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
    const float o = (i % 2 ? -amp : amp);
    pts[k++] = {a.x + ux * s + nx * o, a.y + uy * s + ny * o};
  }
  pts[k++] = {b.x - ux * lead, b.y - uy * lead};
  pts[k++] = b;
  dl->AddPolyline(pts, k, col, 0, 1.8f);
}

void dashpot(ImDrawList* dl, ImVec2 a, ImVec2 b, ImU32 col, float amp) {
  const float dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
  if (len < 1.0f) return;
  const float ux = dx / len, uy = dy / len, nx = -uy, ny = ux;
  // Cylinder (open towards b) fixed to b's side, piston rod from a.
  const float cyl0 = 0.45f * len, cyl1 = 0.8f * len,
              piston = std::clamp(0.6f * len, cyl0 + 3.0f, cyl1 - 3.0f);
  auto P = [&](float s, float o) { return ImVec2(a.x + ux * s + nx * o, a.y + uy * s + ny * o); };
  dl->AddLine(a, P(piston, 0), col, 1.8f);
  dl->AddLine(P(piston, -0.7f * amp), P(piston, 0.7f * amp), col, 2.5f);
  dl->AddLine(P(cyl0, -amp), P(cyl1, -amp), col, 1.8f);
  dl->AddLine(P(cyl0, amp), P(cyl1, amp), col, 1.8f);
  dl->AddLine(P(cyl1, -amp), P(cyl1, amp), col, 1.8f);
  dl->AddLine(P(cyl1, 0), b, col, 1.8f);
}

void arrow(ImDrawList* dl, ImVec2 a, ImVec2 b, ImU32 col, float thick = 2.5f) {
  const float dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
  if (len < 1.0f) return;
  const float ux = dx / len, uy = dy / len, head = std::min(12.0f, 0.5f * len);
  dl->AddLine(a, {b.x - ux * head * 0.8f, b.y - uy * head * 0.8f}, col, thick);
  dl->AddTriangleFilled(b, {b.x - ux * head - uy * head * 0.5f, b.y - uy * head + ux * head * 0.5f},
                        {b.x - ux * head + uy * head * 0.5f, b.y - uy * head - ux * head * 0.5f},
                        col);
}

std::string model_label(const ModelParams& p) {
  std::string s = p.model;
  for (auto& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  const auto& info = model_info(p.model);
  if (info.scalar_index("Fs") >= 0) s += ", Fs " + num(p.scalar("Fs"), "N");
  if (!p.elements.empty()) s += ", N = " + std::to_string(p.elements.size());
  return s;
}

std::string signal_label(const Signal& s, const char* unit) {
  switch (s.kind) {
    case Signal::Kind::Constant:
      return num(s.value, unit);
    case Signal::Kind::Ramp:
      return num(s.slope, (std::string(unit) + "/s").c_str()) + " ramp";
    case Signal::Kind::Sine:
      return num(s.amplitude, unit) + " sine " + num(s.frequency, "Hz");
    default:
      return std::string(to_string(s.kind));
  }
}
}  // namespace

namespace {
using Lines = std::vector<std::pair<std::string, ImU32>>;

// Paints one schematic: the canvas origin (X, Y), the layout, the plant, its pose and the scale,
// and the boxes taken so far (bodies, header, labels), so every label can be placed clear of them.
struct PlantPainter {
  ImDrawList* dl;
  float X, Y;
  const PlantLayout& l;
  const Assembly& a;
  const PlantPose& pose;
  double px_per_m;
  float lh = ImGui::GetTextLineHeight();
  float fy = Y + l.floor_y;  // the floor line
  PlantDrawn drawn;
  Box header{X, Y, X + l.width, Y + 8.0f + 2.0f * lh};  // time, scale and stick / slip key

  float dx(int body) const {
    if (body < 0) return 0.0f;
    const double d = pose.x[static_cast<std::size_t>(body)] * px_per_m;
    return static_cast<float>(std::clamp(d, -0.45 * l.width, 0.45 * l.width));
  }

  bool free_at(const Box& b) const {
    auto hits = [&](const Box& o) {
      return b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1;
    };
    if (hits(header)) return false;
    for (const Box& o : drawn.bodies)
      if (hits(o)) return false;
    for (const Box& o : drawn.labels)
      if (hits(o)) return false;
    return true;
  }

  // A label of one or more lines, centred on cx (or right-aligned at cx) with its top at y; where
  // it would overlap a body, the header or a label placed before, it moves by half lines (first
  // towards `dir`: -1 up, +1 down, then the other way) to the nearest free place.
  void place(float cx, float y, const Lines& lines, bool right_aligned, float dir) {
    float w = 0.0f;
    for (const auto& ln : lines) w = std::max(w, ImGui::CalcTextSize(ln.first.c_str()).x);
    const float h = lh * static_cast<float>(lines.size());
    const float x0 = right_aligned ? cx - w : cx - 0.5f * w;
    auto free_top = [&](float top) { return free_at(Box{x0, top, x0 + w, top + h}); };
    float top = y;
    for (int k = 1; k <= 16 && !free_top(top); ++k) {
      const float step = 0.5f * lh * static_cast<float>((k + 1) / 2);
      top = y + (k % 2 == 1 ? dir : -dir) * step;
    }
    if (!free_top(top)) top = y;  // nowhere free nearby: where it was meant to go
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const float lw = ImGui::CalcTextSize(lines[i].first.c_str()).x;
      const float lx = right_aligned ? cx - lw : cx - 0.5f * lw;
      dl->AddText({lx, top + lh * static_cast<float>(i)}, lines[i].second, lines[i].first.c_str());
    }
    drawn.labels.push_back({x0, top, x0 + w, top + h});
  }

  void reserve_bodies() {  // where the bodies are drawn (labels avoid them)
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
      const Box& b = l.bodies[i];
      const float o = dx(static_cast<int>(i));
      drawn.bodies.push_back({X + b.x0 + o, Y + b.y0, X + b.x1 + o, Y + b.y1});
    }
  }

  void ground() {  // floor and left wall, hatched
    dl->AddRectFilled({X, fy}, {X + l.width, fy + 14.0f}, IM_COL32(235, 235, 238, 255));
    hatch(dl, {X, fy}, {X + l.width, fy + 14.0f}, kDimInk);
    dl->AddLine({X, fy}, {X + l.width, fy}, kInk, 2.0f);
    if (!l.wall) return;
    const float wall_top = Y + 0.22f * l.height;
    dl->AddRectFilled({X + l.wall_x - 14.0f, wall_top}, {X + l.wall_x, fy},
                      IM_COL32(235, 235, 238, 255));
    hatch(dl, {X + l.wall_x - 14.0f, wall_top}, {X + l.wall_x, fy}, kDimInk);
    dl->AddLine({X + l.wall_x, wall_top}, {X + l.wall_x, fy}, kInk, 2.0f);
  }

  void link(const PlantLayout::Link& k, int ia, int ib, bool damper, const std::string& label) {
    const ImVec2 pa(X + k.ax + dx(ia), Y + k.ay), pb(X + k.bx + dx(ib), Y + k.by);
    const float amp = damper ? 6.0f : 7.0f;
    const ImU32 col = kInk;
    if (k.lift > 0.0f) {
      const ImVec2 ua(pa.x, pa.y - k.lift), ub(pb.x, pb.y - k.lift);
      dl->AddLine(pa, ua, col, 1.5f);
      dl->AddLine(pb, ub, col, 1.5f);
      damper ? dashpot(dl, ua, ub, col, amp) : zigzag(dl, ua, ub, col, amp);
      place(0.5f * (ua.x + ub.x), ua.y - lh - 4.0f, {{label, kDimInk}}, false, -1.0f);
      return;
    }
    if (ib == kGround && k.bx > l.wall_x + 1.0f) {  // a post on the floor
      dl->AddLine({pb.x, pb.y - 8.0f}, {pb.x, fy}, kInk, 2.0f);
      hatch(dl, {pb.x - 6.0f, pb.y - 8.0f}, {pb.x, fy}, kDimInk, 5.0f);
    }
    damper ? dashpot(dl, pb, pa, col, amp) : zigzag(dl, pa, pb, col, amp);
    // Labels above springs, below dampers, between the ends; without the name in a narrow gap.
    std::string text = label;
    if (ImGui::CalcTextSize(text.c_str()).x > std::abs(pb.x - pa.x) - 4.0f &&
        text.find(' ') != std::string::npos)
      text = text.substr(text.find(' ') + 1);
    place(0.5f * (pa.x + pb.x), damper ? pa.y + amp + 2.0f : pa.y - amp - lh - 2.0f,
          {{text, kDimInk}}, false, damper ? 1.0f : -1.0f);
  }

  void springs_and_dampers() {
    for (std::size_t i = 0; i < a.springs.size(); ++i) {
      const auto& s = a.springs[i];
      if (s.stiffness == 0.0) continue;  // a zero spring draws nothing (one-body presets carry one)
      std::string label = s.name + " " + num(s.stiffness, "N/m");
      if (pose.t > 0.0) label += ", " + num(pose.spring_force[i], "N");
      link(l.springs[i], s.a, s.b, false, label);
    }
    for (std::size_t i = 0; i < a.dampers.size(); ++i) {
      const auto& d = a.dampers[i];
      if (d.damping == 0.0) continue;  // a zero damper draws nothing (one-body presets carry one)
      link(l.dampers[i], d.a, d.b, true, d.name + " " + num(d.damping, "N s/m"));
    }
  }

  void contacts() {  // hatched pads coloured by stick / slip, with their force
    for (std::size_t j = 0; j < a.contacts.size(); ++j) {
      const auto& c = a.contacts[j];
      const Box& p = l.contacts[j];
      const float off = dx(c.a);
      const ImU32 col = pose.slipping[j] ? kSlip : kStick;
      const ImVec2 p0(X + p.x0 + off, Y + p.y0), p1(X + p.x1 + off, Y + p.y1);
      dl->AddRectFilled(p0, p1, (col & 0x00FFFFFF) | 0x55000000);
      hatch(dl, p0, p1, col, 5.0f);
      dl->AddRect(p0, p1, col, 0.0f, 0, 2.0f);
      const std::string label = c.name + ": " + model_label(c.friction);
      const std::string force = std::string(pose.slipping[j] ? "slip" : "stick") +
                                ", F = " + num(pose.contact_force[j], "N");
      if (c.b == kGround) {  // under the floor, staggered so neighbours do not overlap
        const float ly = fy + 18.0f + static_cast<float>(j % 2) * 2.2f * lh;
        place(0.5f * (p0.x + p1.x), ly, {{label, kInk}, {force, col}}, false, 1.0f);
      } else {  // left of the pad, right-aligned (the body below reaches further right)
        const float lx = X + l.bodies[c.a].x0 + off - 8.0f;
        place(lx, p0.y - lh, {{label, kInk}, {force, col}}, true, -1.0f);
      }
    }
  }

  void bodies() {
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
      const Box& b = l.bodies[i];
      const float o = dx(static_cast<int>(i));
      const ImVec2 p0(X + b.x0 + o, Y + b.y0), p1(X + b.x1 + o, Y + b.y1);
      dl->AddRectFilled(p0, p1, kBody, 3.0f);
      dl->AddRect(p0, p1, kInk, 3.0f, 0, 2.0f);
      const std::string m = num(a.bodies[i].mass, "kg");
      text_centered(dl, 0.5f * (p0.x + p1.x), 0.5f * (p0.y + p1.y) - lh, kInk, a.bodies[i].name);
      text_centered(dl, 0.5f * (p0.x + p1.x), 0.5f * (p0.y + p1.y), kDimInk, m);
      // No contact under a floor body: rollers (frictionless support).
      bool supported = false;
      for (const auto& c : a.contacts) supported = supported || c.a == static_cast<int>(i);
      if (!supported && l.level[i] == 0) {
        const float r = 0.5f * (fy - p1.y);
        for (float f : {0.25f, 0.75f})
          dl->AddCircle({p0.x + f * (p1.x - p0.x), p1.y + r}, r, kInk, 12, 1.5f);
      }
    }
  }

  // A pull drive: a spring (and damper) from the drive point to the body, the point moving.
  void pull_drive(std::size_t i, ImVec2 s) {
    const auto& d = a.drives[i];
    const auto& g = l.drives[i];
    const double room =
        std::max(0.0, static_cast<double>(l.width - g.px - 40.0f));  // arrow stays inside
    const float po = static_cast<float>(
        std::clamp(pose.drive_point[i] * px_per_m, -0.1 * l.width, std::min(0.1 * l.width, room)));
    const ImVec2 pt(X + g.px + po, Y + g.py);
    if (d.pull_damper > 0.0) {
      zigzag(dl, s, {pt.x, pt.y}, kDrive, 6.0f);
      dashpot(dl, {pt.x, pt.y + 16.0f}, {s.x, s.y + 16.0f}, kDrive, 5.0f);
      dl->AddLine({s.x, s.y}, {s.x, s.y + 16.0f}, kDrive, 1.5f);
      dl->AddLine({pt.x, pt.y}, {pt.x, pt.y + 16.0f}, kDrive, 1.5f);
    } else {
      zigzag(dl, s, pt, kDrive, 6.0f);
    }
    dl->AddCircleFilled(pt, 5.0f, kDrive);
    arrow(dl, {pt.x + 8.0f, pt.y}, {pt.x + 34.0f, pt.y}, kDrive);
    std::string l1 = d.name + ": " + num(d.pull_spring, "N/m");
    if (d.pull_damper > 0.0) l1 += ", " + num(d.pull_damper, "N s/m");
    place(0.5f * (s.x + pt.x), s.y - 8.0f - 2.0f * lh,
          {{l1, kInk},
           {(d.point_velocity ? "v_p " : "x_p ") +
                signal_label(d.signal, d.point_velocity ? "m/s" : "m") +
                (pose.t > 0.0 ? ", F = " + num(pose.drive_force[i], "N") : std::string()),
            kDrive}},
          false, -1.0f);
  }

  // A force, displacement or velocity drive: an arrow at the body (its length follows the force).
  void arrow_drive(std::size_t i, ImVec2 s) {
    const auto& d = a.drives[i];
    const bool force = d.kind == DrivePart::Kind::Force;
    const double f = pose.drive_force[i];
    float len = 60.0f;
    if (force && pose.t > 0.0) {
      double fmax = 0.0;
      if (d.signal.kind == Signal::Kind::Sine)
        fmax = std::abs(d.signal.offset) + std::abs(d.signal.amplitude);
      else if (d.signal.kind == Signal::Kind::Constant)
        fmax = std::abs(d.signal.value);
      if (fmax > 0.0) len = static_cast<float>(std::clamp(f / fmax, -1.0, 1.0) * 60.0);
    }
    if (std::abs(len) < 4.0f) len = len < 0 ? -4.0f : 4.0f;
    arrow(dl, s, {s.x + len, s.y}, kDrive, force ? 3.0f : 2.0f);
    if (prescribed_kind(d.kind)) dl->AddCircle(s, 6.0f, kDrive, 12, 2.0f);
    const char* what = force ? "F " : d.kind == DrivePart::Kind::Displacement ? "x " : "v ";
    const char* unit = force ? "N" : d.kind == DrivePart::Kind::Displacement ? "m" : "m/s";
    const std::string l1 = d.name + ": " + what + signal_label(d.signal, unit);
    if (pose.t > 0.0)
      place(s.x, s.y - 8.0f - 2.0f * lh, {{l1, kInk}, {"F = " + num(f, "N"), kDrive}}, false,
            -1.0f);
    else
      place(s.x, s.y - 8.0f - 2.0f * lh, {{l1, kInk}}, false, -1.0f);
  }

  void drives() {
    for (std::size_t i = 0; i < a.drives.size(); ++i) {
      const auto& d = a.drives[i];
      const auto& g = l.drives[i];
      const ImVec2 s(X + g.x + dx(d.body), Y + g.y);
      if (!g.side) dl->AddLine({s.x, Y + l.bodies[d.body].y0}, s, kDrive, 2.0f);
      if (d.kind == DrivePart::Kind::Pull)
        pull_drive(i, s);
      else
        arrow_drive(i, s);
    }
  }

  void time_and_scale() {
    char buf[160];
    std::snprintf(buf, sizeof buf, "t = %.3f s    displacements drawn to scale: 1 mm = %.3g px",
                  pose.t, px_per_m * 1e-3);
    dl->AddText({X + 6.0f, Y + 4.0f}, kDimInk, buf);
    dl->AddRectFilled({X + 6.0f, Y + 8.0f + lh}, {X + 20.0f, Y + 8.0f + 2 * lh - 2}, kStick);
    dl->AddText({X + 24.0f, Y + 8.0f + lh}, kInk, "stick");
    dl->AddRectFilled({X + 74.0f, Y + 8.0f + lh}, {X + 88.0f, Y + 8.0f + 2 * lh - 2}, kSlip);
    dl->AddText({X + 92.0f, Y + 8.0f + lh}, kInk, "slip");
  }
};
}  // namespace

PlantDrawn draw_plant(ImDrawList* dl, float X, float Y, const PlantLayout& l, const Assembly& a,
                      const PlantPose& pose, double px_per_m) {
  PlantPainter p{dl, X, Y, l, a, pose, px_per_m};
  p.reserve_bodies();
  p.ground();
  p.springs_and_dampers();
  p.contacts();
  p.bodies();
  p.drives();
  p.time_and_scale();
  return p.drawn;
}

}  // namespace gmslab::ui
