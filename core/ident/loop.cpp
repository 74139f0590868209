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

namespace {

std::string fmt(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

// 2 -> "2nd", 12 -> "12th", 23 -> "23rd".
std::string ordinal(std::size_t n) {
  const std::size_t t = n % 100, u = n % 10;
  const char* suffix = (t >= 11 && t <= 13) ? "th" : u == 1 ? "st" : u == 2 ? "nd" : u == 3 ? "rd" : "th";
  return std::to_string(n) + suffix;
}

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

// Columns of an effect at the shape of f (g: unit friction along d).
std::vector<std::vector<double>> effect_matrix(Effect e, const Dataset& d, const EffectContext& c,
                                               const std::vector<double>& g) {
  std::vector<double> g2 = g;
  if (e == Effect::DwellStiction) g2.insert(g2.end(), g.begin(), g.end());  // sensitivity ~ g
  std::vector<std::vector<double>> out;
  for (const auto& col : effect_columns(e)) {
    std::vector<double> o(d.size(), 0.0);
    col.fill(d, c, g2, o);
    out.push_back(std::move(o));
  }
  return out;
}

double chi2_tail_large(double x, double dof) {
  // Wilson-Hilferty: chi^2 tail through the normal tail (enough for a screening threshold).
  if (dof <= 0) return 1.0;
  const double z = (std::cbrt(x / dof) - (1 - 2 / (9 * dof))) / std::sqrt(2 / (9 * dof));
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

Candidate screen(Effect e, const FitResult& cur, const Dataset& train, const Dataset& val,
                 const EffectContext& c, const std::vector<double>* shape = nullptr) {
  Candidate k;
  k.effect = e;
  if (shape && shape->size() != cur.u.size()) shape = nullptr;  // not a shape of cur's parameterization
  const auto lin = refit_linear(with(cur.spec, e), train, c, shape ? *shape : cur.u);
  k.screen_rms_train = lin.rms_train;
  k.explained = cur.rms_train > 0 ? 1.0 - std::pow(lin.rms_train / cur.rms_train, 2) : 0.0;
  k.screen_rms_validation = rms_on(lin, val, c);
  std::size_t q = 0;
  for (const auto& t : terms_of(lin, e)) q += t.value != 0.0;
  k.columns = q;
  const double n = static_cast<double>(train.used());
  const double p = static_cast<double>(lin.terms.size());
  const double s0 = cur.rms_train * cur.rms_train * n, s1 = lin.rms_train * lin.rms_train * n;
  if (q > 0 && s1 > 0 && n > p + 1) {
    const double F = (s0 - s1) / static_cast<double>(q) / (s1 / (n - p));
    k.p_value = chi2_tail_large(F * static_cast<double>(q), static_cast<double>(q));
  }
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

// A measurement effect's scalar (tau, T or b): the grid value with the lowest training RMS of a
// linear refit, refined by golden section between its neighbours.
void tune_scalar(const FitResult& cur, const Dataset& train, EffectContext& c, Effect e,
                 double EffectContext::*field, const std::vector<double>& grid) {
  const FitSpec spec = contains(cur.spec.effects, e) ? cur.spec : with(cur.spec, e);
  auto cost = [&](double v) {
    c.*field = v;
    return refit_linear(spec, train, c, cur.u).rms_train;
  };
  std::size_t bi = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> costs;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    costs.push_back(cost(grid[i]));
    if (costs.back() < best) best = costs.back(), bi = i;
  }
  // Neighbours on the same side of zero.
  double a = grid[bi], b = grid[bi];
  if (bi > 0 && grid[bi - 1] * grid[bi] > 0) a = grid[bi - 1];
  if (bi + 1 < grid.size() && grid[bi + 1] * grid[bi] > 0) b = grid[bi + 1];
  const double gr = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = b - gr * (b - a), x2 = a + gr * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int i = 0; i < 20 && b - a > 1e-4 * std::abs(grid[bi]); ++i) {
    if (f1 < f2) b = x2, x2 = x1, f2 = f1, x1 = b - gr * (b - a), f1 = cost(x1);
    else a = x1, x1 = x2, f1 = f2, x2 = a + gr * (b - a), f2 = cost(x2);
  }
  const double xr = f1 < f2 ? x1 : x2;
  c.*field = std::min(f1, f2) < best ? xr : grid[bi];
}

// The measurement effects' scalars. A channel effect changes what shape fits best (a lagging
// force looks like softer presliding), so with `deep` each coarse grid value gets a short refit of
// the shape first; the scalar is then refined by linear refits at the best of those shapes, which
// is returned as the effect's warm start. Without `deep`: linear refits at the current shape.
std::map<Effect, std::vector<double>> tune_measurement_effects(const FitResult& cur, const Dataset& train,
                                                               EffectContext& c,
                                                               const std::vector<Effect>& candidates,
                                                               bool deep, const FitOptions& refit,
                                                               std::set<Effect>* deep_done = nullptr) {
  std::map<Effect, std::vector<double>> shapes;
  const double h = c.h_med;
  auto want = [&](Effect e) {
    if (!contains(candidates, e) || contains(cur.spec.effects, e)) return false;
    // The deep search once per effect: later rounds tune its scalar by linear refits only.
    if (deep && deep_done) return deep_done->insert(e).second;
    return true;
  };
  auto run = [&](Effect e, double EffectContext::*field, const std::vector<double>& coarse,
                 const std::vector<double>& fine) {
    if (!want(e)) return;
    if (!deep) {
      tune_scalar(cur, train, c, e, field, fine);
      return;
    }
    FitOptions fo = serialised_progress(refit);
    fo.starts = 1;
    fo.data_start = false;
    fo.max_evaluations = std::min(refit.max_evaluations, 120);
    // The coarse values' shape refits are independent: all at once, each on its own threads (the
    // same results as one after the other), taken in order. Each names its value in the progress
    // lines, which interleave.
    std::vector<std::future<FitResult>> fits;
    const FitSpec spec = with(cur.spec, e);
    for (double v : coarse) {
      EffectContext cv = c;
      cv.*field = v;
      FitOptions fv = fo;
      fv.stage = "search " + std::string(effect_name(e)) + " at " +
                 (field == &EffectContext::backlash ? fmt(1e6 * v) + " um" : fmt(1e3 * v) + " ms");
      fits.push_back(std::async(std::launch::async, [&, cv, fv] { return fit_model(spec, train, cv, fv, &cur.u); }));
    }
    double best = std::numeric_limits<double>::infinity();
    std::optional<FitResult> bf;
    double bv = coarse.front();
    for (std::size_t i = 0; i < coarse.size(); ++i) {
      FitResult f = fits[i].get();
      if (f.rms_train < best) best = f.rms_train, bv = coarse[i], bf = std::move(f);
    }
    std::vector<double> grid;  // fine grid within the neighbours of the best coarse value
    for (double m : {0.4, 0.55, 0.75, 0.9, 1.0, 1.12, 1.3, 1.6, 2.0}) grid.push_back(bv * m);
    tune_scalar(*bf, train, c, e, field, grid);
    // A refit that kept fewer elements (light ones dropped) has a shape of another size: the
    // candidate is then screened at the current shape.
    if (bf->spec.elements == cur.spec.elements && bf->u.size() == cur.u.size()) shapes[e] = bf->u;
  };
  // Positive shifts only (the force channel lags): a leading force would be read from the
  // viscous share of the shift (about -sigma2 tau a) as a stand-in for inertia.
  run(Effect::TimeShift, &EffectContext::time_shift, {0.5 * h, h, 2 * h, 4 * h, 8 * h},
      {0.1 * h, 0.2 * h, 0.5 * h, h, 2 * h, 3 * h, 5 * h, 8 * h, 12 * h, 20 * h, 30 * h});
  run(Effect::SensorFilter, &EffectContext::filter_T, {h, 3 * h, 9 * h},
      {0.2 * h, 0.5 * h, h, 2 * h, 3 * h, 5 * h, 8 * h, 12 * h, 20 * h, 30 * h});
  const double xb = c.x_ba;
  run(Effect::Backlash, &EffectContext::backlash, {0.2 * xb, xb, 5 * xb},
      {0.05 * xb, 0.1 * xb, 0.2 * xb, 0.4 * xb, 0.7 * xb, xb, 1.5 * xb, 2.5 * xb, 4 * xb, 6 * xb});
  return shapes;
}

// Standard errors of the final model's linear terms (and the effects' scalars) from the
// linearised least squares at the fitted shape.
std::vector<ParameterEstimate> parameter_estimates(const FitResult& f, const Dataset& d,
                                                   const EffectContext& c) {
  const auto g = unit_friction(f, d, c);
  std::vector<std::vector<double>> cols;
  std::vector<ParameterEstimate> out;
  for (const auto& t : f.terms)
    if (t.effect == "base") {
      cols.push_back(t.name == "Fc" ? g : d.v);
      out.push_back({t.effect, t.name, t.unit, t.value, 0});
    }
  for (Effect e : f.spec.effects) {
    auto m = effect_matrix(e, d, c, g);
    const auto ts = terms_of(f, e);
    for (std::size_t j = 0; j < m.size() && j < ts.size(); ++j) {
      cols.push_back(std::move(m[j]));
      out.push_back({ts[j].effect, ts[j].name, ts[j].unit, ts[j].value, 0});
    }
  }
  const std::size_t nlin = cols.size();
  // The scalars: derivative of the effect's contribution sum_j theta_j c_j with respect to them.
  struct Scalar { Effect e; std::string name, unit; double value; int index = -1; };
  std::vector<Scalar> sc;
  for (Effect e : f.spec.effects) {
    if (e == Effect::TimeShift) sc.push_back({e, "tau", "s", c.time_shift});
    if (e == Effect::SensorFilter) sc.push_back({e, "T", "s", c.filter_T});
    if (e == Effect::Backlash) sc.push_back({e, "b", "m", c.backlash});
    if (e == Effect::PositionPeriodic)
      for (std::size_t i = 0; i < c.wavelengths.size(); ++i)
        sc.push_back({e, "L" + std::to_string(i + 1), "m", c.wavelengths[i], static_cast<int>(i)});
  }
  for (const auto& s : sc) {
    const double step = std::max(1e-4 * std::abs(s.value), s.unit == "s" ? 1e-3 * c.h_med : 1e-12);
    std::vector<double> der(d.size(), 0.0);
    const auto ts = terms_of(f, s.e);
    for (int sign : {1, -1}) {
      EffectContext cc = c;
      if (s.e == Effect::TimeShift) cc.time_shift += sign * step;
      if (s.e == Effect::SensorFilter) cc.filter_T += sign * step;
      if (s.e == Effect::Backlash) cc.backlash += sign * step;
      if (s.index >= 0) cc.wavelengths[static_cast<std::size_t>(s.index)] += sign * step;
      const auto m = effect_matrix(s.e, d, cc, g);
      for (std::size_t j = 0; j < m.size() && j < ts.size(); ++j)
        for (std::size_t k = 0; k < d.size(); ++k) der[k] += sign * ts[j].value * m[j][k] / (2 * step);
    }
    cols.push_back(std::move(der));
    out.push_back({std::string(effect_name(s.e)), s.name, s.unit, s.value, 0});
  }
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) rows.push_back(k);
  const auto p = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd A(static_cast<Eigen::Index>(rows.size()), p);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (Eigen::Index j = 0; j < p; ++j) A(static_cast<Eigen::Index>(i), j) = cols[static_cast<std::size_t>(j)][rows[i]];
  const double n = static_cast<double>(rows.size());
  const double s2 = f.rms_train * f.rms_train * n / std::max(1.0, n - static_cast<double>(p));
  // Columns that are all zero (unused ripple slots) get no error; the others by a pseudo-inverse.
  std::vector<Eigen::Index> live;
  for (Eigen::Index j = 0; j < p; ++j)
    if (A.col(j).squaredNorm() > 0) live.push_back(j);
  Eigen::MatrixXd Al(A.rows(), static_cast<Eigen::Index>(live.size()));
  for (std::size_t j = 0; j < live.size(); ++j) Al.col(static_cast<Eigen::Index>(j)) = A.col(live[j]);
  Eigen::VectorXd sc_ = Al.colwise().norm().cwiseMax(1e-300).cwiseInverse();
  const Eigen::MatrixXd G = sc_.asDiagonal() * (Al.transpose() * Al) * sc_.asDiagonal();
  const Eigen::MatrixXd Ginv = G.completeOrthogonalDecomposition().pseudoInverse();
  for (std::size_t j = 0; j < live.size(); ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    out[static_cast<std::size_t>(live[j])].std_error = std::sqrt(std::max(0.0, s2 * Ginv(jj, jj))) * sc_(jj);
  }
  (void)nlin;
  // Leave out the unused ripple slots.
  std::vector<ParameterEstimate> kept;
  for (std::size_t j = 0; j < out.size(); ++j)
    if (A.col(static_cast<Eigen::Index>(j)).squaredNorm() > 0 || out[j].effect == "base") kept.push_back(out[j]);
  return kept;
}

// Whether the final shape is a minimum of the training RMS: every coordinate of the unit box
// stepped by +-1e-3 (inside the box) with the linear terms re-solved must not lower the RMS by
// more than 1e-5 relative (gradient test), and the second difference along each must not be
// negative (curvature test). Standard errors mean something only there.
OptimumCheck check_optimum(const FitResult& f, const Dataset& d, const EffectContext& c) {
  OptimumCheck out;
  if (f.time_limited) {
    out.verified = false;
    out.reason = "the fit was stopped by its time limit";
    return out;
  }
  const Parameterization par(model_info(f.spec.model), f.spec.elements, c);
  if (f.u.size() != par.size()) return out;
  const double c0 = refit_linear(f.spec, d, c, f.u).rms_train;
  const double h = 1e-3;
  double worst = 0;
  for (std::size_t i = 0; i < f.u.size(); ++i) {
    double side[2] = {c0, c0};
    for (int k = 0; k < 2; ++k) {
      std::vector<double> u = f.u;
      u[i] += k == 0 ? h : -h;
      if (u[i] < 0.0 || u[i] > 1.0) continue;
      side[k] = refit_linear(f.spec, d, c, u).rms_train;
    }
    const double drop = (c0 - std::min(side[0], side[1])) / std::max(c0, 1e-300);
    const bool curved_down = side[0] + side[1] - 2 * c0 < -1e-9 * c0;
    if ((drop > 1e-5 || curved_down) && drop >= worst) {
      worst = drop;
      out.verified = false;
      out.reason = "a step of 1e-3 of its range in " + par.params()[i].name + " lowers the training RMS by " +
                   fmt(100 * drop) + " %: not at a minimum";
    }
  }
  return out;
}

// spec with the additive effects a shape or a soft element could stand in for (offset, inertia,
// time drift, a force along the stroke; those whose columns do not depend on the friction) added
// as linear columns: probes for comparing shapes and element ranges fairly.
// Whether one of e's columns multiplies the friction (needs g, the unit model output).
bool multiplies_friction(Effect e) {
  const auto cols = effect_columns(e);
  return std::any_of(cols.begin(), cols.end(), [](const Column& col) { return col.uses_g; });
}

// The element-range test solves the inertia probe only where the fit's residual holds a positive
// mass: a model lagging along the sampled path leaves -M a in its residual, and a probe column
// that takes it up hides what a soft element explains. (The base-fit retry keeps the inertia
// probe: without it seed 28 of the base study is not retried and stays at 4.2x instead of 3.2x.)
FitSpec with_additive_probes(FitSpec spec, bool inertia = true) {
  for (Effect e : {Effect::Offset, Effect::Inertia, Effect::TimeDrift, Effect::PositionDependent})
    if (!multiplies_friction(e) && !contains(spec.effects, e) && (inertia || e != Effect::Inertia))
      spec.effects.push_back(e);
  return spec;
}

// Whether f's training residual correlates positively with the acceleration (sign of the least
// squares mass M = sum r a / sum a^2).
bool residual_mass_positive(const FitResult& f, const Dataset& d, const EffectContext& c) {
  const auto r = residual(f, d, c);
  double ra = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) ra += r[k] * d.a[k];
  return ra > 0;
}
FitSpec additive_probes_for(const FitResult& f, const Dataset& d, const EffectContext& c) {
  return with_additive_probes(f.spec, residual_mass_positive(f, d, c));
}

// The named effects are those the ablation credits (ablation.hpp): refits without each, from the
// final shape with the loop's refit budget, on the record the loop decided on; validation by the
// block test. A dropped effect's gain goes to the refit: the model without it is the final one
// (polished on all samples when the loop screened), and the stages and effects are those named.
void credit_by_ablation(IdentReport& rep, FitResult& cur, double& cur_val, const Dataset& train,
                        const Dataset& full, const Dataset& val, const EffectContext& c, double floor,
                        std::size_t every, const LoopOptions& o) {
  if (cur.spec.effects.empty() && cur.spec.elements < 2) return;
  std::vector<std::pair<Effect, Effect>> alternatives;
  for (const auto& rd : rep.rounds)
    if (rd.added)
      for (const auto& a : rd.attempts)
        if (a.effect != *rd.added && a.verdict.rfind("passed", 0) == 0) alternatives.emplace_back(*rd.added, a.effect);
  AblationOptions ao;
  ao.refit = o.refit;
  ao.refit.stage = "ablation";
  ao.min_size = o.min_size;
  AblationResult ab = ablate(cur, train, val, c, floor, alternatives, ao);
  rep.ablation = ab.table;
  const bool fewer_elements = std::any_of(ab.table.elements.begin(), ab.table.elements.end(),
                                          [](const ElementAblation& e) { return e.dropped; });
  if (ab.table.dropped.empty() && !fewer_elements) {
    if (ab.model.rms_train < cur.rms_train && every == 1) cur = ab.model, cur_val = ab.rms_validation;
    rep.stages.back() = cur;
    return;
  }
  FitResult f = std::move(ab.model);
  if (every > 1) {
    FitOptions fo = o.refit;
    fo.stage = "final refit of the credited model";
    fo.polish_only = true;
    fo.rel_tol = 1e-5;
    FitResult p = fit_model(f.spec, full, c, fo, &f.u);
    f.rms_train = rms_on(f, full, c);
    if (p.rms_train < f.rms_train) f = std::move(p);
  }
  cur = std::move(f);
  cur_val = rms_on(cur, val, c);
  for (const auto& d : ab.table.dropped)
    rep.notes.push_back(std::string(effect_name(d.effect)) + " not named: " + d.verdict);
  for (const auto& e : ab.table.elements)
    if (e.dropped) rep.notes.push_back(e.verdict);
  rep.elements = cur.spec.elements;
  rep.effects_added = cur.spec.effects;
  if (ab.table.dropped.empty() && rep.stages.size() > 1) {
    rep.stages.back() = cur;  // the same effects, fewer elements
    return;
  }
  std::vector<FitResult> stages{rep.stages.front()};
  if (!cur.spec.effects.empty()) stages.push_back(cur);
  else stages.front() = cur;
  rep.stages = std::move(stages);
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

std::string screen_summary(const IdentReport& r) {
  if (r.screen_every <= 1) return {};
  return "the loop screened every " + ordinal(r.screen_every) + " training sample; the final fit used all";
}

IdentReport identify(const Dataset& train_in, const Dataset& val_in, const FitSpec& base,
                     const LoopOptions& o) {
  check_identifiable(train_in, "training", true);
  check_identifiable(val_in, "validation", false);
  EffectContext c = make_context(train_in);
  IdentReport rep;
  rep.noise = noise_level(train_in, c);
  // A long record is screened on every k-th sample (at least screen_samples of them): the base fit
  // and every decision of the loop on it, the floor and the final refit on all samples.
  std::size_t every =
      o.screen_samples > 0 && train_in.size() >= 2 * o.screen_samples ? train_in.size() / o.screen_samples : 1;
  Dataset screen_rec = every > 1 ? decimated(train_in, every, PathRule{}) : Dataset{};
  FitResult cur = fit_base(base, every > 1 ? screen_rec : train_in, val_in, c, o.base);
  auto friction_force = [&](const FitResult& f, const Dataset& d, bool straight = false) {
    auto g = straight ? unit_friction(f, with_straight_steps(d), c) : unit_friction(f, d, c);
    const double fc = f.theta.empty() ? 1.0 : f.theta[0];
    for (auto& x : g) x *= fc;
    return g;
  };
  // The screened record must drive the friction as the full one does: the base fit's friction along
  // both, compared at the kept samples, within a quarter of the noise. Else every k/2-th sample is
  // tried (and so on), and the base fit is made again on the record that passes. (Slow motion at a
  // steep Stribeck curve: the step velocities of a quantised position at the full rate and at
  // every k-th sample give S(v) different means.)
  if (every > 1) {
    const auto ff = friction_force(cur, train_in);
    auto difference = [&](std::size_t e, const Dataset& sc) {
      const auto fs = friction_force(cur, sc);
      double s2 = 0, n = 0;
      for (std::size_t k = 0; k < sc.size(); ++k)
        if (sc.use[k]) s2 += (fs[k] - ff[k * e]) * (fs[k] - ff[k * e]), n += 1;
      return n > 0 ? std::sqrt(s2 / n) : 0.0;
    };
    std::size_t e = every;
    double diff = difference(e, screen_rec);
    const double first_diff = diff;
    while (e > 1 && diff > 0.25 * rep.noise.sigma) {
      e /= 2;
      if (e > 1) screen_rec = decimated(train_in, e, PathRule{}), diff = difference(e, screen_rec);
    }
    if (e != every) {
      rep.notes.push_back("every " + ordinal(every) + " sample would change the base fit's friction by " +
                          std::to_string(first_diff) + " N RMS (more than a quarter of the noise, " +
                          std::to_string(0.25 * rep.noise.sigma) + " N): " +
                          (e == 1 ? std::string("all samples used") : "screened on every " + ordinal(e) + " sample"));
      every = e;
      if (every == 1) screen_rec = Dataset{};
      cur = fit_base(base, every > 1 ? screen_rec : train_in, val_in, c, o.base);
    }
  }
  // The path between samples. The adaptive path steps straight where the speed hardly changes;
  // with a fast attraction (C h >> 1) the force at a sample follows the speed at that sample, and
  // the straight step's mean speed is half a step late. When the base fit's friction along the
  // fine path differs from it by more than a quarter of the noise, everything runs on the fine
  // path (the base fit too: the element table found on the adaptive path bends to its error).
  // Only a fast attraction makes the path within a step matter (a slipping element relaxes at
  // C / S(v); at least a tenth of the way within the median step): on slow-relaxing records the
  // difference is the base fit's own roughness, and the fine path costs 4x the time for nothing
  // (path_difference stays 0: not measured).
  Dataset train_fine, val_fine;
  double relax = 1.0;  // relaxation per median step; models without C: only the difference decides
  const ModelInfo& fi = model_info(cur.friction.model);
  if (fi.scalar_index("C") >= 0 && fi.scalar_index("Fs") >= 0 && cur.friction.scalar("Fs") > 0)
    relax = cur.friction.scalar("C") / cur.friction.scalar("Fs") * c.h_med;
  if (relax >= 0.1) {
    train_fine = train_in;
    set_path(train_fine, kFinePath);
    const auto g0 = unit_friction(cur, train_in, c), g1 = unit_friction(cur, train_fine, c);
    const double fc = cur.theta.empty() ? 1.0 : cur.theta[0];
    double s = 0, n = 0;
    for (std::size_t k = 0; k < train_in.size(); ++k)
      if (train_in.use[k]) s += std::pow(fc * (g1[k] - g0[k]), 2), n += 1;
    rep.path_difference = n > 0 ? std::sqrt(s / n) : 0.0;
    rep.fine_path = rep.path_difference > 0.25 * rep.noise.sigma;
    if (rep.fine_path) {
      val_fine = val_in;
      set_path(val_fine, kFinePath);
      if (every > 1) screen_rec = decimated(train_fine, every, kFinePath);
      cur = fit_base(base, every > 1 ? screen_rec : train_fine, val_fine, c, o.base);
    } else {
      train_fine = Dataset{};
    }
  }
  const Dataset& full = rep.fine_path ? train_fine : train_in;
  const Dataset& val = rep.fine_path ? val_fine : val_in;
  const Dataset& train = every > 1 ? screen_rec : full;
  rep.screen_every = every;
  rep.model = base.model;
  rep.train_source = full.source;
  rep.validation_source = val.source;
  rep.train_samples = full.used();
  rep.validation_samples = val.used();
  rep.elements = cur.spec.elements;
  // The quantisation and sampling shares of the floor, through the base fit (updated at the end).
  const NoiseEstimate noise_data = rep.noise;
  auto add_shares = [&] {
    rep.noise = noise_data;
    const auto f = friction_force(cur, full);
    add_quantisation(rep.noise, full, c, f);
    add_sampling(rep.noise, full, f, friction_force(cur, full, true));
  };
  add_shares();
  // A GMS / Maxwell-slip base fit whose error stays 1.3-5x above the floor the data allow sits in a
  // local minimum of the shape search (or the element table bent to one): it is fitted again from
  // the next design points of other basins, and kept when its shape explains more.
  // Both fits are judged by the grid cost at their shape with the additive effects (offset, drift,
  // a force along the stroke, inertia) solved alongside: an effect the data holds makes any base
  // fit miss the floor, and a shape that only mimics it is no better.
  if (has_linear_elements(base.model) && !cur.u.empty()) {
    const double p0 = grid_cost_at(with_additive_probes(cur.spec), train, c, cur.u);
    // Far above the floor (5x) the misfit is an effect the probes lack, not the shape: the loop
    // deals with it, and a retry would only cost time (EMPS: 6 s for nothing).
    if (p0 > 1.3 * rep.noise.floor() && p0 < 5.0 * rep.noise.floor()) {
      FitOptions ro = o.base;
      ro.first_start = std::clamp(ro.starts, 1, 3);
      ro.stage = "base fit, retry from other starts";
      FitResult again = fit_base(base, train, val, c, ro);
      rep.base_retried = true;
      if (!again.u.empty() && grid_cost_at(with_additive_probes(again.spec), train, c, again.u) < 0.98 * p0) {
        cur = std::move(again);
        rep.elements = cur.spec.elements;
        add_shares();
      }
    }
  }
  // Softer elements than the swing estimate allows. The swing after a reversal is estimated by its
  // median travel; a soft element the motion rarely breaks loose (a slow attraction, a long
  // presliding) lies beyond the grid. Tested with the effects found in the model: when the
  // grid's cost at the final shape drops by 2 % with the range 1.5 decades wider (at most half
  // the stroke), also with the additive effects a soft element could stand in for (offset, drift,
  // a force along the stroke, inertia) solved alongside, the element table is chosen again on the
  // wider grid; kept when it lowers both the training and the validation RMS. Tested on the base fit
  // too, before the rounds: a missing soft element is otherwise taken up by the effects (a negative
  // mass, a time shift, a force along the stroke) and a model with friction-scaling effects is not
  // tested again at the end.
  double cur_val = rms_on(cur, val, c);
  auto widen_element_range = [&](bool before_rounds) {
    if (!has_linear_elements(base.model) || cur.u.empty()) return;
    const bool g_columns = std::any_of(cur.spec.effects.begin(), cur.spec.effects.end(), multiplies_friction);
    EffectContext wide = c;
    wide.x_hi_factor = std::min(c.x_hi_factor * std::pow(10.0, 1.5), c.x_half / std::max(c.x_ba, 1e-12));
    if (!g_columns && wide.x_hi_factor > 1.5 * c.x_hi_factor) {
      const FitSpec probe = additive_probes_for(cur, train, c);
      const double c0 = grid_cost_at(probe, train, c, cur.u), c1 = grid_cost_at(probe, train, wide, cur.u);
      if (c1 < 0.98 * c0) {
        FitOptions wo = o.base;
        wo.stage = "element table on a wider range";
        FitResult again = regrid_elements(cur.spec, train, wide, wo, cur.u);
        const double again_val = rms_on(again, val, wide);
        // Before the rounds a soft element competes with the effects it can mimic (an offset
        // within a stroke, a force along it): when the effect that screens best at the current
        // shape, refitted, predicts the validation record as well (within 3 %), the loop decides.
        const bool better = again.rms_train < cur.rms_train && again_val < cur_val;
        bool effect_alike = false;
        if (before_rounds && better) {
          std::optional<Candidate> top;
          for (Effect e : o.candidates)
            if (e != Effect::TimeShift && e != Effect::SensorFilter && e != Effect::Backlash &&
                e != Effect::DwellStiction && effect_applicable(e, train, c)) {
              Candidate k = screen(e, cur, train, val, c, &cur.u);
              if (!top || k.screen_rms_validation < top->screen_rms_validation) top = std::move(k);
            }
          if (top) {
            FitOptions fo = o.refit;
            fo.stage = "element range or " + std::string(effect_name(top->effect)) + "?";
            const FitResult f = fit_model(with(cur.spec, top->effect), train, c, fo, &cur.u);
            effect_alike = rms_on(f, val, c) <= 1.03 * again_val;
          }
        }
        if (better && !effect_alike) {
          rep.notes.push_back("the element range was widened to " + std::to_string(1e6 * wide.x_hi_factor * wide.x_ba) +
                              " um (softer elements than the swing after most reversals shows): validation RMS " +
                              std::to_string(cur_val) + " -> " + std::to_string(again_val) + " N");
          cur = std::move(again), cur_val = again_val, c = wide, rep.range_widened = true;
          rep.elements = cur.spec.elements;
          if (!rep.stages.empty()) rep.stages.back() = cur;
          if (!rep.rounds.empty()) rep.rounds.back().rms_train_after = cur.rms_train, rep.rounds.back().rms_validation_after = cur_val;
        }
      }
    }
  };
  widen_element_range(true);
  if (rep.range_widened) add_shares();
  const double floor = rep.noise.floor();
  rep.stages.push_back(cur);
  rep.rms_before_train = cur.rms_train;
  rep.rms_before_validation = cur_val;
  const double n_val = static_cast<double>(std::max<std::size_t>(1, val.used()));
  std::set<Effect> deep_done;  // channel effects whose scalar was searched with shape refits
  for (int round = 1; round <= o.max_rounds; ++round) {
    Round rd;
    rd.rms_train_before = cur.rms_train;
    rd.rms_validation_before = cur_val;
    const auto r = residual(cur, train, c);
    const auto g = unit_friction(cur, train, c);
    // The ripple search on all samples: the shortest wavelength it can resolve is 3 position steps.
    const RippleSearch rs = every > 1 ? ripple_search(full, c, residual(cur, full, c), unit_friction(cur, full, c))
                                      : ripple_search(train, c, r, g);
    if (round == 1) rep.ripples = rs;
    if (!contains(cur.spec.effects, Effect::PositionPeriodic)) {
      c.wavelengths.clear();
      for (const auto& p : rs.peaks) c.wavelengths.push_back(p.wavelength);
      if (c.wavelengths.size() > 3) c.wavelengths.resize(3);
    }
    if (!contains(cur.spec.effects, Effect::DwellStiction) &&
        effect_applicable(Effect::DwellStiction, train, c))
      choose_dwell_length(cur, train, c);
    for (const auto& t : cur.terms)  // the viscous share the channel effects carry along
      if (t.effect == "base" && t.name == "sigma2" && !cur.theta.empty() && cur.theta[0] > 0)
        c.viscous_ratio = t.value / cur.theta[0];
    auto shapes = tune_measurement_effects(cur, train, c, o.candidates, false, o.refit);
    auto shape_of = [&](Effect e) { const auto it = shapes.find(e); return it == shapes.end() ? &cur.u : &it->second; };
    std::size_t screened = 0;
    double best_val = cur_val;
    for (Effect e : o.candidates) {
      if (contains(cur.spec.effects, e) || !effect_applicable(e, train, c)) continue;
      if (o.base.cancel && o.base.cancel->load()) throw Cancelled();
      Candidate k = screen(e, cur, train, val, c, shape_of(e));
      k.evidence = effect_evidence(e, train, c, r, g, rs);
      best_val = std::min(best_val, k.screen_rms_validation);
      rd.candidates.push_back(std::move(k));
      ++screened;
    }
    // No screened effect brings the validation error near the noise: the channel effects, which
    // the current shape partly mimics, get shape refits in their scalar search and are screened
    // again at their own shapes.
    if (floor > 0 && best_val > 1.15 * floor) {
      shapes = tune_measurement_effects(cur, train, c, o.candidates, true, o.refit, &deep_done);
      for (auto& k : rd.candidates)
        if (shapes.count(k.effect)) {
          Candidate k2 = screen(k.effect, cur, train, val, c, shape_of(k.effect));
          k2.evidence = effect_evidence(k.effect, train, c, r, g, rs);
          k = std::move(k2);
        }
    }
    // Most promising first: the lowest validation RMS of the screening fit (held-out data decides
    // between effects that look alike on the training record, e.g. offset and a level asymmetry).
    std::stable_sort(rd.candidates.begin(), rd.candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.screen_rms_validation < b.screen_rms_validation;
    });
    int tries = 0;
    bool control_done = false;
    std::optional<std::pair<FitResult, Attempt>> best;
    // Fits ahead, for wall time only: the round's first candidate the filters below let through,
    // the control refit when that candidate's screening already passes the gain, and the next
    // candidate when it screens within 1.5x of the first, each started at once on its own threads.
    // A fit is a pure function of its inputs (taken by value here), so the numbers and decisions
    // are those of fitting when needed; a fit started for nothing costs time, not results. All
    // fits of the round share one progress lock.
    const FitOptions refit_o = serialised_progress(o.refit);
    std::map<Effect, std::future<FitResult>> ahead;
    std::optional<std::future<FitResult>> ahead_control;
    auto fit_ahead = [&](FitSpec spec, std::vector<double> warm, std::string stage) {
      FitOptions fo = refit_o;
      fo.stage = std::move(stage);
      return std::async(std::launch::async, [&train, spec = std::move(spec), warm = std::move(warm), fo = std::move(fo), cc = c] {
        return fit_model(spec, train, cc, fo, &warm);
      });
    };
    const std::string round_stage = "round " + std::to_string(round) + ": ";
    // Worth a refit at all: explains something of the training residual and hints at a lower
    // validation RMS.
    auto worth_a_refit = [&](const Candidate& k) {
      return k.explained >= o.min_explained && k.screen_rms_validation < cur_val;
    };
    {
      std::vector<const Candidate*> next;
      for (const auto& k : rd.candidates) {
        if (next.size() == 2) break;
        if (!worth_a_refit(k)) continue;
        if (!next.empty() && k.screen_rms_validation > 1.5 * next.front()->screen_rms_validation) break;
        next.push_back(&k);
      }
      for (const Candidate* k : next)
        ahead.emplace(k->effect, fit_ahead(with(cur.spec, k->effect), *shape_of(k->effect),
                                           round_stage + "refit with " + std::string(effect_name(k->effect))));
      if (!next.empty() && next.front()->screen_rms_validation <= (1.0 - o.min_gain) * cur_val)
        ahead_control = fit_ahead(cur.spec, cur.u, round_stage + "control refit without a new effect");
    }
    // Whether the current model lags along the sampled path: a refit with inertia whose mass comes
    // out negative (-M a is what a model half a step late leaves). Its validation RMS, once per
    // round (from the round's inertia attempt when there is one).
    bool lag_done = false;
    std::optional<double> lag_val;
    auto lagging_model_fit = [&]() -> std::optional<double> {
      if (lag_done) return lag_val;
      lag_done = true;
      if (contains(cur.spec.effects, Effect::Inertia)) return lag_val;
      auto negative = [](const std::vector<LinearTerm>& ts) {
        return std::any_of(ts.begin(), ts.end(), [](const LinearTerm& t) { return t.name == "M" && t.value < 0; });
      };
      for (const auto& x : rd.attempts)
        if (x.effect == Effect::Inertia) {
          if (negative(x.terms)) lag_val = x.rms_validation;
          return lag_val;
        }
      FitOptions fo = refit_o;
      fo.stage = round_stage + "inertia refit (does the model lag along the sampled path?)";
      const FitResult f = fit_model(with(cur.spec, Effect::Inertia), train, c, fo, &cur.u);
      if (negative(terms_of(f, Effect::Inertia))) lag_val = rms_on(f, val, c);
      return lag_val;
    };
    // Refits one candidate with its effect and judges it; returns false when a guard said the
    // effect cannot be what the refit found (too small, a negative mass, within the sampling):
    // such an attempt does not use up one of the round's tries.
    auto attempt = [&](const Candidate& k) -> bool {
      FitOptions fo = refit_o;
      fo.stage = round_stage + "refit with " + std::string(effect_name(k.effect));
      const auto started = ahead.find(k.effect);
      FitResult f = started != ahead.end() ? started->second.get()
                                           : fit_model(with(cur.spec, k.effect), train, c, fo, shape_of(k.effect));
      Attempt a;
      a.effect = k.effect, a.rms_train = f.rms_train, a.rms_validation = rms_on(f, val, c);
      a.terms = terms_of(f, k.effect);
      a.size = contribution_rms(f, k.effect, train, c);
      a.kept = a.rms_validation <= (1.0 - o.min_gain) * cur_val;
      if (a.kept && !control_done) {
        // Control: the current model refitted with the same budget and starts. What it gains
        // is optimisation, not the effect; the effect must beat it by the same margin.
        control_done = true;
        FitOptions co = fo;
        co.stage = round_stage + "control refit without a new effect";
        FitResult ctrl = ahead_control ? ahead_control->get() : fit_model(cur.spec, train, c, co, &cur.u);
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
      // BIC on the validation record: n ln(SSR / n) + p ln n with the effect's columns.
      a.bic_change = n_val * std::log(std::pow(a.rms_validation / std::max(cur_val, 1e-300), 2)) +
                     static_cast<double>(k.columns) * std::log(n_val);
      // The floor is an estimate; a model that predicts the held-out record better than it shows
      // it lower (e.g. a sampling share taken from a base fit that bent to the missing effect).
      const double fl = std::min(floor, a.rms_validation);
      const bool big = fl <= 0 || a.size >= o.min_size * fl;
      bool guarded = false;  // refused because the effect cannot be what the refit found
      const bool signature = k.p_value * static_cast<double>(screened) <= o.max_p;
      if (!a.kept) a.verdict = "validation RMS not lowered by " + std::to_string(o.min_gain * 100).substr(0, 4) + " %";
      else if (!signature) a.kept = false, a.verdict = "no signature in the training residual (F-test)";
      else if (a.bic_change >= 0) a.kept = false, a.verdict = "validation BIC not lowered";
      else if (!big) a.kept = false, guarded = true, a.verdict = "contribution below " + std::to_string(o.min_size).substr(0, 4) + " x the noise floor";
      else if (fl > 0 && a.size < o.sure_size * fl) {
        // A small contribution must explain a good share of what lies above the floor.
        const double e0 = cur_val * cur_val - fl * fl, e1 = a.rms_validation * a.rms_validation - fl * fl;
        if (!(e0 > 0) || (e0 - e1) / e0 < o.min_excess)
          a.kept = false, guarded = true, a.verdict = "small (below " + std::to_string(o.sure_size).substr(0, 3) +
                                      " x the floor) and explains less than " + std::to_string(o.min_excess).substr(0, 4) +
                                      " of the validation error above the floor";
      }
      if (a.kept && k.effect == Effect::Inertia) {
        // A mass is positive. A negative one is the model lagging along the sampled path (a
        // force that leads the modelled one by a fraction of a step looks like -M a), not inertia.
        for (const auto& t : a.terms)
          if (t.name == "M" && !(t.value > 0))
            a.kept = false, guarded = true, a.verdict = "negative mass M = " + std::to_string(t.value) +
                                        " kg: not an inertia (the model lags along the sampled path)";
      }
      if (a.kept && (k.effect == Effect::Inertia || k.effect == Effect::TimeShift || k.effect == Effect::SensorFilter) &&
          a.size < 1.5 * rep.noise.sampling) {
        // Lag-like effects (a force leading or lagging the motion) are what the unmeasured path
        // between samples also changes: below 1.5 x that share of the floor they cannot be told
        // from it, and the loop says so instead of naming one.
        a.kept = false, guarded = true;
        a.verdict = "contribution " + std::to_string(a.size) + " N is within 1.5 x what the path between samples "
                    "changes (" + std::to_string(rep.noise.sampling) + " N): cannot be told from the sampling";
      }
      if (a.kept && (k.effect == Effect::TimeShift || k.effect == Effect::SensorFilter)) {
        // A lagging force channel or filter, and the model lagging along the sampled path (which a
        // negative mass fits), change the force alike: when the latter fits the validation record
        // as well (within 2 %), the data cannot say the channel lags.
        if (const auto lv = lagging_model_fit(); lv && *lv <= 1.02 * a.rms_validation) {
          a.kept = false, guarded = true;
          a.verdict = "fits the validation record no better than a negative mass (" + std::to_string(*lv) +
                      " N): the model lagging along the sampled path, not the channel: cannot be told from the sampling";
        }
      }
      if (a.kept) a.verdict = "kept: signature p " + std::to_string(k.p_value) + ", validation and BIC lowered";
      rd.attempts.push_back(a);
      if (a.kept && (!best || a.rms_validation < best->second.rms_validation)) {
        best.emplace(std::move(f), a);
      }
      return !guarded;
    };
    auto attempted = [&](Effect e) {
      return std::any_of(rd.attempts.begin(), rd.attempts.end(), [e](const Attempt& a) { return a.effect == e; });
    };
    const int max_attempts = 2 * o.tries_per_round;
    for (const auto& k : rd.candidates) {
      if (tries >= o.tries_per_round || static_cast<int>(rd.attempts.size()) >= max_attempts) break;
      if (!worth_a_refit(k)) continue;
      // Far behind an effect already kept: a refit lowers the screening RMS, but not by half.
      if (best && k.screen_rms_validation > 1.5 * best->second.rms_validation) continue;
      // A close second is tried too once one is kept; otherwise the first kept ends the round.
      if (attempt(k)) ++tries;
    }
    // Nothing kept while the model stays well above the floor: the current shape may have bent
    // to the missing effect, so that its screening at that shape shows no validation gain (a
    // quadratic drag taken up by the Stribeck curve, a level asymmetry by the elements). The
    // candidates that explain most of the *training* residual get a refit too (shape included).
    if (!best && floor > 0 && cur_val > o.refit_above_floor * floor) {
      std::vector<const Candidate*> by_train;
      for (const auto& k : rd.candidates)
        if (!attempted(k.effect) && k.explained >= o.min_explained &&
            k.p_value * static_cast<double>(screened) <= o.max_p && k.screen_rms_train < rd.rms_train_before)
          by_train.push_back(&k);
      std::stable_sort(by_train.begin(), by_train.end(), [](const Candidate* a, const Candidate* b) {
        return a->screen_rms_train < b->screen_rms_train;
      });
      int more = 0;
      for (const Candidate* k : by_train) {
        if (more >= o.train_tries || static_cast<int>(rd.attempts.size()) >= max_attempts + o.train_tries) break;
        if (attempt(*k)) ++more;
      }
    }
    if (best) {
      auto& [f, a] = *best;
      for (auto& x : rd.attempts) x.kept = x.effect == a.effect && x.kept;
      for (auto& x : rd.attempts)
        if (!x.kept && x.verdict.rfind("kept", 0) == 0) x.verdict = "passed, but " + std::string(effect_name(a.effect)) + " explains more";
      FitOptions po = o.refit;  // polish the kept model before the next round screens against it
      po.starts = 1;
      po.data_start = false;
      po.stage = "round " + std::to_string(round) + ": polish";
      FitResult p = fit_model(f.spec, train, c, po, &f.u);
      if (p.rms_train < f.rms_train) {
        f = std::move(p);
        for (auto& x : rd.attempts)
          if (x.effect == a.effect) {
            x.rms_train = f.rms_train;
            x.rms_validation = rms_on(f, val, c);
            x.terms = terms_of(f, a.effect);
            a = x;
          }
      }
      cur = f;
      cur_val = a.rms_validation;
      rd.added = a.effect;
      rep.stages.push_back(cur);
      rep.effects_added.push_back(a.effect);
      // Effects that fit the data alike: said, not hidden.
      for (const auto& x : rd.attempts)
        if (x.effect != a.effect && x.rms_validation <= a.rms_validation * 1.005 && x.verdict.rfind("passed", 0) == 0)
          rep.notes.push_back("round " + std::to_string(round) + ": " + std::string(effect_name(a.effect)) +
                              " and " + std::string(effect_name(x.effect)) +
                              " fit the validation record alike (within 0.5 %); the data cannot tell them apart");
    }
    rd.rms_train_after = cur.rms_train;
    rd.rms_validation_after = cur_val;
    const bool added = rd.added.has_value();
    rep.rounds.push_back(std::move(rd));
    if (!added) break;
  }
  if (every > 1) {
    // Screened on every k-th sample: the element range tested there, then the final model refitted
    // on all samples from its screened shape (and the first stage's training RMS taken on all).
    if (!rep.range_widened) widen_element_range(false);
    rep.rms_before_train = rms_on(rep.stages.front(), full, c);
    cur.rms_train = rms_on(cur, full, c);
    rep.stages.back().rms_train = cur.rms_train;
  }
  if (!rep.effects_added.empty() || every > 1) {
    // A last refit of the final model from its shape and from the data-based guess (the control
    // refit of a round, for the model the loop ends with): what it gains is optimisation.
    FitOptions fo = o.refit;
    fo.stage = "final refit";
    // After screening: one local search from the screened shape on all samples (the shape is
    // found; more samples move it a little).
    fo.polish_only = every > 1;
    if (every > 1) fo.rel_tol = 1e-5;
    FitResult f = fit_model(cur.spec, full, c, fo, &cur.u);
    if (f.rms_train < cur.rms_train) {
      cur = std::move(f);
      cur_val = rms_on(cur, val, c);
      rep.stages.back() = cur;
      if (!rep.rounds.empty()) rep.rounds.back().rms_train_after = cur.rms_train, rep.rounds.back().rms_validation_after = cur_val;
    }
  }
  if (every == 1 && !rep.range_widened) widen_element_range(false);
  {
    // The floor the credit is judged against: noise, and the quantisation and sampling shares
    // through the final model (a base fit far from the data overstates the sampling share).
    NoiseEstimate at_final = noise_data;
    const auto f = friction_force(cur, full);
    add_quantisation(at_final, full, c, f);
    add_sampling(at_final, full, f, friction_force(cur, full, true));
    credit_by_ablation(rep, cur, cur_val, train, full, val, c, at_final.floor(), every, o);
  }
  rep.context = c;
  rep.rms_after_train = cur.rms_train;
  rep.rms_after_validation = cur_val;
  rep.parameters = parameter_estimates(cur, full, c);
  rep.optimum = check_optimum(cur, full, c);
  if (!rep.optimum.verified)
    for (auto& p : rep.parameters) p.std_error = std::numeric_limits<double>::quiet_NaN();
  {
    const auto rv = residual(cur, val, c);
    const auto gv = unit_friction(cur, val, c);
    NoiseEstimate nv = noise_level(val, c);
    if (nv.sigma <= 0 || (!nv.from_rests && rep.noise.from_rests)) nv = rep.noise;
    const auto f = friction_force(cur, val);
    add_quantisation(nv, val, c, f);
    add_sampling(nv, val, f, friction_force(cur, val, true));
    rep.remaining = residual_structure(val, c, rv, gv, nv);
  }
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

nlohmann::json to_json(const Ablation& a, const std::vector<Effect>& named) {
  nlohmann::json j;
  j["ran"] = a.ran;
  j["test"] = "refit from the final shape with the refit budget, without each effect; credited when the "
              "validation MSE difference over time blocks has z >= " + fmt(a.z_crit) +
              ", the contribution is at least half the floor and the model without it is above 1.15x the floor";
  j["validation_rms_all_N"] = a.rms_validation_all;
  j["floor_N"] = a.floor;
  j["named"] = named_effects(a, named);
  auto row = [](const AblationRow& r) {
    nlohmann::json alike = nlohmann::json::array();
    for (Effect e : r.alike) alike.push_back(std::string(effect_name(e)));
    return nlohmann::json{{"effect", std::string(effect_name(r.effect))},
                          {"validation_rms_without_N", r.rms_validation_without},
                          {"mse_difference_N2", r.test.mse_difference},
                          {"std_error_N2", r.test.std_error},
                          {"z", std::isfinite(r.test.z) ? nlohmann::json(r.test.z) : nlohmann::json("inf")},
                          {"blocks", r.test.blocks},
                          {"contribution_N", r.contribution},
                          {"credited", r.credited},
                          {"alike", alike},
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
      cands.push_back({{"effect", std::string(effect_name(k.effect))},
                       {"explained_fraction", k.explained},
                       {"signature_p_value", k.p_value},
                       {"screen_rms", rms_json(k.screen_rms_train, k.screen_rms_validation)},
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
  j["base_retried"] = r.base_retried;
  j["element_range_widened"] = r.range_widened;
  j["ripple_search"] = to_json(r.ripples);
  nlohmann::json pars = nlohmann::json::array();
  for (const auto& p : r.parameters)
    pars.push_back({{"effect", p.effect}, {"name", p.name}, {"unit", p.unit}, {"value", p.value},
                    {"std_error", std::isfinite(p.std_error) ? nlohmann::json(p.std_error) : nlohmann::json()}});
  j["parameters"] = pars;
  j["converged"] = {{"verified_minimum", r.optimum.verified}, {"reason", r.optimum.reason}};
  j["remaining_structure"] = to_json(r.remaining);
  j["notes"] = r.notes;
  j["ablation"] = to_json(r.ablation, r.effects_added);
  j["base_fit"] = fit_json(r.stages.front());
  j["final_model"] = fit_json(r.final_fit());
  const auto& c = r.context;
  j["context"] = {{"x_mid_m", c.x_mid},         {"x_half_m", c.x_half},
                  {"t_mid_s", c.t_mid},         {"t_half_s", c.t_half},
                  {"v_ref_mps", c.v_ref},       {"x_breakaway_m", c.x_ba},
                  {"force_level_N", c.f_level}, {"ripple_wavelengths_m", c.wavelengths},
                  {"time_shift_s", c.time_shift}, {"filter_time_constant_s", c.filter_T},
                  {"backlash_m", c.backlash}, {"sample_step_s", c.h_med},
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
