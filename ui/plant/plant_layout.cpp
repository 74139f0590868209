// The Plant panel's geometry: where bodies, links, contacts and drives go, and the pose of a run.
#include <algorithm>
#include <cmath>

#include "ui/plant/plant_view.hpp"

namespace gmslab::ui {

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
  const float bh = std::min(
      {H * 0.2f, 90.0f, (l.floor_y - H * 0.3f) / static_cast<float>(max_level + 1) - pad_h});
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
      const int k =
          static_cast<int>(std::find(siblings.begin(), siblings.end(), i) - siblings.begin());
      const Box& s = l.bodies[support[i]];
      const float w = (s.x1 - s.x0) * 0.7f / static_cast<float>(siblings.size());
      const float cx = s.x0 + (s.x1 - s.x0) * (static_cast<float>(k) + 0.5f) /
                                  static_cast<float>(siblings.size());
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
  auto adjacent = [&](int i, int j) {
    return l.level[i] == l.level[j] && (left_neighbour(i) == j || left_neighbour(j) == i);
  };
  std::vector<int> lane_count(static_cast<std::size_t>((nb + 1) * (nb + 1)), 0);
  auto link = [&](int ia, int ib, bool damper) {
    const int key = (ia + 1) * (nb + 1) + (ib + 1);
    const int lane = lane_count[key]++;
    const Box& A = l.bodies[ia];
    const float frac =
        (damper ? 0.7f : 0.3f) + 0.12f * static_cast<float>(lane % 3) * (damper ? -1.0f : 1.0f);
    PlantLayout::Link k;
    if (ib == kGround) {
      const int nbr = left_neighbour(ia);
      const float gx = nbr < 0 ? l.wall_x : 0.5f * (l.bodies[nbr].x1 + A.x0);
      l.wall = l.wall || nbr < 0;
      k = {A.x0, A.y0 + frac * (A.y1 - A.y0), gx, A.y0 + frac * (A.y1 - A.y0), 0.0f};
    } else if (adjacent(ia, ib)) {
      const Box& B = l.bodies[ib];
      const float y = std::max(A.y0, B.y0) + frac * (std::min(A.y1, B.y1) - std::max(A.y0, B.y0));
      if (A.x1 <= B.x0)
        k = {A.x1, y, B.x0, y, 0.0f};
      else
        k = {A.x0, y, B.x1, y, 0.0f};
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
      l.contacts.push_back(
          {A.x0 + 0.08f * (A.x1 - A.x0), A.y1, A.x1 - 0.08f * (A.x1 - A.x0), l.bodies[c.b].y0});
    }
  }
  // Drives from the body's right face when nothing is to its right, else from above; a pull
  // drive's point towards the right margin on the same height.
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const int ib = a.drives[i].body;
    const Box& A = l.bodies[ib];
    bool right_free = true;
    for (int j = 0; j < nb; ++j)
      if (j != ib && l.bodies[j].x0 >= A.x1 - 1.0f && l.bodies[j].y1 > A.y0 &&
          l.bodies[j].y0 < A.y1)
        right_free = false;
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
      case Channel::Kind::ContactForce:
        p.contact_force[ch.index] = y;
        break;
      case Channel::Kind::SpringForce:
        p.spring_force[ch.index] = y;
        break;
      case Channel::Kind::DriveForce:
        p.drive_force[ch.index] = y;
        break;
      default:
        break;
    }
  }
  for (std::size_t j = 0; j < a.contacts.size(); ++j) p.slipping[j] = tr.contact_slip[j][k];
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto& d = a.drives[i];
    if (d.kind == DrivePart::Kind::Pull && !d.point_velocity)
      p.drive_point[i] = d.signal(p.t);
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

}  // namespace gmslab::ui
