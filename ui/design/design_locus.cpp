// gmslab ui: the root-locus canvas of the design view (see ui/design/design_view.hpp).
#include <imgui.h>

#include <vector>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"
#include "ui/plot/plot_transform.hpp"

namespace gmslab::ui {

namespace {
using control::cplx;
constexpr double kPi = std::numbers::pi;

const ImU32 kGrid = IM_COL32(200, 200, 205, 255);
const ImU32 kAxis = IM_COL32(90, 90, 95, 255);
const ImU32 kShade = IM_COL32(213, 94, 0, 40);
const ImU32 kText = IM_COL32(60, 60, 65, 255);
const ImU32 kGridText = IM_COL32(140, 140, 150, 255);
const ImU32 kTarget = IM_COL32(204, 121, 167, 255);
const ImU32 kComp = IM_COL32(0, 158, 115, 255);
const ImU32 kPlant = IM_COL32(20, 20, 20, 255);
const ImU32 kClosed = IM_COL32(213, 94, 0, 255);

// Data box with the pixel rectangle's aspect (equal scales on both axes).
PlotTransform fit(const control::ViewBox& v, ImVec2 p0, ImVec2 p1) {
  PlotTransform t;
  t.px0 = p0.x, t.py0 = p0.y, t.px1 = p1.x, t.py1 = p1.y;
  const double w = v.width(), h = v.height();
  const double aspect = (p1.x - p0.x) / std::max(1.0f, p1.y - p0.y);
  const double cx = 0.5 * (v.re_min + v.re_max), cy = 0.5 * (v.im_min + v.im_max);
  double hw = 0.5 * w, hh = 0.5 * h;
  if (hw / hh < aspect) hw = hh * aspect;
  else hh = hw / aspect;
  t.x0 = cx - hw, t.x1 = cx + hw, t.y0 = cy - hh, t.y1 = cy + hh;
  return t;
}

ImVec2 px(const PlotTransform& t, cplx s) {
  return ImVec2(static_cast<float>(t.to_px_x(s.real())), static_cast<float>(t.to_px_y(s.imag())));
}
cplx data(const PlotTransform& t, ImVec2 p) { return {t.from_px_x(p.x), t.from_px_y(p.y)}; }

double nice_step(double range) {
  const double raw = range / 6.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) return m * mag;
  return 10 * mag;
}

void draw_grid(ImDrawList* dl, const PlotTransform& t) {
  const double R = std::hypot(std::max(std::abs(t.x0), std::abs(t.x1)), std::max(std::abs(t.y0), std::abs(t.y1)));
  // wn circles (left half plane arcs) at nice radii
  const double step = nice_step(std::min(t.x1 - t.x0, t.y1 - t.y0));
  const ImVec2 o = px(t, 0.0);
  const float scale = static_cast<float>((t.px1 - t.px0) / (t.x1 - t.x0));
  char buf[48];
  // Grid labels never overprint each other or leave the canvas: a label that would overlap one
  // already drawn (zoomed out, the zeta rays crowd near the origin) is left out.
  struct Box { float x0, y0, x1, y1; };
  std::vector<Box> placed;
  auto label = [&](ImVec2 at, const char* text) {
    const ImVec2 sz = ImGui::CalcTextSize(text);
    const Box b{at.x - 2, at.y - 1, at.x + sz.x + 2, at.y + sz.y + 1};
    if (b.x0 < t.px0 || b.x1 > t.px1 || b.y0 < t.py0 || b.y1 > t.py1) return;
    for (const Box& o : placed)
      if (b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1) return;
    placed.push_back(b);
    dl->AddText(at, kGridText, text);
  };
  for (double r = step; r < R; r += step) {
    dl->PathArcTo(o, static_cast<float>(r) * scale, static_cast<float>(kPi / 2), static_cast<float>(3 * kPi / 2), 64);
    dl->PathStroke(kGrid, 0, 1.0f);
    std::snprintf(buf, sizeof buf, "%g", r);
    const ImVec2 lp = px(t, std::polar(r, 0.53 * kPi));
    label(ImVec2(lp.x - ImGui::CalcTextSize(buf).x - 2, lp.y), buf);
  }
  // zeta rays
  for (double z : {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9}) {
    const double b = std::acos(z);
    for (double sgn : {1.0, -1.0}) {
      const cplx end = std::polar(R, kPi - sgn * b);
      dl->AddLine(o, px(t, end), kGrid, 1.0f);
    }
    const cplx lab = std::polar(0.9 * std::min(t.y1, -t.x0 > 0 ? -t.x0 : t.y1), kPi - b);
    std::snprintf(buf, sizeof buf, "%.1f", z);
    label(px(t, lab), buf);
  }
  // axes
  dl->AddLine(ImVec2(static_cast<float>(t.px0), o.y), ImVec2(static_cast<float>(t.px1), o.y), kAxis, 1.2f);
  dl->AddLine(ImVec2(o.x, static_cast<float>(t.py0)), ImVec2(o.x, static_cast<float>(t.py1)), kAxis, 1.2f);
  // tick labels along the bottom and the left edge
  const double xs = nice_step(t.x1 - t.x0);
  for (double x = std::ceil(t.x0 / xs) * xs; x <= t.x1; x += xs) {
    std::snprintf(buf, sizeof buf, "%g", std::abs(x) < 1e-12 * xs ? 0.0 : x);
    dl->AddText(ImVec2(static_cast<float>(t.to_px_x(x)) + 2, static_cast<float>(t.py1) - ImGui::GetFontSize() - 2), kText, buf);
  }
  const double ys = nice_step(t.y1 - t.y0);
  for (double y = std::ceil(t.y0 / ys) * ys; y <= t.y1; y += ys) {
    if (std::abs(y) < 1e-12 * ys) continue;
    std::snprintf(buf, sizeof buf, "%gj", y);
    dl->AddText(ImVec2(static_cast<float>(t.px0) + 3, static_cast<float>(t.to_px_y(y)) - ImGui::GetFontSize()), kText, buf);
  }
}

// Shade where the requirements fail: zeta < zeta_min (a sector around the imaginary axis and the
// right half plane) and Re s > -sigma_min (a strip).
void draw_requirements(ImDrawList* dl, const PlotTransform& t, double zeta_min, double sigma_min) {
  const double R = 4 * std::hypot(t.x1 - t.x0, t.y1 - t.y0) + std::abs(t.x0) + std::abs(t.x1);
  const double b = std::acos(zeta_min);
  for (double sgn : {1.0, -1.0}) {
    dl->PathLineTo(px(t, 0.0));
    for (int i = 0; i <= 32; ++i) dl->PathLineTo(px(t, std::polar(R, sgn * (kPi - b) * i / 32.0)));
    dl->PathFillConvex(kShade);
  }
  if (sigma_min > 0.0)
    dl->AddRectFilled(px(t, cplx(-sigma_min, t.y1)), px(t, cplx(0.0, t.y0)), kShade);
}

void cross(ImDrawList* dl, ImVec2 p, float r, ImU32 c, float th) {
  dl->AddLine(ImVec2(p.x - r, p.y - r), ImVec2(p.x + r, p.y + r), c, th);
  dl->AddLine(ImVec2(p.x - r, p.y + r), ImVec2(p.x + r, p.y - r), c, th);
}

// A secondary locus (the other regime's, or the 0-degree one): thin branches in `col` and pole
// crosses, no asymptotes.
void draw_other_locus(ImDrawList* dl, const PlotTransform& t, const control::RootLocus& rl,
                      ImU32 col = IM_COL32(150, 150, 160, 200)) {
  const double far = 20 * std::hypot(t.x1 - t.x0, t.y1 - t.y0);
  for (const auto& br : rl.branches)
    for (std::size_t i = 1; i < br.size(); ++i) {
      const cplx a = br[i - 1], c = br[i];
      if (std::isnan(a.real()) || std::isnan(c.real()) || std::abs(a) > far || std::abs(c) > far) continue;
      dl->AddLine(px(t, a), px(t, c), col, 1.2f);
    }
  for (const cplx& p : rl.poles) {
    const ImVec2 q = px(t, p);
    dl->AddLine(ImVec2(q.x - 4, q.y - 4), ImVec2(q.x + 4, q.y + 4), col, 1.5f);
    dl->AddLine(ImVec2(q.x - 4, q.y + 4), ImVec2(q.x + 4, q.y - 4), col, 1.5f);
  }
}

// The axis caption, in the frame's bottom-right corner above the x tick labels, on a white backing:
// the long form when it takes at most 3/4 of the frame's width, else the short one (so it never
// runs past the frame's left edge into the y tick labels at projector sizes).
void axis_caption(ImDrawList* dl, ImVec2 p0, ImVec2 p1, const char* long_form, const char* short_form) {
  const float fh = ImGui::GetFontSize();
  const char* label = ImGui::CalcTextSize(long_form).x <= 0.75f * (p1.x - p0.x) ? long_form : short_form;
  const ImVec2 sz = ImGui::CalcTextSize(label);
  const ImVec2 at(std::max(p0.x + 4.0f * fh, p1.x - sz.x - 8), p1.y - 2 * fh - 6);
  dl->PushClipRect(p0, p1, true);
  dl->AddRectFilled(ImVec2(at.x - 3, at.y - 1), ImVec2(at.x + sz.x + 3, at.y + sz.y + 1), IM_COL32(255, 255, 255, 225));
  dl->AddText(at, kText, label);
  dl->PopClipRect();
}

void draw_locus(ImDrawList* dl, const PlotTransform& t, const control::RootLocus& rl) {
  // asymptotes
  for (double a : rl.asymptote_angles) {
    const cplx c(rl.centroid, 0.0);
    const double R = 4 * std::hypot(t.x1 - t.x0, t.y1 - t.y0);
    const ImVec2 p0 = px(t, c), p1 = px(t, c + std::polar(R, a));
    const int n = 60;
    for (int i = 0; i < n; i += 2)
      dl->AddLine(ImVec2(p0.x + (p1.x - p0.x) * i / n, p0.y + (p1.y - p0.y) * i / n),
                  ImVec2(p0.x + (p1.x - p0.x) * (i + 1) / n, p0.y + (p1.y - p0.y) * (i + 1) / n),
                  IM_COL32(120, 120, 120, 200), 1.0f);
  }
  const double far = 20 * std::hypot(t.x1 - t.x0, t.y1 - t.y0);
  for (std::size_t b = 0; b < rl.branches.size(); ++b) {
    const ImU32 col = palette(static_cast<int>(b % 6));
    const auto& br = rl.branches[b];
    for (std::size_t i = 1; i < br.size(); ++i) {
      const cplx a = br[i - 1], c = br[i];
      if (std::isnan(a.real()) || std::isnan(c.real()) || std::abs(a) > far || std::abs(c) > far) continue;
      dl->AddLine(px(t, a), px(t, c), col, 2.0f);
    }
  }
  for (const auto& p : rl.breakaways) dl->AddCircleFilled(px(t, p.s), 3.0f, kAxis);
  for (const auto& p : rl.crossings) {
    dl->AddCircleFilled(px(t, p.s), 3.5f, kClosed);
    dl->AddCircleFilled(px(t, std::conj(p.s)), 3.5f, kClosed);
  }
}

bool near_px(ImVec2 a, ImVec2 b, float r) { return std::hypot(a.x - b.x, a.y - b.y) <= r; }

void handle_input(DesignViewState& d, const PlotTransform& t, bool hovered) {
  ImGuiIO& io = ImGui::GetIO();
  const ImVec2 m = io.MousePos;
  const control::DesignOutputs& out = d.out;
  const cplx sd = control::design_root(d.settings).s();
  const float grab = 9.0f;
  if (hovered && ImGui::IsMouseClicked(0)) {
    d.drag = DesignViewState::Drag::None;
    if (near_px(m, px(t, sd), grab) || near_px(m, px(t, std::conj(sd)), grab)) d.drag = DesignViewState::Drag::Root;
    else if (out.compensator) {
      // Every section's zero and pole is a handle (the first one under the mouse: zeros first).
      const control::LeadCompensator& c = *out.compensator;
      for (int i = 0; i < c.sections() && d.drag == DesignViewState::Drag::None; ++i)
        if (near_px(m, px(t, cplx(-c.section(i).z, 0)), grab)) d.drag = DesignViewState::Drag::Zero, d.drag_section = i;
      for (int i = 0; i < c.sections() && d.drag == DesignViewState::Drag::None; ++i)
        if (near_px(m, px(t, cplx(-c.section(i).p, 0)), grab)) d.drag = DesignViewState::Drag::Pole, d.drag_section = i;
    }
    if (d.drag != DesignViewState::Drag::None && !d.in.locus_view) {
      // Freeze the view while a handle is dragged, so the point under the mouse stays put.
      d.in.locus_view = control::ViewBox{t.x0, t.x1, t.y0, t.y1};
    }
    if (d.drag == DesignViewState::Drag::None) {
      // Pick the nearest branch sample within 12 px.
      double best = 12.0;
      std::size_t bi = 0, si = 0;
      bool found = false;
      for (std::size_t b = 0; b < out.locus.branches.size(); ++b)
        for (std::size_t i = 0; i < out.locus.branches[b].size(); ++i) {
          const cplx s = out.locus.branches[b][i];
          if (std::isnan(s.real())) continue;
          const ImVec2 p = px(t, s);
          const double dd = std::hypot(p.x - m.x, p.y - m.y);
          if (dd < best) best = dd, bi = b, si = i, found = true;
        }
      d.picked = found;
      if (found) {
        d.picked_k = out.locus.gains[si];
        d.picked_s = out.locus.branches[bi][si];
        d.picked_poles = control::closed_loop_poles(out.loop, d.picked_k);
      } else {
        d.drag = DesignViewState::Drag::Pan;
      }
    }
  }
  if (!ImGui::IsMouseDown(0)) d.drag = DesignViewState::Drag::None;
  const cplx s = data(t, m);
  switch (d.drag) {
    case DesignViewState::Drag::Root: {
      const cplx u(std::min(s.real(), -1e-9), std::max(std::abs(s.imag()), 1e-9));
      d.settings.wn = std::abs(u);
      d.settings.zeta = std::clamp(-u.real() / std::abs(u), 0.01, 0.99);
      d.dirty = true;
      break;
    }
    case DesignViewState::Drag::Zero:
    case DesignViewState::Drag::Pole: {
      control::LeadCompensator c = *out.compensator;
      const double v = std::max(-s.real(), 1e-6 * (t.x1 - t.x0));
      const bool zero = d.drag == DesignViewState::Drag::Zero;
      if (d.drag_section == 0 || !c.second) (zero ? c.z : c.p) = v;
      else (zero ? c.second->z : c.second->p) = v;
      d.in.manual = c;
      d.dirty = true;
      break;
    }
    case DesignViewState::Drag::Pan:
      if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
        const PlotTransform n = t.panned(io.MouseDelta.x, io.MouseDelta.y);
        d.in.locus_view = control::ViewBox{n.x0, n.x1, n.y0, n.y1};
        d.dirty = true;
      }
      break;
    case DesignViewState::Drag::None: break;
  }
  if (hovered && io.MouseWheel != 0.0f) {
    const double f = std::pow(0.85, io.MouseWheel);
    const PlotTransform n = t.zoomed(m.x, m.y, f, f);
    d.in.locus_view = control::ViewBox{n.x0, n.x1, n.y0, n.y1};
    d.dirty = true;
  }
  if (hovered && ImGui::IsMouseDoubleClicked(0)) {
    d.in.locus_view.reset();
    d.dirty = true;
  }
  if (hovered && d.drag == DesignViewState::Drag::None) {
    const double wn = std::abs(s), z = wn > 0 ? -s.real() / wn : 0.0;
    ImGui::SetTooltip("s = %.4g %+.4gj rad/s\nzeta = %.3f, wn = %.4g rad/s\n"
                      "drag the diamond (s_d), the green o (zero) or x (pole); click a branch\n"
                      "to read its gain; wheel zooms, drag pans, double-click fits",
                      s.real(), s.imag(), z, wn);
  }
}
// The z-plane locus of the sampled loop (d.out.z_locus): unit circle, the s-plane damping / wn
// grid mapped by z = e^{sT}, branches, open-loop poles (x) and zeros (o), the closed-loop poles at
// Kc (squares), the unit-circle crossings with their gains, s_d mapped (diamond).
void draw_z_locus(DesignViewState& d, ImVec2 size) {
  const control::ZLocus& zl = *d.out.z_locus;
  const double T = zl.T;
  char buf[200];
  const double Kc = d.out.compensator ? d.out.compensator->Kc : 1.0;
  const std::string ku_s = control::loop_units(d.out.source, d.out.port).gain;
  const char* ku = ku_s.c_str();
  bool stable = false;
  double k_hi = 0.0;
  for (const auto& [lo, hi] : zl.stable_gains)
    if (Kc > lo && Kc < hi) stable = true, k_hi = hi;
  if (stable && std::isfinite(k_hi))
    std::snprintf(buf, sizeof buf, "z plane, T = %.3g s: stable at Kc = %.4g %s, up to %.4g %s (x%.3g)", T, Kc, ku, k_hi, ku,
                  k_hi / Kc);
  else if (stable)
    std::snprintf(buf, sizeof buf, "z plane, T = %.3g s: stable at Kc = %.4g %s (no upper limit)", T, Kc, ku);
  else
    std::snprintf(buf, sizeof buf, "z plane, T = %.3g s: UNSTABLE at Kc = %.4g %s (a pole outside |z| = 1)", T, Kc, ku);
  ImGui::TextColored(stable ? ImVec4(0.0f, 0.5f, 0.3f, 1.0f) : ImVec4(0.75f, 0.1f, 0.1f, 1.0f), "%s", buf);
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  size.y -= ImGui::GetTextLineHeightWithSpacing();
  ImGui::InvisibleButton("##zlocus", size);
  const bool hovered = ImGui::IsItemHovered();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  const PlotTransform t = fit(d.in.z_locus_view ? *d.in.z_locus_view : zl.locus.view, p0, p1);
  d.z_canvas = t;
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, p1, IM_COL32(255, 255, 255, 255));
  dl->PushClipRect(p0, p1, true);
  // grid: constant damping (spirals) and constant wn (arcs) of z = e^{sT}, upper and lower halves
  const double wN = kPi / T;
  auto poly_z = [&](auto s_of, int n) {
    for (double sg : {1.0, -1.0}) {
      for (int i = 0; i <= n; ++i) {
        const cplx s = s_of(static_cast<double>(i) / n);
        dl->PathLineTo(px(t, std::exp(cplx(s.real(), sg * s.imag()) * T)));
      }
      dl->PathStroke(kGrid, 0, 1.0f);
    }
  };
  for (double z : {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9}) {
    const double c = std::sqrt(1 - z * z);
    poly_z([&](double u) { return cplx(-z, c) * (u * wN / c); }, 48);
  }
  for (int k = 1; k <= 10; ++k) {
    const double wn = k * 0.1 * wN;
    poly_z([&](double u) { return cplx(-u * wn, wn * std::sqrt(std::max(0.0, 1 - u * u))); }, 32);
  }
  const ImVec2 o = px(t, 0.0);
  dl->AddLine(ImVec2(static_cast<float>(t.px0), o.y), ImVec2(static_cast<float>(t.px1), o.y), kAxis, 1.2f);
  dl->AddLine(ImVec2(o.x, static_cast<float>(t.py0)), ImVec2(o.x, static_cast<float>(t.py1)), kAxis, 1.2f);
  const float scale = static_cast<float>((t.px1 - t.px0) / (t.x1 - t.x0));
  dl->AddCircle(o, scale, IM_COL32(40, 40, 45, 255), 128, 2.0f);
  const double xs = nice_step(t.x1 - t.x0);
  for (double x = std::ceil(t.x0 / xs) * xs; x <= t.x1; x += xs) {
    std::snprintf(buf, sizeof buf, "%g", std::abs(x) < 1e-12 * xs ? 0.0 : x);
    dl->AddText(ImVec2(static_cast<float>(t.to_px_x(x)) + 2, static_cast<float>(t.py1) - ImGui::GetFontSize() - 2), kText, buf);
  }
  for (double y = std::ceil(t.y0 / xs) * xs; y <= t.y1; y += xs) {
    if (std::abs(y) < 1e-12 * xs) continue;
    std::snprintf(buf, sizeof buf, "%gj", y);
    dl->AddText(ImVec2(static_cast<float>(t.px0) + 3, static_cast<float>(t.to_px_y(y)) - ImGui::GetFontSize()), kText, buf);
  }
  const double far = 20 * std::hypot(t.x1 - t.x0, t.y1 - t.y0);
  for (std::size_t b = 0; b < zl.locus.branches.size(); ++b) {
    const ImU32 col = palette(static_cast<int>(b % 6));
    const auto& br = zl.locus.branches[b];
    for (std::size_t i = 1; i < br.size(); ++i) {
      const cplx a = br[i - 1], c = br[i];
      if (std::isnan(a.real()) || std::isnan(c.real()) || std::abs(a) > far || std::abs(c) > far) continue;
      dl->AddLine(px(t, a), px(t, c), col, 2.0f);
    }
  }
  const float r = 6.0f;
  for (const cplx& p : zl.locus.poles) cross(dl, px(t, p), r, kPlant, 2.2f);
  for (const cplx& z : zl.locus.zeros) dl->AddCircle(px(t, z), r, kPlant, 20, 2.2f);
  if (d.out.discrete)
    for (const cplx& p : d.out.discrete->closed_loop_poles) {
      const ImVec2 q = px(t, p);
      dl->AddRectFilled(ImVec2(q.x - 4, q.y - 4), ImVec2(q.x + 4, q.y + 4), kClosed);
    }
  for (const auto& c : zl.crossings) {
    for (const cplx& z : {c.z, std::conj(c.z)}) dl->AddCircleFilled(px(t, z), 4.0f, IM_COL32(204, 0, 0, 255));
    std::snprintf(buf, sizeof buf, "k = %.4g", c.k);
    const ImVec2 q = px(t, c.z);
    dl->AddText(ImVec2(q.x + 6, q.y - ImGui::GetFontSize() - 2), kText, buf);
  }
  const cplx zd = std::exp(control::design_root(d.settings).s() * T);
  for (const cplx& z : {zd, std::conj(zd)}) {
    const ImVec2 q = px(t, z);
    const float a = 8.0f;
    dl->AddQuad(ImVec2(q.x, q.y - a), ImVec2(q.x + a, q.y), ImVec2(q.x, q.y + a), ImVec2(q.x - a, q.y), kTarget, 2.5f);
  }
  dl->PopClipRect();
  dl->AddRect(p0, p1, kAxis);
  axis_caption(dl, p0, p1, "Re z (horizontal), Im z (vertical); unit circle: stability boundary", "Re z ->, Im z ^");
  // Wheel zooms about the mouse, drag pans, double-click fits; the locus is recomputed for the
  // new view (its resolution is relative to the view).
  ImGuiIO& io = ImGui::GetIO();
  if (hovered && io.MouseWheel != 0.0f) {
    const double f = std::pow(0.85, io.MouseWheel);
    const PlotTransform n = t.zoomed(io.MousePos.x, io.MousePos.y, f, f);
    d.in.z_locus_view = control::ViewBox{n.x0, n.x1, n.y0, n.y1};
    d.dirty = true;
  }
  if (ImGui::IsItemActive() && ImGui::IsMouseDragging(0) && (io.MouseDelta.x != 0 || io.MouseDelta.y != 0)) {
    const PlotTransform n = t.panned(io.MouseDelta.x, io.MouseDelta.y);
    d.in.z_locus_view = control::ViewBox{n.x0, n.x1, n.y0, n.y1};
    d.dirty = true;
  }
  if (hovered && ImGui::IsMouseDoubleClicked(0)) {
    d.in.z_locus_view.reset();
    d.dirty = true;
  }
  if (hovered) {
    const cplx z = data(t, ImGui::GetIO().MousePos);
    const cplx s = std::log(z) / T;
    const double wn = std::abs(s), zeta = wn > 0 ? -s.real() / wn : 0.0;
    ImGui::SetTooltip("z = %.4g %+.4gj, |z| = %.4g\ns = ln(z)/T = %.4g %+.4gj rad/s: zeta = %.3f, wn = %.4g rad/s\n"
                      "grey grid: constant zeta (spirals) and wn (arcs, steps of 0.1 pi/T) of z = e^{sT}\n"
                      "wheel zooms, drag pans, double-click fits",
                      z.real(), z.imag(), std::abs(z), s.real(), s.imag(), zeta, wn);
  }
}
}  // namespace

double zeta_for_overshoot(double os) {
  if (os <= 0.0) return 0.999;
  const double l = std::log(os / 100.0);
  return std::clamp(-l / std::sqrt(kPi * kPi + l * l), 0.0, 0.999);
}

void draw_design_locus(DesignViewState& d, ImVec2 size) {
  const float y_before = ImGui::GetCursorPosY();
  ImGui::BeginGroup();
  if (d.out.z_locus) {
    ImGui::Checkbox("z plane", &d.z_plane);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("The locus of the sampled loop (Tustin controller, ZOH plant) in z, with the unit circle;\n"
                        "off: the continuous s-plane locus with its draggable handles");
    if (d.z_plane) {
      ImGui::SameLine();
      ImGui::TextDisabled("Locus in Kc.  x pole  o zero  square: closed loop at Kc  red dot: leaves |z| = 1  "
                          "diamond: e^{s_d T}");
      size.y -= ImGui::GetCursorPosY() - y_before;
      draw_z_locus(d, size);
      ImGui::EndGroup();
      return;
    }
  }
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + size.x);
  ImGui::TextDisabled("Locus in Kc.  x pole  o zero  green: compensator  square: closed loop at Kc  "
                      "diamond: s_d  shaded: requirement fails  dashed: asymptotes%s%s",
                      d.out.other_locus ? "  grey: other regime" : "",
                      d.out.zero_degree_locus ? "  light blue: 0-degree (k < 0)" : "");
  ImGui::PopTextWrapPos();
  size.y -= ImGui::GetCursorPosY() - y_before;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##locus", size);
  const bool hovered = ImGui::IsItemHovered();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  const control::ViewBox v = d.in.locus_view ? *d.in.locus_view : d.out.locus.view;
  const PlotTransform t = fit(v, p0, p1);
  d.canvas = t;
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, p1, IM_COL32(255, 255, 255, 255));
  dl->PushClipRect(p0, p1, true);
  draw_requirements(dl, t, zeta_for_overshoot(d.settings.max_overshoot), 4.0 / d.settings.settling_time);
  draw_grid(dl, t);
  if (d.out.other_locus) draw_other_locus(dl, t, *d.out.other_locus);
  if (d.out.zero_degree_locus) draw_other_locus(dl, t, *d.out.zero_degree_locus, IM_COL32(86, 180, 233, 170));
  draw_locus(dl, t, d.out.locus);
  const float r = 6.0f;
  // plant poles (black x) and zeros (o); compensator zero/pole in green
  const auto& rl = d.out.locus;
  std::vector<cplx> comp;
  if (d.out.compensator) {
    for (double z : d.out.compensator->zeros()) comp.emplace_back(-z, 0.0);
    for (double p : d.out.compensator->poles()) comp.emplace_back(-p, 0.0);
  }
  auto is_comp = [&](cplx s) {
    for (const cplx& c : comp)
      if (std::abs(c - s) <= 1e-9 * (1 + std::abs(c))) return true;
    return false;
  };
  for (const cplx& p : rl.poles) cross(dl, px(t, p), r, is_comp(p) ? kComp : kPlant, 2.2f);
  // Poles and zeros beyond the left edge: a marker on the edge with their value.
  float y_off = 0.0f;
  auto offscreen = [&](cplx s, const char* kind, ImU32 col) {
    if (s.real() >= t.x0 || std::abs(s.imag()) > t.y1) return;
    char buf[48];
    std::snprintf(buf, sizeof buf, "<- %s %.4g", kind, s.real());
    const ImVec2 q(static_cast<float>(t.px0) + 4, px(t, s).y + 4 + y_off);
    dl->AddText(q, col, buf);
    y_off += ImGui::GetFontSize();
  };
  for (const cplx& p : rl.poles) offscreen(p, "pole", is_comp(p) ? kComp : kPlant);
  for (const cplx& z : rl.zeros) offscreen(z, "zero", is_comp(z) ? kComp : kPlant);
  for (const cplx& p : d.out.closed_loop_poles)
    if (p.imag() >= 0) offscreen(p, "closed-loop pole", kClosed);
  for (const cplx& z : rl.zeros) dl->AddCircle(px(t, z), r, is_comp(z) ? kComp : kPlant, 20, 2.2f);
  for (const cplx& p : d.out.closed_loop_poles) {
    const ImVec2 q = px(t, p);
    dl->AddRectFilled(ImVec2(q.x - 4, q.y - 4), ImVec2(q.x + 4, q.y + 4), kClosed);
  }
  // desired dominant roots: diamonds
  for (const cplx& s : {control::design_root(d.settings).s(), std::conj(control::design_root(d.settings).s())}) {
    const ImVec2 q = px(t, s);
    const float a = 8.0f;
    dl->AddQuad(ImVec2(q.x, q.y - a), ImVec2(q.x + a, q.y), ImVec2(q.x, q.y + a), ImVec2(q.x - a, q.y), kTarget, 2.5f);
  }
  if (d.picked) {
    for (const cplx& p : d.picked_poles) dl->AddCircle(px(t, p), 7.0f, IM_COL32(86, 180, 233, 255), 16, 2.0f);
    char buf[64];
    std::snprintf(buf, sizeof buf, "k = %.4g %s", d.picked_k, control::loop_units(d.out.source, d.out.port).gain.c_str());
    const ImVec2 q = px(t, d.picked_s);
    dl->AddText(ImVec2(q.x + 9, q.y - 18), kText, buf);
  }
  dl->PopClipRect();
  dl->AddRect(p0, p1, kAxis);
  axis_caption(dl, p0, p1, "Re s [rad/s] (horizontal), Im s [rad/s] (vertical)", "Re s ->, Im s ^ [rad/s]");
  handle_input(d, t, hovered);
  ImGui::EndGroup();
}

}  // namespace gmslab::ui
