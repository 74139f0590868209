#include "core/figures/figure_set.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>

#include "core/error.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab {

namespace {

using Style = Series::Style;
constexpr std::size_t kMaxPoints = 20000;  // per series; min/max decimation beyond

// ---- helpers ------------------------------------------------------------------------------------

Scenario load_with(const std::string& dir, const std::string& preset, const std::string& tag) {
  Scenario s = load_scenario(dir + "/" + preset);
  if (!tag.empty() && tag != s.friction.model) s.friction = model_info(tag).defaults();
  return s;
}

std::string model_label(const std::string& tag) {
  static const std::pair<const char*, const char*> names[] = {
      {"gms", "GMS"},           {"lugre", "LuGre"},        {"elastoplastic", "elasto-plastic"},
      {"maxwell_slip", "Maxwell-slip"}, {"leuven", "Leuven"}, {"dahl", "Dahl"},
      {"stribeck", "Stribeck"}, {"coulomb", "Coulomb"}};
  for (const auto& [t, n] : names)
    if (tag == t) return n;
  return tag;
}

// Keeps at most kMaxPoints points: per bucket of consecutive samples the smallest and largest y
// (in time order), so peaks and spikes survive.
void decimate(Series& s) {
  const std::size_t n = s.x.size();
  if (n <= kMaxPoints) return;
  const std::size_t bucket = (2 * n + kMaxPoints - 1) / kMaxPoints;
  Series out{s.label, {}, {}, s.style, s.color};
  for (std::size_t b = 0; b < n; b += bucket) {
    const std::size_t e = std::min(n, b + bucket);
    std::size_t lo = b, hi = b;
    for (std::size_t k = b; k < e; ++k) {
      if (s.y[k] < s.y[lo]) lo = k;
      if (s.y[k] > s.y[hi]) hi = k;
    }
    const std::size_t first = std::min(lo, hi), second = std::max(lo, hi);
    out.x.push_back(s.x[first]);
    out.y.push_back(s.y[first]);
    if (second != first) {
      out.x.push_back(s.x[second]);
      out.y.push_back(s.y[second]);
    }
  }
  s = std::move(out);
}

// A series from trace columns over the samples with t in [t0, t1], scaled.
Series series_of(const Trace& tr, const std::vector<double>& xs, double xscale,
                 const std::vector<double>& ys, double yscale, std::string label, Style style,
                 int color, double t0 = -1e300, double t1 = 1e300, double yshift = 0.0) {
  Series s{std::move(label), {}, {}, style, color};
  for (std::size_t k = 0; k < tr.size(); ++k) {
    if (tr.t[k] < t0 - 1e-12 || tr.t[k] > t1 + 1e-12) continue;
    s.x.push_back(xs[k] * xscale);
    s.y.push_back((ys[k] - yshift) * yscale);
  }
  decimate(s);
  return s;
}

double value_at(const Trace& tr, const std::vector<double>& y, double t) {
  std::size_t k = 0;
  while (k + 1 < tr.size() && tr.t[k + 1] <= t) ++k;
  return y[k];
}

// ---- protocol panels (one model) ----------------------------------------------------------------

Series presliding_series(const std::string& dir, const std::string& tag, int color) {
  const Trace tr = simulate(load_with(dir, "fig2a_presliding.json", tag));
  return series_of(tr, tr.x, 1e6, tr.friction, 1.0, model_label(tag), Style::Solid, color);
}

std::vector<Series> lag_series(const std::string& dir, const std::string& tag) {
  const struct {
    const char* file;
    const char* label;
    Style style;
  } runs[] = {{"fig2b_lag_x1.json", "a0 = 1 mm/s^2 (reference)", Style::Dashed},
              {"fig2b_lag_x16.json", "16 a0", Style::Solid},
              {"fig2b_lag_x100.json", "100 a0", Style::Dotted}};
  std::vector<Series> out;
  int c = 0;
  for (const auto& r : runs) {
    const Scenario s = load_with(dir, r.file, tag);
    const Trace tr = simulate(s);
    out.push_back(series_of(tr, tr.v, 1e3, tr.friction, 1.0, r.label, r.style, c++,
                            s.run.duration * 2.0 / 3.0));
  }
  return out;
}

// Second period of each frequency: F vs x [mm] (as_velocity false) or vs v [mm/s].
std::vector<Series> periodic_series(const std::string& dir, const std::string& tag,
                                    bool as_velocity) {
  const struct {
    const char* file;
    const char* label;
    Style style;
  } runs[] = {{"fig2c_periodic_0p1hz.json", "0.1 Hz", Style::Solid},
              {"fig2c_periodic_1hz.json", "1 Hz", Style::Dotted}};
  std::vector<Series> out;
  int c = 0;
  for (const auto& r : runs) {
    const Scenario s = load_with(dir, r.file, tag);
    const Trace tr = simulate(s);
    out.push_back(series_of(tr, as_velocity ? tr.v : tr.x, 1e3, tr.friction, 1.0, r.label,
                            r.style, c++, s.run.duration / 2.0));
  }
  return out;
}

const char* kDriftRef = "2 s";  // drift is measured from the rest position at t = 2 s

Trace nondrifting_trace(const std::string& dir, const std::string& tag) {
  return simulate(load_with(dir, "fig2d_nondrifting.json", tag));
}

Series drift_series(const Trace& tr, const std::string& label, Style style, int color) {
  return series_of(tr, tr.t, 1.0, tr.x, 1e6, label, style, color, 2.0, 1e300,
                   value_at(tr, tr.x, 2.0));
}

// x - x(2 s) [um] at the same phase of the 2 Hz force, once per period (t = 2, 2.5, ... s): the
// elastic vibration drops out and what is left is the drift.
Series strobe_series(const Trace& tr, const std::string& label, Style style, int color) {
  Series s{label, {}, {}, style, color};
  const double x2 = value_at(tr, tr.x, 2.0);
  for (double t = 2.0; t <= tr.t.back() + 1e-9; t += 0.5) {
    s.x.push_back(t);
    s.y.push_back((value_at(tr, tr.x, t + 1e-9) - x2) * 1e6);
  }
  return s;
}

// ---- seed figures -------------------------------------------------------------------------------

Panel panel_2a(const std::string& dir) {
  return {"A", "Presliding hysteresis, nonlocal memory", "x [um]", "F_f [N]",
          {presliding_series(dir, "gms", 0)}};
}

Panel panel_2b(const std::string& dir) {
  return {"B", "Frictional lag (last of three cycles)", "v [mm/s]", "F_f [N]",
          lag_series(dir, "gms")};
}

Panel panel_2c(const std::string& dir) {
  return {"C", "Periodic sliding, x = 0.5 mm sin(2 pi f t)", "x [mm]", "F_f [N]",
          periodic_series(dir, "gms", false)};
}

Panel panel_2d(const std::string& dir) {
  const Trace tr = nondrifting_trace(dir, "gms");
  return {"D", "Non-drifting: position after sliding", "t [s]", "x [mm]",
          {series_of(tr, tr.t, 1.0, tr.x, 1e3, "position x", Style::Solid, 0)}};
}

Figure fig2a(const std::string& dir) {
  return {"fig2a_presliding", "Seed Fig. 2A - GMS presliding hysteresis with nonlocal memory",
          "Imposed displacement 0 -> 15 -> -15 -> 8 -> -3 -> 8 -> 15 -> -15 um at 10 um/s (GMS "
          "reference set). Turning-point forces 1.35, -1.35, 1.14, -0.585, 1.14, 1.35, -1.35 N: the "
          "inner loop closes exactly at 8 um / 1.14 N and the curve rejoins the outer branch.",
          {panel_2a(dir)}};
}

Figure fig2b(const std::string& dir) {
  return {"fig2b_frictional_lag", "Seed Fig. 2B - GMS frictional lag",
          "Imposed triangular velocity 0.05 - 4 mm/s at a0 = 1 mm/s^2 (dashed), 16 a0 (solid) and "
          "100 a0 (dotted); last of three cycles. At 1 mm/s: accelerating / decelerating branch "
          "1.186 / 1.182, 1.222 / 1.154, 1.320 / 1.079 N (steady state 1.184 N): the loop opens "
          "with acceleration, the accelerating branch above.",
          {panel_2b(dir)}};
}

Figure fig2c(const std::string& dir) {
  Panel fv{"C'", "Periodic sliding: force vs velocity", "v [mm/s]", "F_f [N]",
           periodic_series(dir, "gms", true)};
  return {"fig2c_periodic_sliding", "Seed Fig. 2C - GMS periodic sliding at two frequencies",
          "Imposed x = 0.5 mm sin(2 pi f t), f = 0.1 Hz (solid) and 1 Hz (dotted), second period. "
          "Mid-stroke force about 1.45 N at 0.1 Hz and about 1.00 N at 1 Hz (Stribeck); the "
          "presliding transitions at the reversals are the same at both frequencies.",
          {panel_2c(dir), fv}};
}

Figure fig2d(const std::string& dir) {
  const Trace tr = nondrifting_trace(dir, "gms");
  Panel pos{"D", "Position: slides, stops, stays", "t [s]", "x [mm]",
            {series_of(tr, tr.t, 1.0, tr.x, 1e3, "position x", Style::Solid, 0)}};
  Panel force{"D'", "Applied force and friction", "t [s]", "F [N]",
              {series_of(tr, tr.t, 1.0, tr.applied, 1.0, "applied F_ext", Style::Dashed, 1),
               series_of(tr, tr.t, 1.0, tr.friction, 1.0, "friction F_f", Style::Solid, 0)}};
  Panel drift{"D''", std::string("Drift after the stop: x - x(") + kDriftRef + ")", "t [s]",
              "x - x(2 s) [um]",
              {drift_series(tr, "GMS", Style::Solid, 0),
               strobe_series(tr, "same phase of each force period", Style::Dashed, 1)}};
  return {"fig2d_nondrifting", "Seed Fig. 2D - GMS non-drifting",
          "A 1 kg mass: F_ext = 2 N for 0.5 s (it slides), then 0.45 + 0.45 sin(2 pi 2 Hz t) N, "
          "always below break-away. The mass stops near t = 1.3 s after about 0.30 m and stays put "
          "within 0.03 um.",
          {pos, force, drift}};
}

Figure fig2_all(const std::string& dir) {
  return {"fig2_gms", "Seed Fig. 2 - friction behaviour of the GMS model",
          "A: presliding hysteresis with nonlocal memory. B: frictional lag (dashed a0, solid "
          "x16, dotted x100). C: periodic sliding, frequency x10 between solid and dotted. D: the "
          "non-drifting property under an oscillating force below break-away, after sliding.",
          {panel_2a(dir), panel_2b(dir), panel_2c(dir), panel_2d(dir)}};
}

Figure fig4(const std::string& dir) {
  const Scenario sc = load_with(dir, "fig4_stick_slip.json", "");
  const Trace tr = simulate(sc);
  std::vector<double> xp(tr.size()), vp(tr.size());
  for (std::size_t k = 0; k < tr.size(); ++k) {
    xp[k] = sc.drive.signal(tr.t[k]);
    vp[k] = sc.drive.signal.rate_at(tr.t[k]);
  }
  std::vector<double> spring(tr.size());
  for (std::size_t k = 0; k < tr.size(); ++k) spring[k] = tr.applied[k];
  return {"fig4_stick_slip", "Seed Fig. 4 - GMS stick-slip",
          "A 1 kg mass pulled through a 2 N/m spring whose end moves at 0.1 m/s (seed Fig. 3). "
          "Slip starts at Fs = 1.5 N near t = 7.55, 14.08, 20.61 s; each stick is preceded by a "
          "force spike (about 1.19 N) and followed by a damped vibration at about 72 Hz.",
          {{"a", "Position and velocity", "t [s]", "x [m], v [m/s]",
            {series_of(tr, tr.t, 1.0, xp, 1.0, "desired position x_p", Style::Dotted, 2),
             series_of(tr, tr.t, 1.0, tr.x, 1.0, "position x", Style::Solid, 0),
             series_of(tr, tr.t, 1.0, vp, 1.0, "desired velocity v_p", Style::Dotted, 3),
             series_of(tr, tr.t, 1.0, tr.v, 1.0, "velocity v", Style::Dashed, 1)}},
           {"b", "Friction and spring force", "t [s]", "F [N]",
            {series_of(tr, tr.t, 1.0, tr.friction, 1.0, "friction force", Style::Solid, 0),
             series_of(tr, tr.t, 1.0, spring, 1.0, "spring force", Style::Dashed, 1)}}}};
}

// ---- comparison figures -------------------------------------------------------------------------

const std::vector<std::string> kHysteresisModels = {"gms",  "maxwell_slip", "leuven",
                                                    "lugre", "dahl",         "elastoplastic"};
const std::vector<std::string> kLagModels = {"gms", "lugre", "elastoplastic", "leuven"};

std::string letter(std::size_t i) { return std::string(1, static_cast<char>('A' + i)); }

Figure compare_2a(const std::string& dir) {
  Figure f{"compare_fig2a_presliding", "Fig. 2A protocol with every hysteretic model",
           "Same imposed displacement (turning points 15, -15, 8, -3, 8, 15, -15 um). GMS and "
           "Maxwell-slip close the inner loop exactly and rejoin the outer branch (nonlocal "
           "memory); Leuven nearly (its state z lags x); LuGre and Dahl do not (local memory). "
           "The elasto-plastic loop stays inside its elastic range here.",
           {}};
  for (std::size_t i = 0; i < kHysteresisModels.size(); ++i) {
    const auto& tag = kHysteresisModels[i];
    f.panels.push_back({letter(i), model_label(tag), "x [um]", "F_f [N]",
                        {presliding_series(dir, tag, static_cast<int>(i))}});
  }
  return f;
}

Figure compare_2b(const std::string& dir) {
  Figure f{"compare_fig2b_frictional_lag", "Fig. 2B protocol: frictional lag of the rate-state models",
           "Triangular velocity 0.05 - 4 mm/s at a0 (dashed), 16 a0 (solid), 100 a0 (dotted). All "
           "four open a loop; Maxwell-slip, Dahl and the static laws have none.",
           {}};
  for (std::size_t i = 0; i < kLagModels.size(); ++i)
    f.panels.push_back({letter(i), model_label(kLagModels[i]), "v [mm/s]", "F_f [N]",
                        lag_series(dir, kLagModels[i])});
  return f;
}

Figure compare_2c(const std::string& dir) {
  Figure f{"compare_fig2c_periodic_sliding", "Fig. 2C protocol with other models",
           "x = 0.5 mm sin(2 pi f t), 0.1 Hz solid, 1 Hz dotted. Maxwell-slip has no Stribeck "
           "effect: both frequencies give the same loop.",
           {}};
  const std::vector<std::string> tags = {"gms", "lugre", "leuven", "maxwell_slip"};
  for (std::size_t i = 0; i < tags.size(); ++i)
    f.panels.push_back({letter(i), model_label(tags[i]), "x [mm]", "F_f [N]",
                        periodic_series(dir, tags[i], false)});
  return f;
}

Figure compare_2d(const std::string& dir) {
  const std::vector<std::string> all = {"gms",  "lugre",        "dahl",
                                        "leuven", "elastoplastic", "maxwell_slip"};
  Panel every{"A", "Every model", "t [s]", "x - x(2 s) [um]", {}};
  Panel fine{"B", "Same phase of each force period (t = 2, 2.5, ... s)", "t [s]",
             "x - x(2 s) [um]", {}};
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Trace tr = nondrifting_trace(dir, all[i]);
    const Style st = i == 0 ? Style::Solid : (i % 2 ? Style::Dashed : Style::Dotted);
    if (all[i] != "lugre" && all[i] != "dahl")
      fine.series.push_back(strobe_series(tr, model_label(all[i]), st, static_cast<int>(i)));
    every.series.push_back(drift_series(tr, model_label(all[i]), st, static_cast<int>(i)));
  }
  return {"compare_fig2d_drift", "Fig. 2D protocol: drift under a sub-break-away oscillating force",
          "After sliding and stopping, F_ext = 0.45 + 0.45 sin(2 pi 2 Hz t) N, below break-away. "
          "LuGre drifts about 81 um in 6 s and Dahl more (A). Sampled at the same phase of each force "
          "period (B), GMS, elasto-plastic and Maxwell-slip stay within 0.1 um; Leuven creeps by a "
          "fraction of a micrometre.",
          {every, fine}};
}

Figure compare_4(const std::string& dir) {
  const std::vector<std::string> tags = {"gms", "lugre", "elastoplastic", "leuven"};
  Panel vel{"a", "Velocity", "t [s]", "v [m/s]", {}};
  Panel force{"b", "Friction force", "t [s]", "F_f [N]", {}};
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const Trace tr = simulate(load_with(dir, "fig4_stick_slip.json", tags[i]));
    const Style st = i == 0 ? Style::Solid : (i % 2 ? Style::Dashed : Style::Dotted);
    const int c = static_cast<int>(i);
    vel.series.push_back(series_of(tr, tr.t, 1.0, tr.v, 1.0, model_label(tags[i]), st, c));
    force.series.push_back(series_of(tr, tr.t, 1.0, tr.friction, 1.0, model_label(tags[i]), st, c));
  }
  return {"compare_fig4_stick_slip", "Fig. 4 protocol: stick-slip with GMS and the LuGre family",
          "Same pulled mass. Stick-slip period: GMS 6.53 s, LuGre 6.36 s, elasto-plastic 6.38 s, "
          "Leuven 6.46 s. GMS shows the seed's force spike (about 1.19 N) in the last ms before "
          "each stick and a damped vibration at about 72 Hz; Leuven (sigma1 = 0) rings much longer.",
          {vel, force}};
}

using Builder = std::function<Figure(const std::string&)>;
const std::vector<std::pair<std::string, Builder>>& builders() {
  static const std::vector<std::pair<std::string, Builder>> b = {
      {"fig2a_presliding", fig2a},
      {"fig2b_frictional_lag", fig2b},
      {"fig2c_periodic_sliding", fig2c},
      {"fig2d_nondrifting", fig2d},
      {"fig2_gms", fig2_all},
      {"fig4_stick_slip", fig4},
      {"compare_fig2a_presliding", compare_2a},
      {"compare_fig2b_frictional_lag", compare_2b},
      {"compare_fig2c_periodic_sliding", compare_2c},
      {"compare_fig2d_drift", compare_2d},
      {"compare_fig4_stick_slip", compare_4},
  };
  return b;
}

}  // namespace

std::vector<std::string> figure_ids() {
  std::vector<std::string> ids;
  for (const auto& [id, b] : builders()) ids.push_back(id);
  return ids;
}

Figure make_figure(const std::string& id, const std::string& preset_dir) {
  for (const auto& [fid, build] : builders())
    if (fid == id) {
      Figure f = build(preset_dir);
      // The model comparisons of one protocol (one panel per model, the same quantity in every
      // panel) share the y scale, so the models' magnitudes compare at a glance.
      if (fid.rfind("compare_fig2", 0) == 0 && fid != "compare_fig2d_drift") f.shared_y = true;
      return f;
    }
  std::string known;
  for (const auto& i : figure_ids()) known += (known.empty() ? "" : ", ") + i;
  throw InputError("unknown figure '" + id + "' (known: " + known + ")");
}

namespace {
// One CSV field: quoted (RFC 4180) when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& v) {
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + '"';
}
}  // namespace

// The micro sign (U+00B5) and Greek mu (U+03BC) as "u": the unit prefix in ASCII ("x [um]").
static std::string ascii_micro(std::string v) {
  for (const char* mu : {"\xC2\xB5", "\xCE\xBC"})
    for (std::size_t at = v.find(mu); at != std::string::npos; at = v.find(mu, at)) v.replace(at, 2, "u");
  return v;
}

void write_figure_csv(const Figure& f, std::ostream& out) {
  out << "panel,series,x,y,x_label,y_label\n";
  out << std::setprecision(10);
  for (const auto& p : f.panels) {
    const std::string panel = csv_field(p.letter);
    const std::string labels = csv_field(ascii_micro(p.x_label)) + ',' + csv_field(ascii_micro(p.y_label));
    for (const auto& s : p.series) {
      const std::string series = csv_field(s.label);
      for (std::size_t k = 0; k < s.x.size(); ++k)
        out << panel << ',' << series << ',' << s.x[k] << ',' << s.y[k] << ',' << labels << '\n';
    }
  }
}

}  // namespace gmslab
