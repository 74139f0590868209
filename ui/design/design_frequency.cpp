// gmslab ui: the design view's frequency responses (see ui/design/design_view.hpp): open-loop Bode
// (magnitude and phase, crossovers and margins marked), closed-loop magnitude, and the Nyquist
// plot of the same loop with the critical point -1. All from DesignOutputs::frequency, which the
// panel recomputes with the locus on every drag.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"

namespace gmslab::ui {

namespace {
using control::cplx;
const ImU32 kAxis = IM_COL32(90, 90, 95, 255);
const ImU32 kGrid = IM_COL32(215, 215, 220, 255);
const ImU32 kText = IM_COL32(60, 60, 65, 255);
const ImU32 kCritical = IM_COL32(213, 94, 0, 255);

// Vertical marker at x over the y range of the data.
void vline(const char* label, double x, double y0, double y1, int color) {
  const double xs[2] = {x, x}, ys[2] = {y0, y1};
  PlotLine(label, xs, ys, 2, {.color = color, .line = LineStyle::Dashed, .thickness = 1.0f});
}

void draw_bode(const control::FrequencyReport& f, const control::DiscreteFrequencyReport* dz, ImVec2 size) {
  const auto& o = f.open;
  const auto& c = f.closed;
  const auto& m = f.margins;
  std::vector<double> lw(o.w.size());
  for (std::size_t i = 0; i < o.w.size(); ++i) lw[i] = std::log10(o.w[i]);
  std::vector<double> dzw, dz_phase;
  if (dz && !dz->open.w.empty() && !o.w.empty()) {
    for (double w : dz->open.w) dzw.push_back(std::log10(w));
    // The sampled phase is defined modulo 360 deg: align it with the continuous one where the two
    // loops agree (the lowest sampled frequency, nearest continuous sample).
    const std::size_t i = static_cast<std::size_t>(
        std::lower_bound(o.w.begin(), o.w.end(), dz->open.w.front()) - o.w.begin());
    const double ref = o.phase_deg[std::min(i, o.w.size() - 1)];
    const double shift = 360.0 * std::round((ref - dz->open.phase_deg.front()) / 360.0);
    for (double ph : dz->open.phase_deg) dz_phase.push_back(ph + shift);
  }
  if (dzw.empty()) dz = nullptr;
  const float gap = ImGui::GetStyle().ItemSpacing.y;
  const float h = std::floor(0.5f * (size.y - gap));
  static char title[200];
  const auto num = [](double v, const char* fmt, char* buf, std::size_t n) {
    if (std::isfinite(v)) std::snprintf(buf, n, fmt, v);
    else std::snprintf(buf, n, "inf");
    return buf;
  };
  char gm[32], pm[32], bw[32];
  std::snprintf(title, sizeof title, "GM %s dB, w_b %s rad/s",
                num(m.gain_margin_db, "%.3g", gm, sizeof gm), num(f.bandwidth, "%.4g", bw, sizeof bw));
  PlotOptions po;
  po.title = title;
  po.legend = false;
  if (BeginPlot("##bode_mag", ImVec2(size.x, h), po)) {
    SetupAxes("log10 w [rad/s]", "|L| blue, |T| green [dB]");
    PlotLine("open loop L", lw.data(), o.mag_db.data(), lw.size(), {.color = 0, .x_sorted = true});
    PlotLine("closed loop T", lw.data(), c.mag_db.data(), lw.size(), {.color = 2, .x_sorted = true});
    if (dz) PlotLine("sampled L", dzw.data(), dz->open.mag_db.data(), dzw.size(), {.color = 1, .x_sorted = true});
    const double x0 = lw.empty() ? 0 : lw.front(), x1 = lw.empty() ? 1 : lw.back();
    const double zx[2] = {x0, x1}, zy[2] = {0.0, 0.0};
    PlotLine("0 dB", zx, zy, 2, {.color = 6, .line = LineStyle::Dotted, .thickness = 1.0f});
    double lo = 0, hi = 0;
    for (double v : o.mag_db)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (std::isfinite(m.gain_crossover)) vline("w_gc", std::log10(m.gain_crossover), lo, hi, 1);
    if (std::isfinite(m.phase_crossover)) vline("w_pc", std::log10(m.phase_crossover), lo, hi, 3);
    EndPlot();
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Open-loop |Kc Gc G| (blue) and closed-loop |T| = |L / (1 + L)| (green) [dB];\n"
                      "dashed: gain crossover w_gc (|L| = 1) and phase crossover w_pc (L real < 0),\n"
                      "both found as polynomial roots; peak %.3g dB at %.4g rad/s",
                      f.peak_db, f.peak_w);
  char spm[32];
  if (dz)
    std::snprintf(title, sizeof title, "PM %s deg (sampled %s) at %s rad/s", num(m.phase_margin, "%.3g", pm, sizeof pm),
                  num(dz->margins.phase_margin, "%.3g", spm, sizeof spm), num(m.gain_crossover, "%.4g", gm, sizeof gm));
  else
    std::snprintf(title, sizeof title, "PM %s deg at %s rad/s",
                  num(m.phase_margin, "%.3g", pm, sizeof pm), num(m.gain_crossover, "%.4g", gm, sizeof gm));
  po.title = title;
  if (BeginPlot("##bode_phase", ImVec2(size.x, size.y - h - gap), po)) {
    SetupAxes("log10 w [rad/s]", "arg L [deg]");
    PlotLine("arg L", lw.data(), o.phase_deg.data(), lw.size(), {.color = 0, .x_sorted = true});
    if (dz) PlotLine("sampled arg L", dzw.data(), dz_phase.data(), dzw.size(), {.color = 1, .x_sorted = true});
    const double x0 = lw.empty() ? 0 : lw.front(), x1 = lw.empty() ? 1 : lw.back();
    const double zx[2] = {x0, x1}, zy[2] = {-180.0, -180.0};
    PlotLine("-180 deg", zx, zy, 2, {.color = 6, .line = LineStyle::Dotted, .thickness = 1.0f});
    double lo = -180, hi = -180;
    for (double v : o.phase_deg) lo = std::min(lo, v), hi = std::max(hi, v);
    if (std::isfinite(m.gain_crossover)) vline("w_gc", std::log10(m.gain_crossover), lo, hi, 1);
    if (std::isfinite(m.phase_crossover)) vline("w_pc", std::log10(m.phase_crossover), lo, hi, 3);
    EndPlot();
  }
}

}  // namespace

namespace {
// A complex-plane canvas with equal scales: `curve` for w > 0 (dark) and its mirror (light), a
// unit circle and the critical point -1 (Nyquist of L), or the locus -1/N and the predicted cycles
// (harmonic balance in the H plane). Centre and half-height `R` of the view in data units.
struct PlaneView {
  const std::vector<cplx>* curve = nullptr;
  bool critical = true;                      // unit circle and -1
  const std::vector<cplx>* locus = nullptr;  // -1/N
  const std::vector<control::LimitCycle>* cycles = nullptr;
  double cx = -0.5, R = 1.7;
};
void draw_plane(const PlaneView& v, ImVec2 size, const char* title, bool title_ok) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##plane", ImVec2(std::max(size.x, 8.0f), std::max(size.y, 8.0f)));
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  dl->AddRectFilled(p0, p1, IM_COL32(255, 255, 255, 255));
  dl->AddRect(p0, p1, kAxis);
  const float title_h = 2 * ImGui::GetFontSize() + 6;
  PlotTransform t;
  t.px0 = p0.x, t.px1 = p1.x, t.py0 = p0.y + title_h, t.py1 = p1.y;
  const double aspect = (t.px1 - t.px0) / std::max(1.0, t.py1 - t.py0);
  double hw = 1.4 * v.R, hh = v.R;
  if (hw / hh < aspect) hw = hh * aspect;
  else hh = hw / aspect;
  t.x0 = v.cx - hw, t.x1 = v.cx + hw, t.y0 = -hh, t.y1 = hh;
  const auto P = [&](cplx s) {
    return ImVec2(static_cast<float>(t.to_px_x(s.real())), static_cast<float>(t.to_px_y(s.imag())));
  };
  dl->PushClipRect(ImVec2(p0.x, p0.y + title_h), p1, true);
  dl->AddLine(P(cplx(t.x0, 0)), P(cplx(t.x1, 0)), kGrid, 1.0f);
  dl->AddLine(P(cplx(0, t.y0)), P(cplx(0, t.y1)), kGrid, 1.0f);
  const float unit = static_cast<float>((t.px1 - t.px0) / (t.x1 - t.x0));
  if (v.critical) dl->AddCircle(P(0.0), unit, kGrid, 96, 1.0f);
  const double far = 10 * (hw + hh + std::abs(v.cx));
  const std::vector<cplx>& c = *v.curve;
  for (int mirror = 1; mirror >= 0; --mirror) {
    const ImU32 col = mirror ? IM_COL32(86, 180, 233, 160) : IM_COL32(0, 114, 178, 255);
    for (std::size_t i = 1; i < c.size(); ++i) {
      cplx a = c[i - 1], b = c[i];
      if (!std::isfinite(std::abs(a)) || !std::isfinite(std::abs(b)) || std::abs(a) > far || std::abs(b) > far) continue;
      if (mirror) a = std::conj(a), b = std::conj(b);
      dl->AddLine(P(a), P(b), col, mirror ? 1.2f : 2.0f);
    }
  }
  if (c.size() > 8) {  // direction of increasing w: an arrow head at the middle sample
    const std::size_t i = c.size() / 2;
    const ImVec2 a = P(c[i - 1]), b = P(c[i + 1]);
    const float dx = b.x - a.x, dy = b.y - a.y, n = std::max(1e-3f, std::hypot(dx, dy));
    const ImVec2 u(dx / n, dy / n);
    dl->AddTriangleFilled(b, ImVec2(b.x - 8 * u.x + 4 * u.y, b.y - 8 * u.y - 4 * u.x),
                          ImVec2(b.x - 8 * u.x - 4 * u.y, b.y - 8 * u.y + 4 * u.x), IM_COL32(0, 114, 178, 255));
  }
  const ImU32 kDf = IM_COL32(204, 121, 167, 255);
  if (v.locus)
    for (std::size_t i = 1; i < v.locus->size(); ++i) dl->AddLine(P((*v.locus)[i - 1]), P((*v.locus)[i]), kDf, 2.0f);
  if (v.cycles)
    for (const auto& lc : *v.cycles) {
      dl->AddCircleFilled(P(lc.point), 5.0f, lc.stable ? kDf : IM_COL32(255, 255, 255, 255));
      dl->AddCircle(P(lc.point), 5.0f, kDf, 16, 1.5f);
    }
  if (v.critical) {
    const ImVec2 m = P(-1.0);
    dl->AddLine(ImVec2(m.x - 6, m.y - 6), ImVec2(m.x + 6, m.y + 6), kCritical, 2.5f);
    dl->AddLine(ImVec2(m.x - 6, m.y + 6), ImVec2(m.x + 6, m.y - 6), kCritical, 2.5f);
    dl->AddText(ImVec2(m.x + 10, m.y + 5), kCritical, "-1");
  }
  dl->PopClipRect();
  dl->AddText(ImVec2(p0.x + 4, p0.y + 2), title_ok ? kText : kCritical, title);
}
}  // namespace

// Nyquist of L with the critical point, or (d.harmonic_balance) the friction loop's H(jw) with the
// describing function's -1/N(a) and the predicted cycles.
void draw_design_nyquist(DesignViewState& d, ImVec2 size) {
  if (!d.out.frequency) return;
  const float y0 = ImGui::GetCursorPosY();
  ImGui::Checkbox("harmonic balance (H, -1/N)", &d.harmonic_balance);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Off: Nyquist plot of L = Kc Gc G with the critical point -1.\n"
                      "On: the friction loop v = -H(s) F, H = s G / (1 + Gc G) [m/(N s)] (blue) and -1/N(a) of the\n"
                      "scenario's friction (pink, a = velocity amplitude); dots: predicted limit cycles\n"
                      "(filled: stable, hollow: unstable threshold).");
  size.y -= ImGui::GetCursorPosY() - y0;
  char buf[240];
  if (d.harmonic_balance && d.out.limit_cycles) {
    const control::LimitCycleReport& r = *d.out.limit_cycles;
    PlaneView v;
    v.curve = &r.h_curve;
    v.critical = false;
    v.locus = &r.locus;
    v.cycles = &r.cycles;
    double R = 0.0;
    for (const auto& lc : r.cycles) R = std::max(R, 1.5 * std::abs(lc.point));
    if (R == 0.0)
      for (const cplx& h : r.h_curve) R = std::max(R, std::abs(h));
    v.R = R > 0 ? R : 1.0;
    v.cx = -0.3 * v.R;
    if (r.cycles.empty()) {
      std::snprintf(buf, sizeof buf, "H(jw) [m/(N s)], -1/N(a): no cycle predicted");
    } else {
      const auto& c = r.cycles.front();
      std::snprintf(buf, sizeof buf, "H(jw) [m/(N s)], -1/N(a)\ncycle %.3g mm, %.3g ms, %s%s", c.amplitude * 1e3,
                    c.period * 1e3, c.stable ? "stable" : "unstable", r.cycles.size() > 1 ? " (+ more)" : "");
    }
    draw_plane(v, size, buf, true);
    return;
  }
  const control::FrequencyReport& f = *d.out.frequency;
  const auto& ny = f.nyquist;
  // View: at least [-2.2, 1.2] x [-1.7, 1.7]; grown to the phase crossovers' points (x1.3), capped.
  PlaneView v;
  v.curve = &ny.curve;
  const double k = d.out.compensator ? d.out.compensator->Kc : 1.0;
  for (double w : f.margins.phase_crossovers)
    v.R = std::max(v.R, 1.3 * k * std::abs(d.out.loop.num(cplx(0, w)) / d.out.loop.den(cplx(0, w))));
  v.R = std::min(v.R, 50.0);
  std::snprintf(buf, sizeof buf, "Nyquist L(jw), critical point -1\nN = %d, P = %d, Z = N + P = %d%s", ny.encirclements,
                ny.open_rhp_poles, ny.closed_rhp_poles,
                ny.marginal ? " (marginal)" : ny.stable ? " (stable)" : " (UNSTABLE)");
  draw_plane(v, size, buf, ny.stable);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("L(jw) for w > 0 (dark blue, arrow: increasing w) and w < 0 (light blue); unit circle grey;\n"
                      "N: clockwise encirclements of -1 along the D-contour indented around the %d imaginary-axis\n"
                      "pole(s); P: open-loop poles in the right half plane; Z: closed-loop poles there.",
                      ny.axis_poles);
}

void draw_design_frequency(DesignViewState& d, ImVec2 size) {
  if (!d.out.frequency) {
    ImGui::Dummy(size);
    return;
  }
  const float gap = ImGui::GetStyle().ItemSpacing.x, vgap = ImGui::GetStyle().ItemSpacing.y;
  const float wb = std::floor(0.4f * (size.x - gap));  // Bode; Nyquist over the hunting map beside
  ImGui::BeginGroup();
  draw_bode(*d.out.frequency, d.out.discrete ? &*d.out.discrete : nullptr, ImVec2(wb, size.y));
  if (d.out.discrete && ImGui::IsItemHovered())
    ImGui::SetTooltip("Vermillion: the loop sampled at T = %.3g s (Tustin controller, ZOH plant) up to the Nyquist\n"
                      "frequency %.4g rad/s: PM %.3g deg at %.4g rad/s, GM %.3g dB; %s",
                      d.out.discrete->T, d.out.discrete->nyquist_frequency, d.out.discrete->margins.phase_margin,
                      d.out.discrete->margins.gain_crossover, d.out.discrete->margins.gain_margin_db,
                      d.out.discrete->nyquist.stable ? "stable" : "UNSTABLE (closed-loop poles outside the unit circle)");
  ImGui::EndGroup();
  ImGui::SameLine();
  ImGui::BeginGroup();
  const float hn = std::floor(0.5f * (size.y - vgap));
  draw_design_nyquist(d, ImVec2(size.x - wb - gap, hn));
  draw_design_hunting_map(d, ImVec2(size.x - wb - gap, size.y - hn - vgap));
  ImGui::EndGroup();
}

}  // namespace gmslab::ui
