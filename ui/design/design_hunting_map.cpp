// gmslab ui: the design view's hunting map (see ui/design/design_view.hpp): the amplitude of the
// loop's periodic orbits (limit cycles of the loop without compensation) against a scale s of the
// controller gain, stable solid, unstable dashed, the current gain and the fold (the threshold)
// marked, the describing function's cycle as the quick estimate. Computed by compute_design
// (periodic_orbits, hunting_map) on a worker thread (HuntingMapState, ui/panel_state.hpp).
#include <imgui.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"

namespace gmslab::ui {

namespace {
constexpr double kMapLo = 0.2, kMapHi = 5.0;  // gain scales of the map
constexpr int kMapN = 13;

void start_job(HuntingMapState& h, control::DesignInputs in, int generation) {
  auto job = std::make_shared<HuntingMapJob>();
  job->generation = generation;
  HuntingMapJob* j = job.get();
  j->thread = std::thread([j, in = std::move(in)] {
    try {
      j->out = control::compute_design(in);  // typed failures are recorded in out.error
    } catch (const std::exception& e) {
      j->error = std::string("internal error: ") + e.what();
    }
    j->done = true;
  });
  h.job = std::move(job);
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}
}  // namespace

void hunting_map_request(DesignViewState& d) {
  HuntingMapState& h = d.hunting_map;
  ++h.generation;
  h.out.reset();
  h.error.clear();
  h.queued.reset();
  if (!d.out.compensator) {
    h.error = "no compensator (the design failed)";
    return;
  }
  if (d.out.source == control::PlantSource::Typed) {
    h.error = "none for a typed plant (no friction)";
    return;
  }
  if (d.in.reference.kind != Signal::Kind::Constant) {
    h.error = "step reference only";  // orbits around a constant set point
    return;
  }
  control::DesignInputs in = d.in;
  in.manual = *d.out.compensator;
  in.view = false;
  in.simulate = false;
  in.periodic_orbits = true;
  in.hunting_map = control::DesignInputs::GainGrid{kMapLo, kMapHi, kMapN};
  in.loop_compensations = {control::Compensation::None};
  in.accuracy = control::Accuracy::Report;  // the describing function's cycle: the quick estimate
  h.queued = std::move(in);
  h.queued_generation = h.generation;
  hunting_map_poll(d);
}

bool hunting_map_poll(DesignViewState& d) {
  HuntingMapState& h = d.hunting_map;
  if (h.job && h.job->done) {
    h.job->thread.join();
    if (h.job->generation == h.generation) {  // else superseded: dropped
      if (!h.job->error.empty())
        h.error = h.job->error;
      else
        h.out = std::move(h.job->out);
    }
    h.job.reset();
  }
  if (!h.job && h.queued) {
    start_job(h, std::move(*h.queued), h.queued_generation);
    h.queued.reset();
  }
  return h.job != nullptr;
}

bool hunting_map_busy(const DesignViewState& d) {
  return (d.hunting_map.job && !d.hunting_map.job->done) || d.hunting_map.queued.has_value();
}

namespace {
// The title and, when there is a map, its series (x: log10 s, y: amplitude [mm]).
struct MapSeries {
  std::vector<double> xs, ys, xu, yu;  // stable / unstable runs, NaN between runs
  double ymax = 0.0;
  std::string title, tip;
};

MapSeries map_series(const HuntingMapState& h) {
  MapSeries s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!h.out) {
    s.title = "Hunting map: " + (h.error.empty() ? std::string("computing...") : h.error);
    return s;
  }
  const control::DesignOutputs& o = *h.out;
  const control::HuntingMap* m = o.hunting_map ? &*o.hunting_map : nullptr;
  const control::OrbitReport* r = o.orbits ? &*o.orbits : nullptr;
  if (!m || m->points.empty()) {
    s.title = "Hunting map: no cycle found in s = " + num(kMapLo) + ".." + num(kMapHi) +
              " (method: shooting on the section map, seeded by simulations)";
    s.tip = (r ? r->method + "\n" + r->not_found : o.error) + (m ? "\n" + m->note : std::string());
    return s;
  }
  for (std::size_t i = 0; i < m->points.size(); ++i) {
    const auto& p = *m->points[i].orbit;
    const double x = std::log10(p.gain_scale), y = p.amplitude * 1e3;
    s.ymax = std::max(s.ymax, y);
    // A run of one stability; the point where it changes belongs to both runs.
    const bool prev_same = i > 0 && m->points[i - 1].orbit->stable == p.stable;
    auto& X = p.stable ? s.xs : s.xu;
    auto& Y = p.stable ? s.ys : s.yu;
    if (i > 0 && !prev_same) {
      X.push_back(nan), Y.push_back(nan);
      const auto& q = *m->points[i - 1].orbit;
      X.push_back(std::log10(q.gain_scale)), Y.push_back(q.amplitude * 1e3);
    }
    X.push_back(x), Y.push_back(y);
  }
  if (m->fold)
    s.title = "Hunting map: threshold (fold) at gain x " + num(*m->fold);
  else
    s.title = "Hunting map: no fold in s = " + num(kMapLo) + ".." + num(kMapHi);
  const control::PeriodicOrbit* now = r ? r->stable() : nullptr;
  s.tip = now ? "At the current gain: cycle " + num(now->amplitude * 1e3) + " mm, period " +
                    num(now->period) + " s.\n"
              : "At the current gain: no cycle found from rest.\n";
  s.tip += m->note;
  return s;
}
}  // namespace

void draw_design_hunting_map(DesignViewState& d, ImVec2 size) {
  hunting_map_poll(d);
  const HuntingMapState& h = d.hunting_map;
  const MapSeries s = map_series(h);
  const double x0 = std::log10(kMapLo), x1 = std::log10(kMapHi);
  double ymax = s.ymax > 0.0 ? 1.15 * s.ymax : 1.0;
  const control::HuntingCycle* df = h.out && h.out->hunting ? h.out->hunting->hunting() : nullptr;
  if (df && df->amplitude > 0.0) ymax = std::max(ymax, 1.1 * df->amplitude * 1e3);
  PlotOptions po;
  po.title = s.title.c_str();
  po.legend = false;  // the marks are labelled where they are drawn
  const control::HuntingMap* m = h.out && h.out->hunting_map ? &*h.out->hunting_map : nullptr;
  const double cx[2] = {0.0, 0.0}, cy[2] = {0.0, ymax};
  // A label at a data point (y NaN: a vertical mark's, at the top of the view, one line apart),
  // right of the point unless `left` (or the view's edge) puts it on the left.
  struct Label {
    ImVec2 at;
    std::string text;
    bool left = false;
  };
  std::vector<Label> labels;
  if (BeginPlot("##hunting_map", size, po)) {
    SetupAxes("log10 s (controller gain Kc x s) [-]", "cycle amplitude [mm]");
    SetupFitRangeX(x0, x1);
    SetupFitRangeY(0.0, ymax);
    if (!s.xs.empty())
      PlotLine("stable cycle", s.xs.data(), s.ys.data(), s.xs.size(), {.color = 0});
    if (!s.xu.empty())
      PlotLine("unstable cycle", s.xu.data(), s.yu.data(), s.xu.size(),
               {.color = 1, .line = LineStyle::Dashed});
    PlotLine("current gain (s = 1)", cx, cy, 2,
             {.color = 6, .line = LineStyle::Dotted, .thickness = 1.0f});
    // The two vertical marks labelled on the sides away from each other.
    const bool fold_right = m && m->fold && *m->fold > 1.0;
    labels.push_back({ImVec2(0.0f, NAN), "current gain", fold_right});
    if (m && m->fold) {
      const double fx[2] = {std::log10(*m->fold), std::log10(*m->fold)};
      PlotLine("threshold (fold)", fx, cy, 2,
               {.color = 3, .line = LineStyle::Dashed, .thickness = 1.5f});
      labels.push_back({ImVec2(static_cast<float>(fx[0]), NAN), "fold x " + num(*m->fold),
                        !fold_right});  // the title says it is the threshold
    }
    if (df && df->amplitude > 0.0) {  // a cross at s = 1
      const double a = df->amplitude * 1e3, dx = 0.03 * (x1 - x0), dy = 0.03 * ymax;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      const double qx[5] = {-dx, dx, nan, 0.0, 0.0}, qy[5] = {a, a, nan, a - dy, a + dy};
      PlotLine("quick estimate (describing function)", qx, qy, 5, {.color = 4});
      labels.push_back({ImVec2(static_cast<float>(dx), static_cast<float>(a)),
                        "quick estimate (describing function)", false});
    }
    EndPlot();
  }
  const PlotTransform t = LastPlotTransform();
  // (over the plot's child window, which covers this window's draw list; clipped to its area)
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  dl->PushClipRect(ImVec2(static_cast<float>(t.px0), static_cast<float>(t.py0)),
                   ImVec2(static_cast<float>(t.px1), static_cast<float>(t.py1)), true);
  // The curves' kind at a point of each (solid: stable, dashed: unstable); the vertical marks'
  // labels at the top of the view, one line apart.
  if (!s.xs.empty())
    labels.push_back({ImVec2(static_cast<float>(s.xs.front()), static_cast<float>(s.ys.front())),
                      "stable", false});
  if (!s.xu.empty())
    labels.push_back({ImVec2(static_cast<float>(s.xu.front()), static_cast<float>(s.yu.front())),
                      "unstable", false});
  float top = static_cast<float>(t.py0) + 2.0f;
  for (const auto& [at, text, left] : labels) {
    const float y =
        std::isnan(at.y) ? top : static_cast<float>(t.to_px_y(at.y)) - ImGui::GetFontSize();
    if (std::isnan(at.y)) top += ImGui::GetFontSize();
    const float w = ImGui::CalcTextSize(text.c_str()).x, px = static_cast<float>(t.to_px_x(at.x));
    const bool fits_right = px + 4.0f + w <= t.px1, fits_left = px - 4.0f - w >= t.px0;
    const bool on_left = (left && fits_left) || !fits_right;
    dl->AddText(ImVec2(on_left ? px - 4.0f - w : px + 4.0f, y), IM_COL32(60, 60, 65, 255),
                text.c_str());
  }
  dl->PopClipRect();
  if (ImGui::IsItemHovered()) {
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
    ImGui::TextUnformatted(
        "Limit cycles of the loop without compensation (periodic orbits of the full nonlinear "
        "loop, shooting on a Poincare section) against the controller gain Kc x s; amplitude: half "
        "peak-to-peak of the position. Solid: stable cycle (the loop hunts with it); dashed: "
        "unstable cycle (the boundary between the basin of rest and that of the cycle). The fold "
        "is where the two meet: the threshold gain beyond which this cycle does not exist. Cross: "
        "the describing function's quick estimate at the current gain. Computed in the background "
        "by pseudo-arclength continuation.");
    ImGui::Separator();
    ImGui::TextUnformatted(s.tip.c_str());
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
  }
}

}  // namespace gmslab::ui
