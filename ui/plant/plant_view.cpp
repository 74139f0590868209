#include "ui/plant/plant_view.hpp"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/control/assembly_plant.hpp"
#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "ui/param_editor.hpp"
#include "ui/plot/plot.hpp"
#include "ui/text_wrap.hpp"

namespace gmslab::ui {

namespace {
std::string printf_string(const char* fmt, double a, double b = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}
bool prescribed_kind(DrivePart::Kind k) { return k == DrivePart::Kind::Displacement || k == DrivePart::Kind::Velocity; }
}  // namespace

PlantLayout layout_plant(const Assembly& a, float W, float H) {
  PlantLayout l;
  l.width = W;
  l.height = H;
  const int nb = static_cast<int>(a.bodies.size());
  l.bodies.assign(nb, {});
  l.level.assign(nb, 0);
  // Stacking: a body in contact with another sits on it (its first such contact), unless that
  // would close a cycle or stack more than three high; then it stands on the floor.
  std::vector<int> support(nb, -1);
  auto depth = [&](int i) {
    int d = 0;
    for (int j = support[i]; j >= 0 && d <= nb; j = support[j]) ++d;
    return d;
  };
  for (const auto& c : a.contacts) {
    if (c.b == kGround || c.a == c.b || support[c.a] >= 0) continue;
    bool cycle = false;
    for (int j = c.b; j >= 0; j = support[j]) cycle = cycle || j == c.a;
    if (cycle || depth(c.b) >= 2) continue;
    bool carries = false;  // c.a already carries a stack: keep it on its level
    for (int j = 0; j < nb; ++j) carries = carries || support[j] == c.a;
    if (carries && depth(c.b) >= 1) continue;
    support[c.a] = c.b;
  }
  for (int i = 0; i < nb; ++i) l.level[i] = depth(i);
  std::vector<int> base;
  for (int i = 0; i < nb; ++i)
    if (support[i] < 0) base.push_back(i);
  const float margin_l = std::max(40.0f, 0.07f * W), margin_r = std::max(60.0f, 0.12f * W);
  l.wall_x = margin_l;
  l.floor_y = H * 0.74f;
  const int nbase = std::max<int>(1, static_cast<int>(base.size()));
  const float col = (W - margin_l - margin_r) / static_cast<float>(nbase);
  const int max_level = nb ? *std::max_element(l.level.begin(), l.level.end()) : 0;
  const float pad_h = std::max(8.0f, H * 0.035f);
  const float bh = std::min({H * 0.2f, 90.0f, (l.floor_y - H * 0.3f) / static_cast<float>(max_level + 1) - pad_h});
  const float bw = std::min(col * 0.42f, 150.0f);
  for (int k = 0; k < static_cast<int>(base.size()); ++k) {
    const float cx = margin_l + col * (static_cast<float>(k) + 0.5f);
    l.bodies[base[k]] = {cx - 0.5f * bw, l.floor_y - pad_h - bh, cx + 0.5f * bw, l.floor_y - pad_h};
  }
  for (int lev = 1; lev <= max_level; ++lev) {
    for (int i = 0; i < nb; ++i) {
      if (l.level[i] != lev || support[i] < 0) continue;
      std::vector<int> siblings;
      for (int j = 0; j < nb; ++j)
        if (support[j] == support[i] && l.level[j] == lev) siblings.push_back(j);
      const int k = static_cast<int>(std::find(siblings.begin(), siblings.end(), i) - siblings.begin());
      const Box& s = l.bodies[support[i]];
      const float w = (s.x1 - s.x0) * 0.7f / static_cast<float>(siblings.size());
      const float cx = s.x0 + (s.x1 - s.x0) * (static_cast<float>(k) + 0.5f) / static_cast<float>(siblings.size());
      l.bodies[i] = {cx - 0.5f * w, s.y0 - pad_h - bh * 0.8f, cx + 0.5f * w, s.y0 - pad_h};
    }
  }
  // Springs and dampers: between neighbours on one level, straight between facing sides (springs
  // in the upper part of the blocks, dampers in the lower); to ground, to the wall or a post
  // left of the body; otherwise over the bodies.
  auto left_neighbour = [&](int i) {
    int best = -1;
    for (int j = 0; j < nb; ++j)
      if (j != i && l.level[j] == l.level[i] && l.bodies[j].x1 <= l.bodies[i].x0 &&
          (best < 0 || l.bodies[j].x1 > l.bodies[best].x1))
        best = j;
    return best;
  };
  auto adjacent = [&](int i, int j) { return l.level[i] == l.level[j] && (left_neighbour(i) == j || left_neighbour(j) == i); };
  std::vector<int> lane_count(static_cast<std::size_t>((nb + 1) * (nb + 1)), 0);
  auto link = [&](int ia, int ib, bool damper) {
    const int key = (ia + 1) * (nb + 1) + (ib + 1);
    const int lane = lane_count[key]++;
    const Box& A = l.bodies[ia];
    const float frac = (damper ? 0.7f : 0.3f) + 0.12f * static_cast<float>(lane % 3) * (damper ? -1.0f : 1.0f);
    PlantLayout::Link k;
    if (ib == kGround) {
      const int nbr = left_neighbour(ia);
      const float gx = nbr < 0 ? l.wall_x : 0.5f * (l.bodies[nbr].x1 + A.x0);
      l.wall = l.wall || nbr < 0;
      k = {A.x0, A.y0 + frac * (A.y1 - A.y0), gx, A.y0 + frac * (A.y1 - A.y0), 0.0f};
    } else if (adjacent(ia, ib)) {
      const Box& B = l.bodies[ib];
      const float y = std::max(A.y0, B.y0) + frac * (std::min(A.y1, B.y1) - std::max(A.y0, B.y0));
      if (A.x1 <= B.x0) k = {A.x1, y, B.x0, y, 0.0f};
      else k = {A.x0, y, B.x1, y, 0.0f};
    } else {
      const Box& B = l.bodies[ib];
      k = {A.cx(), A.y0, B.cx(), B.y0, 0.12f * H + 0.04f * H * static_cast<float>(lane)};
    }
    return k;
  };
  for (const auto& s : a.springs) l.springs.push_back(link(s.a, s.b, false));
  for (const auto& d : a.dampers) l.dampers.push_back(link(d.a, d.b, true));
  for (const auto& c : a.contacts) {
    const Box& A = l.bodies[c.a];
    if (c.b == kGround || support[c.a] != c.b) {
      l.contacts.push_back({A.x0 + 0.12f * (A.x1 - A.x0), A.y1, A.x1 - 0.12f * (A.x1 - A.x0),
                            c.b == kGround ? l.floor_y : A.y1 + pad_h});
    } else {
      l.contacts.push_back({A.x0 + 0.08f * (A.x1 - A.x0), A.y1, A.x1 - 0.08f * (A.x1 - A.x0), l.bodies[c.b].y0});
    }
  }
  // Drives from the body's right face when nothing is to its right, else from above; a pull
  // drive's point towards the right margin on the same height.
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const int ib = a.drives[i].body;
    const Box& A = l.bodies[ib];
    bool right_free = true;
    for (int j = 0; j < nb; ++j)
      if (j != ib && l.bodies[j].x0 >= A.x1 - 1.0f && l.bodies[j].y1 > A.y0 && l.bodies[j].y0 < A.y1) right_free = false;
    PlantLayout::DriveGlyph g;
    g.side = right_free;
    g.x = right_free ? A.x1 : A.cx();
    g.y = right_free ? A.cy() : A.y0 - 0.07f * H - 0.05f * H * static_cast<float>(i % 2);
    g.px = std::max(g.x + 0.5f * margin_r, W - 0.8f * margin_r);
    g.py = g.y;
    l.drives.push_back(g);
  }
  return l;
}

PlantPose rest_pose(const Assembly& a) {
  PlantPose p;
  p.x.assign(a.bodies.size(), 0.0);
  p.contact_force.assign(a.contacts.size(), 0.0);
  p.slipping.assign(a.contacts.size(), 0);
  p.spring_force.assign(a.springs.size(), 0.0);
  p.drive_force.assign(a.drives.size(), 0.0);
  p.drive_point.assign(a.drives.size(), 0.0);
  return p;
}

PlantPose pose_of(const AssemblySimulation& sim) {
  const Assembly& a = sim.scenario().plant;
  PlantPose p = rest_pose(a);
  const AssemblyTrace& tr = sim.trace();
  p.t = sim.time();
  for (std::size_t i = 0; i < a.bodies.size(); ++i) p.x[i] = sim.positions()[i];
  if (tr.size() == 0) return p;
  const std::size_t k = tr.size() - 1;
  for (std::size_t c = 0; c < tr.channels.size(); ++c) {
    const auto& ch = tr.channels[c];
    const double y = tr.at(k, c);
    switch (ch.kind) {
      case Channel::Kind::ContactForce: p.contact_force[ch.index] = y; break;
      case Channel::Kind::SpringForce: p.spring_force[ch.index] = y; break;
      case Channel::Kind::DriveForce: p.drive_force[ch.index] = y; break;
      default: break;
    }
  }
  for (std::size_t j = 0; j < a.contacts.size(); ++j) p.slipping[j] = tr.contact_slip[j][k];
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto& d = a.drives[i];
    if (d.kind == DrivePart::Kind::Pull && !d.point_velocity) p.drive_point[i] = d.signal(p.t);
    else if (d.kind == DrivePart::Kind::Pull)  // the point's position: x + stretch of its spring
      p.drive_point[i] = p.x[d.body] + p.drive_force[i] / d.pull_spring;
  }
  return p;
}

double auto_magnification(const PlantLayout& l, const AssemblyTrace& tr) {
  double xmax = 0.0;
  for (std::size_t c = 0; c < tr.channels.size(); ++c) {
    if (tr.channels[c].kind != Channel::Kind::Position) continue;
    for (std::size_t k = 0; k < tr.size(); ++k) xmax = std::max(xmax, std::abs(tr.at(k, c)));
  }
  float col = l.width;
  for (const auto& b : l.bodies) col = std::min(col, b.x1 - b.x0);
  if (!(xmax > 0.0)) return 1.0;
  return 0.5 * col / xmax;
}

namespace {
const ImU32 kInk = IM_COL32(30, 30, 34, 255);
const ImU32 kDimInk = IM_COL32(90, 90, 98, 255);
const ImU32 kBody = IM_COL32(205, 215, 228, 255);
const ImU32 kStick = IM_COL32(0, 114, 178, 255);
const ImU32 kSlip = IM_COL32(230, 120, 0, 255);
const ImU32 kDrive = IM_COL32(0, 158, 115, 255);

std::string num(double v, const char* unit) {
  char buf[64];
  const double a = std::abs(v);
  if (a != 0.0 && (a < 1e-3 || a >= 1e5)) std::snprintf(buf, sizeof buf, "%.3g %s", v, unit);
  else std::snprintf(buf, sizeof buf, "%.4g %s", v, unit);
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
    const float s = lead + (len - 2 * lead) * (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
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
  const float cyl0 = 0.45f * len, cyl1 = 0.8f * len, piston = std::clamp(0.6f * len, cyl0 + 3.0f, cyl1 - 3.0f);
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
                        {b.x - ux * head + uy * head * 0.5f, b.y - uy * head - ux * head * 0.5f}, col);
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
    case Signal::Kind::Constant: return num(s.value, unit);
    case Signal::Kind::Ramp: return num(s.slope, (std::string(unit) + "/s").c_str()) + " ramp";
    case Signal::Kind::Sine: return num(s.amplitude, unit) + " sine " + num(s.frequency, "Hz");
    default: return std::string(to_string(s.kind));
  }
}
}  // namespace

PlantDrawn draw_plant(ImDrawList* dl, float X, float Y, const PlantLayout& l, const Assembly& a, const PlantPose& pose,
                      double px_per_m) {
  const float lh = ImGui::GetTextLineHeight();
  auto dx = [&](int body) {
    if (body < 0) return 0.0f;
    const double d = pose.x[static_cast<std::size_t>(body)] * px_per_m;
    return static_cast<float>(std::clamp(d, -0.45 * l.width, 0.45 * l.width));
  };
  PlantDrawn drawn;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {  // where the bodies are drawn (labels avoid them)
    const Box& b = l.bodies[i];
    const float o = dx(static_cast<int>(i));
    drawn.bodies.push_back({X + b.x0 + o, Y + b.y0, X + b.x1 + o, Y + b.y1});
  }
  // The header rows (time, scale, stick / slip key) are taken too.
  const Box header{X, Y, X + l.width, Y + 8.0f + 2.0f * lh};
  // A label of one or more lines, centred on cx (or right-aligned at cx) with its top at y; where it
  // would overlap a body, the header or a label placed before, it moves by half lines (first
  // towards `dir`: -1 up, +1 down, then the other way) to the nearest free place.
  auto place = [&](float cx, float y, const std::vector<std::pair<std::string, ImU32>>& lines, bool right_aligned,
                   float dir) {
    float w = 0.0f;
    for (const auto& ln : lines) w = std::max(w, ImGui::CalcTextSize(ln.first.c_str()).x);
    const float h = lh * static_cast<float>(lines.size());
    const float x0 = right_aligned ? cx - w : cx - 0.5f * w;
    auto free_at = [&](float top) {
      const Box b{x0, top, x0 + w, top + h};
      auto hits = [&](const Box& o) { return b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1; };
      if (hits(header)) return false;
      for (const Box& o : drawn.bodies)
        if (hits(o)) return false;
      for (const Box& o : drawn.labels)
        if (hits(o)) return false;
      return true;
    };
    float top = y;
    for (int k = 1; k <= 16 && !free_at(top); ++k) {
      const float step = 0.5f * lh * static_cast<float>((k + 1) / 2);
      top = y + (k % 2 == 1 ? dir : -dir) * step;
    }
    if (!free_at(top)) top = y;  // nowhere free nearby: where it was meant to go
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const float lw = ImGui::CalcTextSize(lines[i].first.c_str()).x;
      const float lx = right_aligned ? cx - lw : cx - 0.5f * lw;
      dl->AddText({lx, top + lh * static_cast<float>(i)}, lines[i].second, lines[i].first.c_str());
    }
    drawn.labels.push_back({x0, top, x0 + w, top + h});
  };
  // Ground: floor and left wall, hatched.
  const float fy = Y + l.floor_y;
  dl->AddRectFilled({X, fy}, {X + l.width, fy + 14.0f}, IM_COL32(235, 235, 238, 255));
  hatch(dl, {X, fy}, {X + l.width, fy + 14.0f}, kDimInk);
  dl->AddLine({X, fy}, {X + l.width, fy}, kInk, 2.0f);
  const float wall_top = Y + 0.22f * l.height;
  if (l.wall) {
  dl->AddRectFilled({X + l.wall_x - 14.0f, wall_top}, {X + l.wall_x, fy}, IM_COL32(235, 235, 238, 255));
  hatch(dl, {X + l.wall_x - 14.0f, wall_top}, {X + l.wall_x, fy}, kDimInk);
  dl->AddLine({X + l.wall_x, wall_top}, {X + l.wall_x, fy}, kInk, 2.0f);
  }
  // Springs and dampers.
  auto draw_link = [&](const PlantLayout::Link& k, int ia, int ib, bool damper, const std::string& label) {
    const ImVec2 pa(X + k.ax + dx(ia), Y + k.ay), pb(X + k.bx + dx(ib), Y + k.by);
    const float amp = damper ? 6.0f : 7.0f;
    const ImU32 col = kInk;
    if (k.lift > 0.0f) {
      const ImVec2 ua(pa.x, pa.y - k.lift), ub(pb.x, pb.y - k.lift);
      dl->AddLine(pa, ua, col, 1.5f);
      dl->AddLine(pb, ub, col, 1.5f);
      damper ? dashpot(dl, ua, ub, col, amp) : zigzag(dl, ua, ub, col, amp);
      place(0.5f * (ua.x + ub.x), ua.y - lh - 4.0f, {{label, kDimInk}}, false, -1.0f);
    } else {
      if (ib == kGround && k.bx > l.wall_x + 1.0f) {  // a post on the floor
        dl->AddLine({pb.x, pb.y - 8.0f}, {pb.x, fy}, kInk, 2.0f);
        hatch(dl, {pb.x - 6.0f, pb.y - 8.0f}, {pb.x, fy}, kDimInk, 5.0f);
      }
      damper ? dashpot(dl, pb, pa, col, amp) : zigzag(dl, pa, pb, col, amp);
      // Labels above springs, below dampers, between the ends; without the name in a narrow gap.
      std::string text = label;
      if (ImGui::CalcTextSize(text.c_str()).x > std::abs(pb.x - pa.x) - 4.0f && text.find(' ') != std::string::npos)
        text = text.substr(text.find(' ') + 1);
      place(0.5f * (pa.x + pb.x), damper ? pa.y + amp + 2.0f : pa.y - amp - lh - 2.0f, {{text, kDimInk}}, false,
            damper ? 1.0f : -1.0f);
    }
  };
  for (std::size_t i = 0; i < a.springs.size(); ++i) {
    const auto& s = a.springs[i];
    if (s.stiffness == 0.0) continue;  // a zero spring draws nothing (one-body presets carry one)
    std::string label = s.name + " " + num(s.stiffness, "N/m");
    if (pose.t > 0.0) label += ", " + num(pose.spring_force[i], "N");
    draw_link(l.springs[i], s.a, s.b, false, label);
  }
  for (std::size_t i = 0; i < a.dampers.size(); ++i) {
    const auto& d = a.dampers[i];
    if (d.damping == 0.0) continue;  // a zero damper draws nothing (one-body presets carry one)
    draw_link(l.dampers[i], d.a, d.b, true, d.name + " " + num(d.damping, "N s/m"));
  }
  // Contacts: hatched pads coloured by stick / slip, with their force.
  for (std::size_t j = 0; j < a.contacts.size(); ++j) {
    const auto& c = a.contacts[j];
    const Box& p = l.contacts[j];
    const float off = c.b == kGround ? dx(c.a) : dx(c.a);
    const ImU32 col = pose.slipping[j] ? kSlip : kStick;
    const ImVec2 p0(X + p.x0 + off, Y + p.y0), p1(X + p.x1 + off, Y + p.y1);
    dl->AddRectFilled(p0, p1, (col & 0x00FFFFFF) | 0x55000000);
    hatch(dl, p0, p1, col, 5.0f);
    dl->AddRect(p0, p1, col, 0.0f, 0, 2.0f);
    std::string label = c.name + ": " + model_label(c.friction);
    std::string force = std::string(pose.slipping[j] ? "slip" : "stick") + ", F = " + num(pose.contact_force[j], "N");
    if (c.b == kGround) {
      // Under the floor, staggered so neighbours do not overlap.
      const float ly = fy + 18.0f + static_cast<float>(j % 2) * 2.2f * lh;
      place(0.5f * (p0.x + p1.x), ly, {{label, kInk}, {force, col}}, false, 1.0f);
    } else {  // left of the pad, right-aligned (the body below reaches further right)
      const float lx = X + l.bodies[c.a].x0 + off - 8.0f;
      place(lx, p0.y - lh, {{label, kInk}, {force, col}}, true, -1.0f);
    }
  }
  // Bodies.
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
      for (float f : {0.25f, 0.75f}) dl->AddCircle({p0.x + f * (p1.x - p0.x), p1.y + r}, r, kInk, 12, 1.5f);
    }
  }
  // Drives.
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto& d = a.drives[i];
    const auto& g = l.drives[i];
    const float o = dx(d.body);
    const ImVec2 s(X + g.x + o, Y + g.y);
    const Box& b = l.bodies[d.body];
    if (!g.side) dl->AddLine({s.x, Y + b.y0}, s, kDrive, 2.0f);
    if (d.kind == DrivePart::Kind::Pull) {
      const double room = std::max(0.0, static_cast<double>(l.width - g.px - 40.0f));  // arrow stays inside
      const float po = static_cast<float>(std::clamp(pose.drive_point[i] * px_per_m, -0.1 * l.width, std::min(0.1 * l.width, room)));
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
             {(d.point_velocity ? "v_p " : "x_p ") + signal_label(d.signal, d.point_velocity ? "m/s" : "m") +
                  (pose.t > 0.0 ? ", F = " + num(pose.drive_force[i], "N") : std::string()),
              kDrive}},
            false, -1.0f);
    } else {
      const bool force = d.kind == DrivePart::Kind::Force;
      const double f = pose.drive_force[i];
      float len = 60.0f;
      if (force && pose.t > 0.0) {
        double fmax = 0.0;
        if (d.signal.kind == Signal::Kind::Sine) fmax = std::abs(d.signal.offset) + std::abs(d.signal.amplitude);
        else if (d.signal.kind == Signal::Kind::Constant) fmax = std::abs(d.signal.value);
        if (fmax > 0.0) len = static_cast<float>(std::clamp(f / fmax, -1.0, 1.0) * 60.0);
      }
      if (std::abs(len) < 4.0f) len = len < 0 ? -4.0f : 4.0f;
      arrow(dl, s, {s.x + len, s.y}, kDrive, force ? 3.0f : 2.0f);
      if (prescribed_kind(d.kind)) dl->AddCircle(s, 6.0f, kDrive, 12, 2.0f);
      const char* what = force ? "F " : d.kind == DrivePart::Kind::Displacement ? "x " : "v ";
      const char* unit = force ? "N" : d.kind == DrivePart::Kind::Displacement ? "m" : "m/s";
      std::string l1 = d.name + ": " + what + signal_label(d.signal, unit);
      if (pose.t > 0.0)
        place(s.x, s.y - 8.0f - 2.0f * lh, {{l1, kInk}, {"F = " + num(f, "N"), kDrive}}, false, -1.0f);
      else
        place(s.x, s.y - 8.0f - 2.0f * lh, {{l1, kInk}}, false, -1.0f);
    }
  }
  // Time and scale.
  char buf[160];
  std::snprintf(buf, sizeof buf, "t = %.3f s    displacements drawn to scale: 1 mm = %.3g px", pose.t, px_per_m * 1e-3);
  dl->AddText({X + 6.0f, Y + 4.0f}, kDimInk, buf);
  dl->AddRectFilled({X + 6.0f, Y + 8.0f + lh}, {X + 20.0f, Y + 8.0f + 2 * lh - 2}, kStick);
  dl->AddText({X + 24.0f, Y + 8.0f + lh}, kInk, "stick");
  dl->AddRectFilled({X + 74.0f, Y + 8.0f + lh}, {X + 88.0f, Y + 8.0f + 2 * lh - 2}, kSlip);
  dl->AddText({X + 92.0f, Y + 8.0f + lh}, kInk, "slip");
  return drawn;
}


const char* to_string(PartRef::Kind k) {
  switch (k) {
    case PartRef::Kind::None: return "none";
    case PartRef::Kind::Body: return "body";
    case PartRef::Kind::Spring: return "spring";
    case PartRef::Kind::Damper: return "damper";
    case PartRef::Kind::Contact: return "contact";
    case PartRef::Kind::Drive: return "drive";
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
float body_dx(const PlantLayout& l, const PlantPose& pose, double mag, int body) {
  if (body < 0) return 0.0f;
  const double d = pose.x[static_cast<std::size_t>(body)] * mag;
  return static_cast<float>(std::clamp(d, -0.45 * l.width, 0.45 * l.width));
}
}  // namespace

PartRef hit_test(const PlantLayout& l, const Assembly& a, const PlantPose& pose, double mag, float mx, float my) {
  auto dx = [&](int b) { return body_dx(l, pose, mag, b); };
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto& g = l.drives[i];
    const float x = g.x + dx(a.drives[i].body);
    if (std::hypot(mx - x, my - g.y) < 10.0f || (a.drives[i].kind == DrivePart::Kind::Pull && seg_dist(mx, my, x, g.y, g.px, g.py) < 6.0f))
      return {PartRef::Kind::Drive, static_cast<int>(i)};
  }
  for (std::size_t j = 0; j < a.contacts.size(); ++j) {
    const Box& p = l.contacts[j];
    const float o = dx(a.contacts[j].a);
    if (mx >= p.x0 + o && mx <= p.x1 + o && my >= p.y0 && my <= p.y1) return {PartRef::Kind::Contact, static_cast<int>(j)};
  }
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const Box& b = l.bodies[i];
    const float o = dx(static_cast<int>(i));
    if (mx >= b.x0 + o && mx <= b.x1 + o && my >= b.y0 && my <= b.y1) return {PartRef::Kind::Body, static_cast<int>(i)};
  }
  auto near_link = [&](const PlantLayout::Link& k, int ia, int ib) {
    const float ax = k.ax + dx(ia), bx = k.bx + dx(ib);
    if (k.lift > 0.0f) return seg_dist(mx, my, ax, k.ay - k.lift, bx, k.by - k.lift) < 8.0f;
    return seg_dist(mx, my, ax, k.ay, bx, k.by) < 8.0f;
  };
  for (std::size_t i = 0; i < a.springs.size(); ++i)
    if (near_link(l.springs[i], a.springs[i].a, a.springs[i].b)) return {PartRef::Kind::Spring, static_cast<int>(i)};
  for (std::size_t i = 0; i < a.dampers.size(); ++i)
    if (near_link(l.dampers[i], a.dampers[i].a, a.dampers[i].b)) return {PartRef::Kind::Damper, static_cast<int>(i)};
  return {};
}

Assembly remove_part(const Assembly& a, PartRef p) {
  Assembly out = a;
  auto erase = [&](auto& v) {
    if (p.index >= 0 && p.index < static_cast<int>(v.size())) v.erase(v.begin() + p.index);
  };
  switch (p.kind) {
    case PartRef::Kind::None: break;
    case PartRef::Kind::Spring: erase(out.springs); break;
    case PartRef::Kind::Damper: erase(out.dampers); break;
    case PartRef::Kind::Contact: erase(out.contacts); break;
    case PartRef::Kind::Drive: erase(out.drives); break;
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
  for (const auto& x : a.bodies) if (x.name == n) return true;
  for (const auto& x : a.springs) if (x.name == n) return true;
  for (const auto& x : a.dampers) if (x.name == n) return true;
  for (const auto& x : a.contacts) if (x.name == n) return true;
  for (const auto& x : a.drives) if (x.name == n) return true;
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
    default: return {};
  }
}
}  // namespace

PartRef add_part(Assembly& a, PartRef::Kind kind, int at) {
  if (at < 0 || at >= static_cast<int>(a.bodies.size())) at = a.bodies.empty() ? kGround : 0;
  switch (kind) {
    case PartRef::Kind::None: return {};
    case PartRef::Kind::Body: {
      a.bodies.push_back({fresh_name(a, "body"), 1.0});
      const int i = static_cast<int>(a.bodies.size()) - 1;
      a.springs.push_back({fresh_name(a, "spring"), i, at, 1000.0});
      return {kind, i};
    }
    case PartRef::Kind::Spring:
    case PartRef::Kind::Damper:
    case PartRef::Kind::Contact: return add_link(a, kind, at, kGround);
    case PartRef::Kind::Drive:
      a.drives.push_back({fresh_name(a, "drive"), DrivePart::Kind::Force, at, Signal::constant(1.0)});
      return {kind, static_cast<int>(a.drives.size()) - 1};
  }
  return {};
}

int attachment_at(const PlantLayout& l, const Assembly& a, const PlantPose& pose, double mag, float mx, float my) {
  if (!(mx >= 0.0f && my >= 0.0f && mx <= l.width && my <= l.height)) return kNoEnd;  // off the schematic
  const float reach = 8.0f;
  for (std::size_t i = 0; i < a.bodies.size() && i < l.bodies.size(); ++i) {
    const Box& b = l.bodies[i];
    const float o = body_dx(l, pose, mag, static_cast<int>(i));
    if (mx >= b.x0 + o - reach && mx <= b.x1 + o + reach && my >= b.y0 - reach && my <= b.y1 + reach) return static_cast<int>(i);
  }
  if (my >= l.floor_y - 2.0f) return kGround;
  if (l.wall && mx <= l.wall_x + 2.0f && my >= 0.22f * l.height) return kGround;
  return kNoEnd;
}

PartRef connect_parts(Assembly& a, PartRef::Kind kind, int from, int to) {
  const int nb = static_cast<int>(a.bodies.size());
  auto ok = [&](int e) { return e == kGround || (e >= 0 && e < nb); };
  if (!ok(from) || !ok(to) || from == to) return {};
  if (kind != PartRef::Kind::Spring && kind != PartRef::Kind::Damper && kind != PartRef::Kind::Contact) return {};
  if (from == kGround) std::swap(from, to);
  return add_link(a, kind, from, to);
}

bool apply_plant_edit(PlantPanelState& st, const AssemblyScenario& edited) {
  try {
    auto sim = std::make_unique<AssemblySimulation>(edited, TraceOptions{.max_bytes = st.history_bytes});
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
void swap_to(PlantPanelState& st, std::vector<AssemblyScenario>& from, std::vector<AssemblyScenario>& to) {
  if (from.empty() || !st.scenario) return;
  AssemblyScenario s = std::move(from.back());
  from.pop_back();
  to.push_back(*st.scenario);
  st.scenario = std::make_unique<AssemblyScenario>(s);
  st.sim = std::make_unique<AssemblySimulation>(s, TraceOptions{.max_bytes = st.history_bytes});  // was valid when pushed
  st.running = false;
  st.plotted.assign(st.sim->trace().channels.size(), 1);
  st.selected = {};
  st.edit_msg.clear();
}

// The selected part's fields; an edit is applied only when the plant validates.
void part_editor(PlantPanelState& st) {
  AssemblyScenario ed = *st.scenario;
  Assembly& a = ed.plant;
  const PartRef sel = st.selected;
  bool changed = false;
  std::vector<std::string> ends{"ground"};
  for (const auto& b : a.bodies) ends.push_back(b.name);
  auto end_combo = [&](const char* label, int& idx, bool ground_ok) {
    int k = idx + 1;
    ImGui::SetNextItemWidth(-80);
    if (ImGui::BeginCombo(label, ends[static_cast<std::size_t>(std::clamp(k, 0, static_cast<int>(ends.size()) - 1))].c_str())) {
      for (std::size_t i = ground_ok ? 0 : 1; i < ends.size(); ++i)
        if (ImGui::Selectable(ends[i].c_str(), k == static_cast<int>(i))) idx = static_cast<int>(i) - 1, changed = true;
      ImGui::EndCombo();
    }
  };
  auto number = [&](const char* label, double& v, const char* tip) {
    ImGui::SetNextItemWidth(-80);
    if (ImGui::InputDouble(label, &v, 0, 0, "%.6g", ImGuiInputTextFlags_EnterReturnsTrue)) changed = true;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tip);
  };
  auto name = [&](std::string& n) {
    ImGui::SetNextItemWidth(-80);
    if (ImGui::InputText("name", &n, ImGuiInputTextFlags_EnterReturnsTrue)) changed = true;
  };
  ImGui::Text("Selected %s", to_string(sel.kind));
  ImGui::PushID("part");
  switch (sel.kind) {
    case PartRef::Kind::None: ImGui::TextUnformatted("(click a part of the schematic)"); break;
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
        number("k_p [N/m]", d.pull_spring, "Spring from the drive point to the body [N/m], (0, 1e12]");
        number("c_p [N s/m]", d.pull_damper, "Damper from the drive point to the body [N s/m], [0, 1e12]");
      }
      if (d.signal.kind == Signal::Kind::Constant) number("value", d.signal.value, "Constant drive value (N, m or m/s by kind)");
      if (d.signal.kind == Signal::Kind::Sine) {
        number("amplitude", d.signal.amplitude, "Sine amplitude (N, m or m/s by kind)");
        number("frequency [Hz]", d.signal.frequency, "Sine frequency [Hz]");
      }
      if (d.signal.kind == Signal::Kind::Ramp) number("slope", d.signal.slope, "Ramp slope (per s)");
      break;
    }
  }
  ImGui::PopID();
  if (changed) apply_plant_edit(st, ed);
}
}  // namespace

void plant_undo(PlantPanelState& st) { swap_to(st, st.undo, st.redo); }
void plant_redo(PlantPanelState& st) { swap_to(st, st.redo, st.undo); }

void load_plant(PlantPanelState& st, const AssemblyScenario& s, const std::string& path) {
  auto sim = std::make_unique<AssemblySimulation>(s, TraceOptions{.max_bytes = st.history_bytes});  // validates first
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
  PlantTabSettings t{st.path, *st.scenario, st.speed, static_cast<double>(st.magnification), {}, "", "", st.tf_sliding};
  const Assembly& a = st.scenario->plant;
  if (st.sim) {
    const auto& ch = st.sim->trace().channels;
    for (std::size_t c = 0; c < ch.size() && c < st.plotted.size(); ++c)
      if (st.plotted[c]) t.plotted.push_back(ch[c].name);
  }
  if (!a.drives.empty()) t.tf_drive = a.drives[static_cast<std::size_t>(std::clamp(st.tf_drive, 0, static_cast<int>(a.drives.size()) - 1))].name;
  t.tf_output = a.bodies[static_cast<std::size_t>(std::clamp(st.tf_output, 0, static_cast<int>(a.bodies.size()) - 1))].name;
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
    const auto left = t < 0.0 ? std::size_t{1} << 20
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
    ImGui::SetTooltip("From a force drive (u = F [N]) or pull drive (u = x_p [m]) to a body's position x [m], with every "
                      "contact stuck (springs sum k_i, micro-damping) or sliding at v0 = 10 Vs (damping dF_ss/dv)");
  auto combo = [](const char* id, int& sel, const std::vector<std::string>& items) {
    sel = std::clamp(sel, 0, std::max(0, static_cast<int>(items.size()) - 1));
    ImGui::SetNextItemWidth(-1);
    if (ImGui::BeginCombo(id, items.empty() ? "" : items[static_cast<std::size_t>(sel)].c_str())) {
      for (std::size_t i = 0; i < items.size(); ++i)
        if (ImGui::Selectable(items[i].c_str(), sel == static_cast<int>(i))) sel = static_cast<int>(i);
      ImGui::EndCombo();
    }
  };
  std::vector<std::string> drives, outputs;
  for (const auto& d : a.drives) drives.push_back("from " + d.name + " (" + to_string(d.kind) + ")");
  for (const auto& b : a.bodies) outputs.push_back("to x." + b.name);
  combo("##tf_drive", st.tf_drive, drives);
  combo("##tf_output", st.tf_output, outputs);
  ImGui::Checkbox("contacts sliding", &st.tf_sliding);
  if (drives.empty()) return;
  try {
    const auto g = control::assembly_transfer_function(a, static_cast<std::size_t>(st.tf_drive),
                                                       "x." + a.bodies[static_cast<std::size_t>(st.tf_output)].name,
                                                       st.tf_sliding ? control::Regime::Sliding : control::Regime::Presliding);
    auto list = [](std::vector<control::cplx> r) {
      std::string s;
      std::sort(r.begin(), r.end(), [](auto p, auto q) { return std::abs(p) < std::abs(q); });
      for (const auto& z : r) {
        if (z.imag() < 0.0) continue;  // one of each conjugate pair
        char b[64];
        if (z.imag() > 0.0) std::snprintf(b, sizeof b, "%s%.3g Hz (zeta %.2g)", s.empty() ? "" : ", ", std::abs(z) / (2 * M_PI), -z.real() / std::abs(z));
        else std::snprintf(b, sizeof b, "%s%.3g rad/s", s.empty() ? "" : ", ", z.real());
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

void draw_plant_panel(PlantPanelState& st, double frame_dt, const std::function<std::vector<PresetChoice>()>& presets) {
  const float left_w = std::min(340.0f, ImGui::GetContentRegionAvail().x * 0.28f);
  ImGui::BeginChild("##plant_controls", ImVec2(left_w, 0), true);
  ImGui::TextUnformatted("Assembled plant preset");
  if (presets) {  // the presets, listed when the combo opens
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    if (ImGui::BeginCombo("##plant_presets", "presets")) {
      for (const PresetChoice& c : presets())
        if (ImGui::Selectable(c.label.c_str(), c.path == st.path)) {
          try {
            load_plant(st, load_assembly_scenario(c.path), c.path);
          } catch (const std::exception& e) {
            st.error = std::string("load failed: ") + e.what();
          }
        }
      ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Open a shipped or saved preset in this tab (assembled plants first)");
  }
  ImGui::SetNextItemWidth(-1);
  ImGui::InputText("##plant_path", &st.path);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Preset file (JSON): schema_version 2 (assembled plant) or 1 (one body), e.g. presets/two_mass_drive.json");
  if (ImGui::Button("Load")) {
    try {
      load_plant(st, load_assembly_scenario(st.path), st.path);
    } catch (const std::exception& e) {
      st.error = std::string("load failed: ") + e.what();
    }
  }
  if (st.sim) {
    ImGui::SameLine();
    if (ImGui::Button("Save")) {
      try {
        save_assembly_scenario(*st.scenario, st.path);
        st.error.clear();
      } catch (const std::exception& e) {
        st.error = std::string("save failed: ") + e.what();
      }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Write the plant as edited to the path above (schema_version 2, atomic)");
    ImGui::SameLine();
    if (ImGui::Button(st.running ? "Pause" : "Run")) st.running = !st.running;
    ImGui::SameLine();
    if (ImGui::Button("Reset")) {
      st.sim->reset();
      st.running = false;
    }
    ImGui::SetNextItemWidth(-1);
    float sp = static_cast<float>(st.speed);
    if (ImGui::SliderFloat("##speed", &sp, 0.01f, 10.0f, "speed %.2f x", ImGuiSliderFlags_Logarithmic)) st.speed = sp;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Simulated seconds per wall-clock second");
    ImGui::SetNextItemWidth(-1);
    ImGui::SliderFloat("##mag", &st.magnification, 0.0f, 1000.0f, st.magnification == 0.0f ? "magnification auto" : "%.1f px/mm",
                       ImGuiSliderFlags_Logarithmic);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Displacement magnification of the schematic [px per mm of displacement]; 0 = auto (the largest "
                        "displacement so far spans half the narrowest body)");
    ImGui::Separator();
    // Palette: add a part at the selected body (or the first), delete, undo / redo.
    const int at = st.selected.kind == PartRef::Kind::Body ? st.selected.index : 0;
    const PartRef::Kind kinds[] = {PartRef::Kind::Body, PartRef::Kind::Spring, PartRef::Kind::Damper, PartRef::Kind::Contact,
                                   PartRef::Kind::Drive};
    for (auto k : kinds) {
      if (k != PartRef::Kind::Body && k != PartRef::Kind::Contact) ImGui::SameLine();
      const std::string label = std::string("+") + to_string(k);
      if (ImGui::SmallButton(label.c_str())) {
        AssemblyScenario ed = *st.scenario;
        const PartRef added = add_part(ed.plant, k, at);
        if (apply_plant_edit(st, ed)) st.selected = added;
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Add a %s at the selected body (to ground); then edit it below", to_string(k));
    }
    ImGui::TextUnformatted("Drag from a body to another adds a");
    for (auto k : {PartRef::Kind::Spring, PartRef::Kind::Damper, PartRef::Kind::Contact}) {
      if (k != PartRef::Kind::Spring) ImGui::SameLine();
      if (ImGui::RadioButton(to_string(k), st.connect_kind == k)) st.connect_kind = k;
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Dragging from a body (or the ground) to another body in the schematic adds a %s between them (%s)",
                          to_string(k),
                          k == PartRef::Kind::Spring ? "1000 N/m" : k == PartRef::Kind::Damper ? "1 N s/m" : "GMS, default parameters");
    }
    if (!st.hint.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.55f, 0.35f, 0.0f, 1.0f));
      TextWrappedAtSpaces(st.hint);
      ImGui::PopStyleColor();
    }
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
    part_editor(st);
    if (!st.edit_msg.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.75f, 0.10f, 0.10f, 1.0f));
      TextWrappedAtSpaces("Not applied: " + st.edit_msg);
      ImGui::PopStyleColor();
    }
    ImGui::Separator();
    const auto& sc = *st.scenario;
    TextWrappedAtSpaces(sc.name);
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.35f, 0.35f, 0.38f, 1.0f));
    TextWrappedAtSpaces(sc.description);
    ImGui::PopStyleColor();
    const auto w = modal_frequencies(sc.plant, true);
    std::string modes;
    for (double wi : w) {
      char b[32];
      std::snprintf(b, sizeof b, "%s%.3g", modes.empty() ? "" : ", ", wi / (2 * M_PI));
      modes += b;
    }
    if (modes.empty()) TextWrappedAtSpaces("Modes: none (every body's motion is prescribed)");
    else TextWrappedAtSpaces("Modes, contacts stuck: " + modes + " Hz");
    const double lim = stability_limit_dt(sc.plant);
    if (std::isfinite(lim)) TextWrappedAtSpaces(printf_string("Step limit: dt < %.3g s (run.dt = %.3g s)", lim, sc.run.dt));
    else TextWrappedAtSpaces(printf_string("Step limit: none (nothing free and stiff; run.dt = %.3g s)", sc.run.dt));
    ImGui::Separator();
    linear_plant_section(st);
    ImGui::Separator();
    ImGui::TextUnformatted("Plotted outputs");
    const auto& ch = st.sim->trace().channels;
    for (std::size_t c = 0; c < ch.size() && c < st.plotted.size(); ++c) {
      bool on = st.plotted[c];
      const std::string label = ch[c].name + " [" + ch[c].unit + "]";
      if (ImGui::Checkbox(label.c_str(), &on)) st.plotted[c] = on;
    }
  }
  if (!st.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.75f, 0.10f, 0.10f, 1.0f));
    TextWrappedAtSpaces(st.error);
    ImGui::PopStyleColor();
  }
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("##plant_view", ImVec2(0, 0), false);
  if (!st.sim) {
    ImGui::TextUnformatted("No plant loaded: enter a preset path on the left and press Load.");
    ImGui::EndChild();
    return;
  }
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float canvas_h = std::max(220.0f, avail.y * 0.52f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const Assembly& a = st.scenario->plant;
  const PlantLayout l = layout_plant(a, avail.x, canvas_h);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(origin, {origin.x + avail.x, origin.y + canvas_h}, IM_COL32(255, 255, 255, 255));
  const double mag = st.magnification > 0.0f ? st.magnification * 1e3 : auto_magnification(l, st.sim->trace());
  const PlantPose pose = pose_of(*st.sim);
  st.canvas_drawn = draw_plant(dl, origin.x, origin.y, l, a, pose, mag);
  st.canvas_x = origin.x, st.canvas_y = origin.y, st.canvas_layout = l, st.canvas_pose = pose, st.canvas_mag = mag;
  ImGui::InvisibleButton("##plant_canvas", ImVec2(avail.x, canvas_h));
  {  // click: select a part; drag from a body (or ground) to another: connect them
    const ImVec2 m = ImGui::GetMousePos();
    const float mx = m.x - origin.x, my = m.y - origin.y;
    const char* kind = to_string(st.connect_kind);
    if (ImGui::IsItemActivated()) {
      st.selected = hit_test(l, a, pose, mag, mx, my);
      st.drag_from = attachment_at(l, a, pose, mag, mx, my);
      st.drag_x = mx, st.drag_y = my;
      st.hint.clear();
    }
    const bool moved = std::hypot(mx - st.drag_x, my - st.drag_y) >= 5.0f;
    if (ImGui::IsItemActive() && st.drag_from != kNoEnd && moved) {
      const int to = attachment_at(l, a, pose, mag, mx, my);
      const bool can = to != kNoEnd && to != st.drag_from && !(to == kGround && st.drag_from == kGround);
      dl->AddLine({origin.x + st.drag_x, origin.y + st.drag_y}, m, can ? kDrive : kDimInk, 2.5f);
      dl->AddCircleFilled({origin.x + st.drag_x, origin.y + st.drag_y}, 4.5f, kDrive);
      const std::string from = st.drag_from == kGround ? "ground" : a.bodies[static_cast<std::size_t>(st.drag_from)].name;
      if (can && to >= 0) {  // the body it would connect to, outlined
        const Box& b = l.bodies[static_cast<std::size_t>(to)];
        const float o = body_dx(l, pose, mag, to);
        dl->AddRect({origin.x + b.x0 + o - 4, origin.y + b.y0 - 4}, {origin.x + b.x1 + o + 4, origin.y + b.y1 + 4}, kDrive, 3.0f, 0, 2.5f);
      }
      if (can) {
        const std::string target = to == kGround ? "ground" : a.bodies[static_cast<std::size_t>(to)].name;
        ImGui::SetTooltip("Release to connect %s and %s with a %s", from.c_str(), target.c_str(), kind);
      } else {
        ImGui::SetTooltip("Drag to another body or the ground to connect %s with a %s", from.c_str(), kind);
      }
    }
    if (ImGui::IsItemDeactivated() && st.drag_from != kNoEnd && moved) {
      const int from = st.drag_from, to = attachment_at(l, a, pose, mag, mx, my);
      st.drag_from = kNoEnd;
      AssemblyScenario ed = *st.scenario;
      const PartRef added = connect_parts(ed.plant, st.connect_kind, from, to);
      if (added.kind == PartRef::Kind::None) {
        st.hint = to == kNoEnd ? std::string("Nothing connected: release the drag on another body or on the ground")
                               : std::string("Nothing connected: a ") + kind + " needs two different ends (a body and another body or the ground)";
      } else if (apply_plant_edit(st, ed)) {
        st.selected = added;
      }
    }
    if (ImGui::IsItemDeactivated()) st.drag_from = kNoEnd;
    if (ImGui::IsItemHovered() && !ImGui::IsItemActive()) {
      for (std::size_t i = 0; i < l.bodies.size(); ++i) {  // the attachment points
        const Box& b = l.bodies[i];
        const float o = body_dx(l, pose, mag, static_cast<int>(i));
        dl->AddCircle({origin.x + b.x0 + o, origin.y + b.cy()}, 4.0f, kDrive, 0, 2.0f);
        dl->AddCircle({origin.x + b.x1 + o, origin.y + b.cy()}, 4.0f, kDrive, 0, 2.0f);
      }
      // The hint on the schematic's own header row (after the stick / slip key), not as a tooltip
      // that would cover the plots' legends below.
      const std::string hint = std::string("click a part to edit it; drag from a body or the ground to another body: a ") + kind;
      dl->AddText({origin.x + 130.0f, origin.y + 8.0f + ImGui::GetTextLineHeight()}, kDimInk, hint.c_str());
    }
  }
  {  // the selected block or pad, outlined
    const auto& sel = st.selected;
    const Box* b = nullptr;
    int body = -1;
    if (sel.kind == PartRef::Kind::Body && sel.index < static_cast<int>(l.bodies.size())) b = &l.bodies[sel.index], body = sel.index;
    if (sel.kind == PartRef::Kind::Contact && sel.index < static_cast<int>(l.contacts.size()))
      b = &l.contacts[sel.index], body = a.contacts[sel.index].a;
    if (b) {
      const float o = body_dx(l, pose, mag, body);
      dl->AddRect({origin.x + b->x0 + o - 4, origin.y + b->y0 - 4}, {origin.x + b->x1 + o + 4, origin.y + b->y1 + 4},
                  IM_COL32(204, 121, 167, 255), 3.0f, 0, 2.5f);
    }
  }
  // Plots of the chosen outputs: lengths, velocities and forces on separate axes.
  const auto& tr = st.sim->trace();
  struct Group {
    const char* id;
    const char* name;
    const char* unit;
    std::vector<Channel::Kind> kinds;
  };
  const Group groups[] = {{"##plant_x", "x", "m", {Channel::Kind::Position}},
                          {"##plant_v", "v", "m/s", {Channel::Kind::Velocity}},
                          {"##plant_f", "F", "N",
                           {Channel::Kind::ContactForce, Channel::Kind::SpringForce, Channel::Kind::DamperForce,
                            Channel::Kind::DriveForce}}};
  std::vector<const Group*> shown;
  for (const auto& g : groups)
    for (std::size_t c = 0; c < tr.channels.size(); ++c)
      if (c < st.plotted.size() && st.plotted[c] &&
          std::find(g.kinds.begin(), g.kinds.end(), tr.channels[c].kind) != g.kinds.end()) {
        shown.push_back(&g);
        break;
      }
  std::vector<std::vector<double>> series(tr.channels.size());  // per channel, alive until EndPlot
  const float ph = shown.empty() ? 0.0f : (ImGui::GetContentRegionAvail().y - 4.0f) / static_cast<float>(shown.size());
  for (const Group* g : shown) {
    if (BeginPlot(g->id, ImVec2(-1, ph))) {
      SetupAxesSI("t", "s", g->name, g->unit);
      SetupFitRangeX(0.0, st.scenario->run.duration);
      int color = 0;
      for (std::size_t c = 0; c < tr.channels.size(); ++c) {
        if (!st.plotted[c] || std::find(g->kinds.begin(), g->kinds.end(), tr.channels[c].kind) == g->kinds.end()) continue;
        series[c] = tr.series(tr.channels[c].name);
        SeriesStyle s;
        s.color = color++;
        s.x_sorted = true;
        PlotLine(tr.channels[c].name.c_str(), tr.t.data(), series[c].data(), tr.size(), s);
      }
      EndPlot();
    }
  }
  ImGui::EndChild();
  if (st.running) {
    try {
      plant_run_until(st, st.sim->time() + st.speed * frame_dt);
      if (st.sim->finished()) st.running = false;
    } catch (const std::exception& e) {
      st.running = false;
      st.error = std::string("run stopped: ") + e.what();
    }
  }
}

}  // namespace gmslab::ui
