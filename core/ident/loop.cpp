#include "core/ident/loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <sstream>
#include <limits>
#include <map>
#include <set>
#include <optional>
#include <cstdio>
#include <Eigen/Dense>

#include "core/ident/ablation.hpp"
#include "core/ident/loop_stages.hpp"
#include "core/ident/element_fit.hpp"
#include "core/ident/evidence.hpp"
#include "core/ident/parallel.hpp"
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

using detail::contains;
using detail::fmt;
using detail::ordinal;
using detail::residual;
using detail::terms_of;


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

std::string nothing_added(const IdentReport& r) {
  if (!r.effects_added.empty()) return {};
  if (!r.rounds_skipped.empty()) return "nothing added: " + r.rounds_skipped;
  if (const std::string more = more_elements_summary(r.ablation); !more.empty())
    return "nothing added: " + more;
  return "nothing added: no catalog effect is credited by the data";
}

std::string screen_summary(const IdentReport& r) {
  if (r.screen_every <= 1) return {};
  return "the loop screened every " + ordinal(r.screen_every) + " training sample; the final fit used all";
}

IdentReport identify(const Dataset& train, const Dataset& validation, const FitSpec& base,
                     const LoopOptions& o) {
  check_identifiable(train, "training", true);
  check_identifiable(validation, "validation", false);
  detail::LoopState s(train, validation, base, o);
  detail::screen_record(s);
  detail::choose_path(s);
  detail::retry_base_fit(s);
  s.cur_val = rms_on(s.cur, s.val(), s.c);
  detail::widen_stribeck_range(s);
  detail::widen_break_away_range(s, true);
  detail::widen_element_range(s, true);
  if (s.rep.range_widened) s.add_shares();
  s.floor = s.rep.noise.floor();
  s.rep.stages.push_back(s.cur);
  s.rep.rms_before_train = s.cur.rms_train;
  s.rep.rms_before_validation = s.cur_val;
  if (!detail::no_effect_creditable(s))
    for (int round = 1; round <= o.max_rounds; ++round)
      if (!detail::run_round(s, round)) break;
  detail::final_refit(s);
  detail::widen_break_away_range(s, false);
  detail::credit(s);
  detail::descend_to_minimum(s);
  detail::discover_terms(s);
  detail::join_discovered(s);
  detail::finish_report(s);
  return std::move(s.rep);
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

std::vector<double> predict_final(const IdentReport& r, const Dataset& d) {
  auto f = predict(r.final_fit(), d, r.context);
  if (!r.discovery.found || r.discovery.joined) return f;
  const auto extra = discovered_force(r.discovery, d, r.context, f);
  for (std::size_t k = 0; k < f.size(); ++k) f[k] += extra[k];
  return f;
}

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

nlohmann::json to_json(const Ablation& a, const std::vector<Effect>& named) {
  nlohmann::json j;
  j["ran"] = a.ran;
  j["test"] = "refit from the final shape with the refit budget, without each effect; credited when the "
              "validation MSE difference over time blocks has z >= " + fmt(a.z_crit) +
              ", the contribution is at least half the floor and the model without it is above 1.15x the floor";
  j["validation_rms_all_N"] = a.rms_validation_all;
  j["validation_rms_all_elements_N"] = a.rms_validation_all_elements;
  j["floor_N"] = a.floor;
  j["named"] = named_effects(a, named);
  auto row = [](const AblationRow& r) {
    nlohmann::json alike = nlohmann::json::array();
    for (Effect e : r.alike) alike.push_back(std::string(effect_name(e)));
    nlohmann::json more;  // null: not tested
    if (r.more_elements > 0)
      more = {{"elements", r.more_elements},
              {"validation_rms_N", r.rms_validation_more_elements},
              {"z", std::isfinite(r.more_elements_test.z) ? nlohmann::json(r.more_elements_test.z)
                                                          : nlohmann::json("inf")},
              {"explains_it_as_well", r.explained_by_element}};
    return nlohmann::json{
        {"effect", std::string(effect_name(r.effect))},
        {"validation_rms_without_N", r.rms_validation_without},
        {"mse_difference_N2", r.test.mse_difference},
        {"std_error_N2", r.test.std_error},
        {"z", std::isfinite(r.test.z) ? nlohmann::json(r.test.z) : nlohmann::json("inf")},
        {"blocks", r.test.blocks},
        {"contribution_N", r.contribution},
        {"credited", r.credited},
        {"alike", alike},
        {"more_elements", more},
        {"verdict", r.verdict}};
  };
  nlohmann::json rows = nlohmann::json::array(), dropped = nlohmann::json::array();
  for (const auto& r : a.rows) rows.push_back(row(r));
  for (const auto& r : a.dropped) dropped.push_back(row(r));
  j["rows"] = rows;
  j["dropped"] = dropped;
  nlohmann::json els = nlohmann::json::array();
  for (const auto& e : a.elements)
    els.push_back({{"elements", e.elements},
                   {"validation_rms_without_N", e.rms_validation_without},
                   {"z", std::isfinite(e.test.z) ? nlohmann::json(e.test.z) : nlohmann::json("inf")},
                   {"dropped", e.dropped},
                   {"verdict", e.verdict}});
  j["element_count"] = {{"before", a.elements_before}, {"tests", els}};
  const std::string more = more_elements_summary(a);
  j["more_elements"] = {
      {"test",
       "each effect that passes is refitted out with one element more, from the final shape plus "
       "the element that helps most; not credited when the data do not resolve that model from "
       "the one with the effect (the same test)"},
      {"called_for",
       a.elements_called_for > 0 ? nlohmann::json(a.elements_called_for) : nlohmann::json()},
      {"count_raised", a.count_raised},
      {"summary", more.empty() ? nlohmann::json() : nlohmann::json(more)}};
  return j;
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
      o["stopped"] = rd.attempts.empty()
                         ? "no candidate with a signature in the residual (training F-test) that also lowers the validation RMS"
                         : "no candidate passed: validation RMS drop, validation BIC and size against the noise";
    }
    nlohmann::json cands = nlohmann::json::array();
    for (const auto& k : rd.candidates)
      cands.push_back(
          {{"effect", std::string(effect_name(k.effect))},
           {"explained_fraction", k.explained},
           {"signature_p_value", k.p_value},
           {"screen_rms", rms_json(k.screen_rms_train, k.screen_rms_validation)},
           {"screen_validation_z", std::isnan(k.screen_z)   ? nlohmann::json()
                                   : std::isinf(k.screen_z) ? nlohmann::json("infinite")
                                                            : nlohmann::json(k.screen_z)},
           {"evidence", k.evidence}});
    o["candidates"] = cands;
    nlohmann::json atts = nlohmann::json::array();
    for (const auto& a : rd.attempts)
      atts.push_back({{"effect", std::string(effect_name(a.effect))},
                      {"rms_after_refit", rms_json(a.rms_train, a.rms_validation)},
                      {"kept", a.kept},
                      {"verdict", a.verdict},
                      {"contribution_rms_N", a.size},
                      {"validation_bic_change", a.bic_change},
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
  j["noise"] = {{"sigma_N", r.noise.sigma},          {"from_rests", r.noise.from_rests},
                {"samples", r.noise.samples},         {"encoder_step_m", r.noise.quantum},
                {"quantisation_N", r.noise.quantisation}, {"sampling_N", r.noise.sampling},
                {"floor_N", r.noise.floor()}};
  j["path"] = {{"fine", r.fine_path}, {"difference_N", r.path_difference}};
  j["screened_every"] = r.screen_every;
  j["rounds_skipped"] =
      r.rounds_skipped.empty() ? nlohmann::json() : nlohmann::json(r.rounds_skipped);
  j["base_retried"] = r.base_retried;
  j["element_range_widened"] = r.range_widened;
  j["stribeck_range_widened"] = r.stribeck_range_widened;
  j["break_away_range_widened"] = r.break_away_range_widened;
  j["ripple_search"] = to_json(r.ripples);
  nlohmann::json pars = nlohmann::json::array();
  for (const auto& p : r.parameters)
    pars.push_back(
        {{"effect", p.effect},
         {"name", p.name},
         {"unit", p.unit},
         {"value", p.value},
         {"std_error", std::isfinite(p.std_error) ? nlohmann::json(p.std_error) : nlohmann::json()},
         {"std_error_path",
          std::isfinite(p.std_error) ? nlohmann::json(p.path_error) : nlohmann::json()},
         {"std_error_encoder",
          std::isfinite(p.std_error) ? nlohmann::json(p.encoder_error) : nlohmann::json()},
         {"no_error", p.no_error}});
  j["parameters"] = pars;
  j["converged"] = {{"verified_minimum", r.optimum.verified}, {"reason", r.optimum.reason}};
  j["remaining_structure"] = to_json(r.remaining);
  j["notes"] = r.notes;
  j["ablation"] = to_json(r.ablation, r.effects_added);
  j["discovery"] = to_json(r.discovery);
  j["base_fit"] = fit_json(r.stages.front());
  j["final_model"] = fit_json(r.final_fit());
  const auto& c = r.context;
  j["context"] = {{"x_mid_m", c.x_mid},           {"x_half_m", c.x_half},
                  {"t_mid_s", c.t_mid},           {"t_half_s", c.t_half},
                  {"v_ref_mps", c.v_ref},         {"x_breakaway_m", c.x_ba},
                  {"force_level_N", c.f_level},   {"ripple_wavelengths_m", c.wavelengths},
                  {"time_shift_s", c.time_shift}, {"filter_time_constant_s", c.filter_T},
                  {"backlash_m", c.backlash},     {"sample_step_s", c.h_med},
                  {"dwell_decay_m", c.dwell_s0},  {"dwell_rise_per_ln", c.dwell_rise},
                  {"normal_force_mean_N", c.Fn0}};
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

std::string stage_label(const IdentReport& r, std::size_t i) {
  if (i == 0) return "base " + r.model;
  // The effects this stage has that the one before lacks (one per round; the credited set after
  // an ablation dropped some).
  std::string s;
  for (Effect e : r.stages[i].spec.effects)
    if (!contains(r.stages[i - 1].spec.effects, e)) s += (s.empty() ? "+ " : " + ") + std::string(effect_name(e));
  return s.empty() ? "refit" : s;
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
  if (r.stages.size() > 1 || r.discovery.found) {
    a.series.push_back(window("final", val, predict_final(r, val), t0, t1));
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
