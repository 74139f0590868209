#include "core/ident/loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/ident/element_fit.hpp"
#include "core/ident/evidence.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab::ident {

LoopOptions::LoopOptions() {
  base.stage = "base fit";
  base.max_evaluations = 500;
  refit.starts = 2;
  refit.max_evaluations = 400;
  refit.stage = "refit";
  candidates = effect_catalog();
}

namespace {

bool contains(const std::vector<Effect>& v, Effect e) {
  return std::find(v.begin(), v.end(), e) != v.end();
}

std::vector<double> residual(const FitResult& f, const Dataset& d, const EffectContext& c) {
  auto p = predict(f, d, c);
  for (std::size_t k = 0; k < d.size(); ++k) p[k] = d.F[k] - p[k];
  return p;
}

std::vector<LinearTerm> terms_of(const FitResult& f, Effect e) {
  std::vector<LinearTerm> out;
  for (const auto& t : f.terms)
    if (t.effect == effect_name(e)) out.push_back(t);
  return out;
}

FitSpec with(const FitSpec& s, Effect e) {
  FitSpec r = s;
  r.effects.push_back(e);
  return r;
}

Candidate screen(Effect e, const FitResult& cur, const Dataset& train, const Dataset& val,
                 const EffectContext& c) {
  Candidate k;
  k.effect = e;
  const auto lin = refit_linear(with(cur.spec, e), train, c, cur.u);
  k.screen_rms_train = lin.rms_train;
  k.explained = cur.rms_train > 0 ? 1.0 - std::pow(lin.rms_train / cur.rms_train, 2) : 0.0;
  k.screen_rms_validation = rms_on(lin, val, c);
  return k;
}

// The dwell decay length that explains most, from a few multiples of x_ba.
void choose_dwell_length(const FitResult& cur, const Dataset& train, EffectContext& c) {
  double best = -1, best_s0 = c.dwell_s0;
  for (double m : {0.1, 0.2, 0.4, 0.7, 1.0, 2.0, 4.0, 8.0}) {
    c.dwell_s0 = m * c.x_ba;
    const auto lin = refit_linear(with(cur.spec, Effect::DwellStiction), train, c, cur.u);
    if (cur.rms_train - lin.rms_train > best) best = cur.rms_train - lin.rms_train, best_s0 = c.dwell_s0;
  }
  c.dwell_s0 = best_s0;
}

// Golden-section refinement of the ripple wavelength (+-2 %) on the training RMS.
void refine_wavelength(const FitResult& cur, const Dataset& train, EffectContext& c) {
  const FitSpec spec = contains(cur.spec.effects, Effect::PositionPeriodic)
                           ? cur.spec
                           : with(cur.spec, Effect::PositionPeriodic);
  auto cost = [&](double L) {
    c.wavelength = L;
    return refit_linear(spec, train, c, cur.u).rms_train;
  };
  double a = 0.98 * c.wavelength, b = 1.02 * c.wavelength;
  const double gr = 0.5 * (std::sqrt(5.0) - 1);
  for (int i = 0; i < 25; ++i) {
    const double c1 = b - gr * (b - a), c2 = a + gr * (b - a);
    if (cost(c1) < cost(c2)) b = c2;
    else a = c1;
  }
  c.wavelength = 0.5 * (a + b);
}

}  // namespace

FitResult fit_base(const FitSpec& base, const Dataset& train, const Dataset& val,
                   const EffectContext& c, const FitOptions& o) {
  const ModelInfo& info = model_info(base.model);
  if (base.elements == 0 && !info.columns.empty()) {
    if (has_linear_elements(base.model)) return fit_elements_auto(base, train, val, c, o);
    FitSpec s = base;
    s.elements = 4;  // no grid fit for this model: its default element count
    return fit_model(s, train, c, o);
  }
  return fit_model(base, train, c, o);
}

IdentReport identify(const Dataset& train, const Dataset& val, const FitSpec& base,
                     const LoopOptions& o) {
  IdentReport rep;
  rep.model = base.model;
  rep.elements = model_info(base.model).columns.empty() ? 0 : base.elements;
  rep.train_source = train.source;
  rep.validation_source = val.source;
  rep.train_samples = train.used();
  rep.validation_samples = val.used();
  EffectContext c = make_context(train);
  FitResult cur = fit_base(base, train, val, c, o.base);
  rep.elements = cur.spec.elements;
  double cur_val = rms_on(cur, val, c);
  rep.stages.push_back(cur);
  rep.rms_before_train = cur.rms_train;
  rep.rms_before_validation = cur_val;
  for (int round = 1; round <= o.max_rounds; ++round) {
    Round rd;
    rd.rms_train_before = cur.rms_train;
    rd.rms_validation_before = cur_val;
    const auto r = residual(cur, train, c);
    const auto g = unit_friction(cur, train, c);
    const Spectrum sp = position_spectrum(train, c, r);
    if (!contains(cur.spec.effects, Effect::PositionPeriodic))
      c.wavelength = sp.peak_to_median >= 4.0 ? sp.peak_wavelength : 0.0;
    if (c.wavelength > 0 && !contains(cur.spec.effects, Effect::PositionPeriodic))
      refine_wavelength(cur, train, c);
    if (!contains(cur.spec.effects, Effect::DwellStiction) &&
        effect_applicable(Effect::DwellStiction, train, c))
      choose_dwell_length(cur, train, c);
    for (Effect e : o.candidates) {
      if (contains(cur.spec.effects, e) || !effect_applicable(e, train, c)) continue;
      if (o.base.cancel && o.base.cancel->load()) throw Cancelled();
      Candidate k = screen(e, cur, train, val, c);
      k.evidence = effect_evidence(e, train, c, r, g, sp);
      rd.candidates.push_back(std::move(k));
    }
    std::stable_sort(rd.candidates.begin(), rd.candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.explained > b.explained + 1e-4; });
    int tries = 0;
    bool control_done = false;
    for (const auto& k : rd.candidates) {
      if (tries >= o.tries_per_round || k.explained < o.min_explained) break;
      if (k.screen_rms_validation >= cur_val) continue;  // not even a hint on validation
      ++tries;
      FitOptions fo = o.refit;
      fo.stage = "round " + std::to_string(round) + ": refit with " + std::string(effect_name(k.effect));
      FitResult f = fit_model(with(cur.spec, k.effect), train, c, fo, &cur.u);
      if (k.effect == Effect::PositionPeriodic) {  // re-estimate L on the refitted shape
        refine_wavelength(f, train, c);
        FitOptions po = fo;
        po.starts = 1;
        po.data_start = false;
        f = fit_model(f.spec, train, c, po, &f.u);
      }
      Attempt a{k.effect, f.rms_train, rms_on(f, val, c), false, terms_of(f, k.effect)};
      a.kept = a.rms_validation <= (1.0 - o.min_gain) * cur_val;
      if (a.kept && !control_done) {
        // Control: the current model refitted with the same budget and starts. What it gains
        // is optimisation, not the effect; the effect must beat it by the same margin.
        control_done = true;
        FitOptions co = fo;
        co.stage = "round " + std::to_string(round) + ": control refit without a new effect";
        FitResult ctrl = fit_model(cur.spec, train, c, co, &cur.u);
        if (ctrl.rms_train < cur.rms_train) {
          cur = std::move(ctrl);
          cur_val = rms_on(cur, val, c);
          rep.stages.back() = cur;
          if (round == 1) rep.rms_before_train = cur.rms_train, rep.rms_before_validation = cur_val;
          rd.rms_train_before = cur.rms_train;
          rd.rms_validation_before = cur_val;
        }
        a.kept = a.rms_validation <= (1.0 - o.min_gain) * cur_val;
      }
      rd.attempts.push_back(a);
      if (a.kept) {
        FitOptions po = fo;  // polish the kept model before the next round screens against it
        po.starts = 1;
        po.data_start = false;
        po.stage = "round " + std::to_string(round) + ": polish";
        FitResult p = fit_model(f.spec, train, c, po, &f.u);
        if (p.rms_train < f.rms_train) {
          f = std::move(p);
          a.rms_train = f.rms_train;
          a.rms_validation = rms_on(f, val, c);
          a.terms = terms_of(f, k.effect);
          rd.attempts.back() = a;
        }
        cur = f;
        cur_val = a.rms_validation;
        rd.added = k.effect;
        rep.stages.push_back(cur);
        rep.effects_added.push_back(k.effect);
        break;
      }
    }
    rd.rms_train_after = cur.rms_train;
    rd.rms_validation_after = cur_val;
    const bool added = rd.added.has_value();
    rep.rounds.push_back(std::move(rd));
    if (!added) break;
  }
  rep.context = c;
  rep.rms_after_train = cur.rms_train;
  rep.rms_after_validation = cur_val;
  return rep;
}

// ------------------------------------------------------------------------------------------------
// Report
// ------------------------------------------------------------------------------------------------

namespace {

nlohmann::json terms_json(const std::vector<LinearTerm>& ts) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& t : ts) j[t.name] = {{"value", t.value}, {"unit", t.unit}};
  return j;
}

nlohmann::json rms_json(double train, double val) {
  return {{"train", train}, {"validation", val}};
}

nlohmann::json fit_json(const FitResult& f) {
  nlohmann::json j;
  j["friction"] = to_json(f.friction);
  nlohmann::json lin = nlohmann::json::array();
  for (const auto& t : f.terms)
    lin.push_back({{"effect", t.effect}, {"name", t.name}, {"value", t.value}, {"unit", t.unit}});
  j["linear_terms"] = lin;
  nlohmann::json eff = nlohmann::json::array();
  for (Effect e : f.spec.effects) eff.push_back(std::string(effect_name(e)));
  j["effects"] = eff;
  j["rms_train"] = f.rms_train;
  j["evaluations"] = f.evaluations;
  return j;
}

}  // namespace

std::vector<ModelComparison> compare_models(const IdentReport& r, const Dataset& train,
                                            const Dataset& validation, const std::vector<std::string>& models,
                                            const FitOptions& o) {
  std::vector<ModelComparison> out;
  for (const auto& tag : models) {
    const ModelInfo& info = model_info(tag);
    FitSpec spec;
    spec.model = std::string(info.tag);
    const std::size_t wanted = r.elements ? r.elements : 4;  // a base model without elements: 4
    spec.elements = info.columns.empty() ? 0 : std::clamp(wanted, info.min_elements, info.max_elements);
    spec.effects = r.effects_added;
    FitOptions fo = o;
    fo.stage = "compare: " + spec.model;
    const auto t0 = std::chrono::steady_clock::now();
    // The loop's own model starts from where the loop left it, so it never compares worse than
    // the report says; the others start from their data-based guesses.
    const bool is_base = spec.model == r.model && spec.elements == r.elements && !r.stages.empty();
    if (is_base) fo.data_start = false;
    FitResult f = fit_model(spec, train, r.context, fo, is_base ? &r.final_fit().u : nullptr);
    // A warm-started refit, as every stage of the loop gets one: the comparison is then as well
    // converged as the loop's own final model.
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!f.time_limited && (o.max_seconds <= 0 || spent < o.max_seconds) && !f.u.empty()) {
      FitOptions again = fo;
      again.data_start = false;
      again.starts = 2;
      if (o.max_seconds > 0) again.max_seconds = o.max_seconds - spent;
      FitResult g = fit_model(spec, train, r.context, again, &f.u);
      const int evaluations = f.evaluations + g.evaluations;
      const bool limited = g.time_limited;
      if (g.rms_train < f.rms_train) f = std::move(g);
      f.evaluations = evaluations;
      f.time_limited = limited;
    }
    ModelComparison c;
    c.model = spec.model;
    c.elements = spec.elements;
    c.shape_parameters = f.u.size();
    c.rms_train = f.rms_train;
    c.rms_validation = rms_on(f, validation, r.context);
    c.evaluations = f.evaluations;
    c.time_limited = f.time_limited;
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.push_back(c);
  }
  return out;
}

std::vector<std::string> parse_model_list(std::string_view spec) {
  std::vector<std::string> out;
  if (spec == "all") {
    for (const auto& m : model_registry()) out.emplace_back(m.tag);
    return out;
  }
  std::size_t a = 0;
  while (a <= spec.size()) {
    auto b = spec.find(',', a);
    if (b == std::string_view::npos) b = spec.size();
    if (b > a) out.emplace_back(model_info(spec.substr(a, b - a)).tag);  // throws on unknown tags
    a = b + 1;
  }
  return out;
}

nlohmann::json to_json(const IdentReport& r) {
  nlohmann::json j;
  j["base_model"] = r.model;
  j["elements"] = r.elements;
  j["force_unit"] = r.force_unit;
  j["train"] = {{"source", r.train_source}, {"samples_used", r.train_samples}};
  j["validation"] = {{"source", r.validation_source}, {"samples_used", r.validation_samples}};
  j["rms_before"] = rms_json(r.rms_before_train, r.rms_before_validation);
  j["rms_after"] = rms_json(r.rms_after_train, r.rms_after_validation);
  nlohmann::json added = nlohmann::json::array();
  for (Effect e : r.effects_added) added.push_back(std::string(effect_name(e)));
  j["effects_added"] = added;
  nlohmann::json rounds = nlohmann::json::array();
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const Round& rd = r.rounds[i];
    nlohmann::json o;
    o["round"] = i + 1;
    o["effect"] = rd.added ? nlohmann::json(std::string(effect_name(*rd.added))) : nlohmann::json();
    o["rms_before"] = rms_json(rd.rms_train_before, rd.rms_validation_before);
    o["rms_after"] = rms_json(rd.rms_train_after, rd.rms_validation_after);
    if (rd.added) {
      for (const auto& k : rd.candidates)
        if (k.effect == *rd.added) o["evidence"] = k.evidence, o["explained_fraction"] = k.explained;
      for (const auto& a : rd.attempts)
        if (a.kept) o["parameters"] = terms_json(a.terms);
    } else {
      o["stopped"] = "no candidate lowered the validation RMS by the required margin";
    }
    nlohmann::json cands = nlohmann::json::array();
    for (const auto& k : rd.candidates)
      cands.push_back({{"effect", std::string(effect_name(k.effect))},
                       {"explained_fraction", k.explained},
                       {"screen_rms", rms_json(k.screen_rms_train, k.screen_rms_validation)},
                       {"evidence", k.evidence}});
    o["candidates"] = cands;
    nlohmann::json atts = nlohmann::json::array();
    for (const auto& a : rd.attempts)
      atts.push_back({{"effect", std::string(effect_name(a.effect))},
                      {"rms_after_refit", rms_json(a.rms_train, a.rms_validation)},
                      {"kept", a.kept},
                      {"parameters", terms_json(a.terms)}});
    o["attempts"] = atts;
    rounds.push_back(o);
  }
  j["rounds"] = rounds;
  if (!r.comparison.empty()) {
    nlohmann::json cmp = nlohmann::json::array();
    for (const auto& c : r.comparison)
      cmp.push_back({{"model", c.model},
                     {"elements", c.elements},
                     {"shape_parameters", c.shape_parameters},
                     {"rms", rms_json(c.rms_train, c.rms_validation)},
                     {"evaluations", c.evaluations},
                     {"seconds", c.seconds},
                     {"time_limited", c.time_limited}});
    j["model_comparison"] = cmp;
  }
  j["base_fit"] = fit_json(r.stages.front());
  j["final_model"] = fit_json(r.final_fit());
  const auto& c = r.context;
  j["context"] = {{"x_mid_m", c.x_mid},         {"x_half_m", c.x_half},
                  {"t_mid_s", c.t_mid},         {"t_half_s", c.t_half},
                  {"v_ref_mps", c.v_ref},       {"x_breakaway_m", c.x_ba},
                  {"force_level_N", c.f_level}, {"ripple_wavelength_m", c.wavelength},
                  {"dwell_decay_m", c.dwell_s0}, {"normal_force_mean_N", c.Fn0}};
  return j;
}

namespace {

// Min/max decimation to about 2 * buckets points, keeping peaks.
Series decimated(std::string label, const std::vector<double>& x, const std::vector<double>& y,
                 const std::vector<std::uint8_t>* use, std::size_t buckets = 1500) {
  Series s;
  s.label = std::move(label);
  const std::size_t n = x.size();
  const std::size_t per = std::max<std::size_t>(1, n / buckets);
  for (std::size_t b = 0; b < n; b += per) {
    std::size_t lo = n, hi = n;
    for (std::size_t k = b; k < std::min(n, b + per); ++k) {
      if (use && !(*use)[k]) continue;
      if (lo == n || y[k] < y[lo]) lo = k;
      if (hi == n || y[k] > y[hi]) hi = k;
    }
    if (lo == n) continue;
    for (std::size_t k : {std::min(lo, hi), std::max(lo, hi)}) {
      s.x.push_back(x[k]);
      s.y.push_back(y[k]);
      if (lo == hi) break;
    }
  }
  return s;
}

}  // namespace

namespace {

std::string fmt(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

std::string stage_label(const IdentReport& r, std::size_t i) {
  return i == 0 ? "base " + r.model : "+ " + std::string(effect_name(r.effects_added[i - 1]));
}

// Mean residual in signed-velocity bins over the used samples (empty bins skipped).
Series by_velocity(std::string label, const Dataset& d, const std::vector<double>& res, double vmax) {
  const int nb = 48;
  std::vector<double> s(nb, 0.0), n(nb, 0.0);
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (!d.use[k]) continue;
    const int b = static_cast<int>((d.v[k] / vmax + 1.0) * 0.5 * nb);
    if (b < 0 || b >= nb) continue;
    s[static_cast<std::size_t>(b)] += res[k], n[static_cast<std::size_t>(b)] += 1;
  }
  Series out;
  out.label = std::move(label);
  for (int b = 0; b < nb; ++b)
    if (n[static_cast<std::size_t>(b)] >= 5) {
      out.x.push_back(((b + 0.5) / nb * 2.0 - 1.0) * vmax * 1e3);
      out.y.push_back(s[static_cast<std::size_t>(b)] / n[static_cast<std::size_t>(b)]);
    }
  return out;
}

// The used samples of d within [t0, t1].
Series window(std::string label, const Dataset& d, const std::vector<double>& y, double t0, double t1) {
  Series s;
  s.label = std::move(label);
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k] && d.t[k] >= t0 && d.t[k] <= t1) s.x.push_back(d.t[k]), s.y.push_back(y[k]);
  return s;
}

}  // namespace

Figure report_figure(const IdentReport& r, const Dataset& train, const Dataset& val) {
  Figure f;
  f.id = "identify_report";
  f.title = "Identification: " + r.model + " on " +
            std::filesystem::path(r.train_source).filename().string() + ", validated on " +
            std::filesystem::path(r.validation_source).filename().string();
  std::string cap = "Validation RMS " + fmt(r.rms_before_validation) + " N (base " + r.model +
                    ") -> " + fmt(r.rms_after_validation) + " N";
  if (r.effects_added.empty()) cap += " (no effect added)";
  else {
    cap += " after adding";
    for (Effect e : r.effects_added) cap += " " + std::string(effect_name(e));
  }
  // Panel A: a 4 s window of the validation record at full resolution (masked samples left out).
  const double t0 = val.t.front() + 0.4 * (val.t.back() - val.t.front());
  const double t1 = std::min(val.t.back(), t0 + 4.0);
  Panel a{"A", "Force, validation, " + fmt(t1 - t0) + " s: measured and fitted", "t [s]",
          "F [N]", {}};
  a.series.push_back(window("measured", val, val.F, t0, t1));
  a.series.push_back(window("base " + r.model, val, predict(r.stages.front(), val, r.context), t0, t1));
  if (r.stages.size() > 1) {
    a.series.push_back(window("final", val, predict(r.final_fit(), val, r.context), t0, t1));
    a.series.back().style = Series::Style::Dashed;
  }
  // Panels B and C: residual over time and by velocity after each stage. Stages whose RMS is more
  // than 5x the final one would flatten the others and are left out (named in the caption).
  Panel b{"B", "Training residual after each round", "t [s]", "F - F_fit [N]", {}};
  Panel c{"C", "Mean training residual by velocity", "v [mm/s]", "mean F - F_fit [N]", {}};
  // Panel D: the residual's amplitude spectrum over position (the position_periodic evidence),
  // against spatial frequency so that a ripple of a few mm stands clear of the slow trends.
  Panel dp{"D", "Residual's spectrum over position", "1 / wavelength [1/mm]",
           "sine amplitude [N]", {}};
  double vmax = 0;
  for (std::size_t k = 0; k < train.size(); ++k)
    if (train.use[k]) vmax = std::max(vmax, std::abs(train.v[k]));
  std::string left_out;
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    if (i + 1 < r.stages.size() && r.stages[i].rms_train > 5.0 * r.final_fit().rms_train) {
      left_out += (left_out.empty() ? "" : ", ") + stage_label(r, i) + " (" + fmt(r.stages[i].rms_train) + " N RMS)";
      continue;
    }
    auto res = predict(r.stages[i], train, r.context);
    for (std::size_t k = 0; k < train.size(); ++k) res[k] = train.F[k] - res[k];
    b.series.push_back(decimated(stage_label(r, i), train.t, res, &train.use));
    c.series.push_back(by_velocity(stage_label(r, i), train, res, vmax));
    const Spectrum sp = position_spectrum(train, r.context, res);
    Series spec;
    spec.label = stage_label(r, i);
    for (std::size_t k = sp.wavelength.size(); k-- > 0;)  // ascending spatial frequency
      spec.x.push_back(1e-3 / sp.wavelength[k]), spec.y.push_back(sp.amplitude[k]);
    if (!spec.x.empty()) dp.series.push_back(std::move(spec));
  }
  if (!left_out.empty()) cap += ". B, C, D leave out " + left_out;
  f.caption = cap;
  f.panels = {std::move(a), std::move(b), std::move(c)};
  if (!dp.series.empty()) f.panels.push_back(std::move(dp));
  return f;
}

Scenario identified_scenario(const IdentReport& r, const Dataset& train) {
  Scenario s;
  const FitResult& fr = r.final_fit();
  s.name = "Identified " + r.model + " (" + std::filesystem::path(r.train_source).filename().string() + ")";
  std::ostringstream d;
  d << "Friction identified by gmslab identify; validation RMS " << r.rms_after_validation
    << " N. Replays the training motion.";
  s.plant.mass = 1.0;
  for (const auto& t : fr.terms) {
    if (t.name == "M" && t.value > 0) s.plant.mass = t.value;
    else if (t.effect != "base") d << ' ' << t.effect << '.' << t.name << " = " << t.value << ' ' << t.unit << ';';
  }
  s.description = d.str();
  s.friction = fr.friction;
  s.drive.kind = Drive::Kind::Displacement;
  std::vector<double> pt, py;
  const std::size_t stride = std::max<std::size_t>(1, train.size() / 5000);
  for (std::size_t k = 0; k < train.size(); k += stride) {
    pt.push_back(train.t[k] - train.t.front());
    py.push_back(train.x[k]);
  }
  s.drive.signal = Signal::piecewise_linear(pt, py);
  std::vector<double> h(train.h.begin() + 1, train.h.end());
  std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(h.size() / 2), h.end());
  s.run.dt = h[h.size() / 2];
  s.run.duration = pt.back();
  s.run.record_every = 1;
  return s;
}

}  // namespace gmslab::ident
