#include "core/ident/loop_stages.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/ident/ablation.hpp"
#include "core/ident/element_fit.hpp"
#include "core/ident/parallel.hpp"

namespace gmslab::ident::detail {

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

// Whether one of e's columns multiplies the friction (needs g, the unit model output).
bool multiplies_friction(Effect e) {
  const auto cols = effect_columns(e);
  return std::any_of(cols.begin(), cols.end(), [](const Column& col) { return col.uses_g; });
}

// spec with the additive effects a shape or a soft element could stand in for (offset, inertia,
// time drift, a force along the stroke; those whose columns do not depend on the friction) added
// as linear columns: probes for comparing shapes and element ranges fairly.
// The element-range test solves the inertia probe only where the fit's residual holds a positive
// mass: a model lagging along the sampled path leaves -M a in its residual, and a probe column
// that takes it up hides what a soft element explains. The base-fit retry keeps the inertia
// probe (docs/identification.md, the base study).
FitSpec with_additive_probes(FitSpec spec, bool inertia) {
  for (Effect e : {Effect::Offset, Effect::Inertia, Effect::TimeDrift, Effect::PositionDependent})
    if (!multiplies_friction(e) && !contains(spec.effects, e) && (inertia || e != Effect::Inertia))
      spec.effects.push_back(e);
  return spec;
}

namespace {

// Whether f's training residual correlates positively with the acceleration (sign of the least
// squares mass M = sum r a / sum a^2).
bool residual_mass_positive(const FitResult& f, const Dataset& d, const EffectContext& c) {
  const auto r = residual(f, d, c);
  double ra = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) ra += r[k] * d.a[k];
  return ra > 0;
}

}  // namespace

FitSpec additive_probes_for(const FitResult& f, const Dataset& d, const EffectContext& c) {
  return with_additive_probes(f.spec, residual_mass_positive(f, d, c));
}

namespace {

// Columns of an effect at the shape of f (the effect's unit outputs along d, fit.hpp).
std::vector<std::vector<double>> effect_matrix(Effect e, const Dataset& d, const EffectContext& c,
                                               const FitResult& f) {
  const std::vector<double> g2 = unit_outputs(f, FitSpec{f.spec.model, f.spec.elements, {e}}, d, c);
  std::vector<std::vector<double>> out;
  const std::vector<ExtraOutput> extras = extra_outputs({e});
  std::vector<double> scratch;
  for (const auto& col : effect_columns(e)) {
    std::vector<double> o(d.size(), 0.0);
    col.fill(d, c, column_input(col, g2, d.size(), extras, scratch), o);
    out.push_back(std::move(o));
  }
  return out;
}
// Standard errors of the final model's linear terms (and the effects' scalars) from the
// linearised least squares at the fitted shape.
std::vector<ParameterEstimate> parameter_estimates(const FitResult& f, const Dataset& d,
                                                   const EffectContext& c, const PathRule& rule,
                                                   double quantum) {
  const auto g = unit_friction(f, d, c);
  std::vector<std::vector<double>> cols;
  std::vector<ParameterEstimate> out;
  for (const auto& t : f.terms)
    if (t.effect == "base") {
      cols.push_back(t.name == "Fc" ? g : d.v);
      out.push_back({t.effect, t.name, t.unit, t.value, 0, 0, ""});
    }
  for (Effect e : f.spec.effects) {
    auto m = effect_matrix(e, d, c, f);
    const auto ts = terms_of(f, e);
    for (std::size_t j = 0; j < m.size() && j < ts.size(); ++j) {
      cols.push_back(std::move(m[j]));
      out.push_back({ts[j].effect, ts[j].name, ts[j].unit, ts[j].value, 0, 0, ""});
    }
  }
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
      const auto m = effect_matrix(s.e, d, cc, f);
      for (std::size_t j = 0; j < m.size() && j < ts.size(); ++j)
        for (std::size_t k = 0; k < d.size(); ++k) der[k] += sign * ts[j].value * m[j][k] / (2 * step);
    }
    cols.push_back(std::move(der));
    out.push_back({std::string(effect_name(s.e)), s.name, s.unit, s.value, 0, 0, ""});
  }
  // The shape (the nonlinear parameters, in the unit box): nuisance columns, so that the errors
  // of the terms above carry their correlation with it (Gauss-Newton covariance of all).
  for (std::size_t i = 0; i < f.u.size(); ++i) {
    const double step = 1e-4;
    FitResult hi = f, lo = f;
    hi.u[i] = std::min(1.0, f.u[i] + step), lo.u[i] = std::max(0.0, f.u[i] - step);
    if (!(hi.u[i] > lo.u[i])) continue;
    const auto ph = predict(hi, d, c), pl = predict(lo, d, c);
    std::vector<double> der(d.size());
    for (std::size_t k = 0; k < d.size(); ++k) der[k] = (ph[k] - pl[k]) / (hi.u[i] - lo.u[i]);
    cols.push_back(std::move(der));
    out.push_back({"shape", "u" + std::to_string(i), "-", f.u[i], 0, 0, ""});
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
  // The residual is not white: what the sampled path and the encoder leave runs over many samples.
  // The covariance is the cluster-robust (sandwich) one over kBlocks contiguous blocks,
  // Ginv (sum_b g_b g_b^T) Ginv with g_b the scaled columns times the residual over block b,
  // and never below the white-noise one (s2 Ginv).
  const auto pr = predict(f, d, c);
  const Eigen::MatrixXd As = Al * sc_.asDiagonal();
  constexpr std::size_t kBlocks = 20;
  const std::size_t nb = std::min<std::size_t>(kBlocks, rows.size());
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(As.cols(), As.cols());
  for (std::size_t b = 0; b < nb; ++b) {
    Eigen::VectorXd gb = Eigen::VectorXd::Zero(As.cols());
    for (std::size_t i = b * rows.size() / nb; i < (b + 1) * rows.size() / nb; ++i)
      gb += As.row(static_cast<Eigen::Index>(i)).transpose() * (d.F[rows[i]] - pr[rows[i]]);
    meat += gb * gb.transpose();
  }
  const double dof = nb > 1 ? static_cast<double>(nb) / static_cast<double>(nb - 1) : 1.0;
  const Eigen::MatrixXd robust = dof * Ginv * meat * Ginv;
  // The path between samples is not measured. Where the model runs along the cubic through the
  // samples, the same fit along straight steps predicts differently (the sampling share of the
  // floor); that difference is systematic (at reversals, where |a| peaks in a sine, it reads as
  // inertia) and no count of samples averages it out. Its image in the parameters, the
  // least-squares shift it would cause, over sqrt(3) (the true path anywhere between the two,
  // as in the sampling share of the floor, structure.hpp), is added in quadrature as the path
  // share.
  // The least-squares shift of the (scaled) parameters that the model along another path of the
  // record, predicting `other`, would cause.
  auto image = [&](const std::vector<double>& other) {
    Eigen::VectorXd diff(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i)
      diff(static_cast<Eigen::Index>(i)) = other[rows[i]] - pr[rows[i]];
    return Eigen::VectorXd(Ginv * (As.transpose() * diff));
  };
  const Eigen::VectorXd shift = d.sub.empty() ? Eigen::VectorXd::Zero(As.cols())
                                              : image(predict(f, with_straight_steps(d), c));
  // The encoder rounds the position to its step q: where the slide was within the count is not
  // recorded, and where the elements are stiff (k q comparable with the noise) the model along the
  // recorded staircase differs systematically from the model along the slide's smooth motion.
  // The image of that difference in the parameters (the model along the smoothest positions the
  // encoder allows against the model along the recorded ones) is added in quadrature as the
  // encoder share.
  const Eigen::VectorXd enc = quantum > 0
                                  ? image(predict(f, within_encoder_step(d, quantum, rule), c))
                                  : Eigen::VectorXd::Zero(As.cols());
  for (std::size_t j = 0; j < live.size(); ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    const double var = std::max(s2 * Ginv(jj, jj), robust(jj, jj));
    auto& e = out[static_cast<std::size_t>(live[j])];
    e.path_error = std::abs(shift(jj)) * sc_(jj) / std::sqrt(3.0);
    e.encoder_error = std::abs(enc(jj)) * sc_(jj);
    e.std_error = std::sqrt(std::max(0.0, var) * sc_(jj) * sc_(jj) + e.path_error * e.path_error +
                            e.encoder_error * e.encoder_error);
  }
  // Leave out the unused ripple slots.
  std::vector<ParameterEstimate> kept;
  for (std::size_t j = 0; j < out.size(); ++j)
    if ((A.col(static_cast<Eigen::Index>(j)).squaredNorm() > 0 || out[j].effect == "base") && out[j].effect != "shape")
      kept.push_back(out[j]);
  return kept;
}

// Whether the final shape is a minimum of the training RMS: every coordinate of the unit box
// stepped by +-1e-3 (inside the box) with the linear terms re-solved must not lower the RMS by
// more than 1e-5 relative (gradient test), the second difference along each must not be
// negative (curvature test), and a coordinate within 5 % of the box from an end must not do
// better at the end itself (a search stopped short of a bound it presses on). Standard errors
// mean something only there.
OptimumCheck check_optimum(const FitResult& f, const Dataset& d, const EffectContext& c) {
  constexpr double kNearEnd = 0.05;  // of the unit box: where the end itself is tried
  OptimumCheck out;
  if (f.time_limited) {
    out.verified = false;
    out.reason = "the fit was stopped by its time limit";
    return out;
  }
  const Parameterization par(model_info(f.spec.model), f.spec.elements, c);
  if (f.u.size() != par.size()) return out;
  const double h = 1e-3;
  // Every point the test costs (the fit, a step each way per coordinate, an end within kNearEnd),
  // costed at once on two threads (each a pure function of its point), then judged in order.
  const std::size_t n = f.u.size();
  std::vector<std::vector<double>> pts{f.u};
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::array<std::size_t, 2>> step_at(n, {kNone, kNone}), end_at(n, {kNone, kNone});
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 2; ++k) {
      std::vector<double> u = f.u;
      u[i] += k == 0 ? h : -h;
      if (u[i] < 0.0 || u[i] > 1.0) continue;
      step_at[i][k] = pts.size();
      pts.push_back(std::move(u));
    }
    for (int k = 0; k < 2; ++k) {
      const double end = k == 0 ? 1.0 : 0.0, gap = std::abs(end - f.u[i]);
      if (!(gap > h && gap <= kNearEnd)) continue;
      std::vector<double> u = f.u;
      u[i] = end;
      end_at[i][k] = pts.size();
      pts.push_back(std::move(u));
    }
  }
  std::vector<double> cost(pts.size());
  std::unique_ptr<LinearRefit> on[2];
  run_tasks(pts.size(), [&](std::size_t t, int w) {
    if (!on[w]) on[w] = std::make_unique<LinearRefit>(f.spec, d, c);
    cost[t] = on[w]->rms(pts[t]);
  });
  const double c0 = cost[0];
  double worst = 0;
  std::string pinned;
  for (std::size_t i = 0; i < n; ++i) {
    double side[2] = {c0, c0};
    for (int k = 0; k < 2; ++k)
      if (step_at[i][k] != kNone) side[k] = cost[step_at[i][k]];
    const double drop = (c0 - std::min(side[0], side[1])) / std::max(c0, 1e-300);
    const bool curved_down = side[0] + side[1] - 2 * c0 < -1e-9 * c0;
    if ((drop > 1e-5 || curved_down) && drop >= worst) {
      worst = drop;
      out.verified = false;
      out.reason = "a step of 1e-3 of its range in " + par.params()[i].name + " lowers the training RMS by " +
                   fmt(100 * drop) + " %: not at a minimum";
    }
    // A search can stop short of an end it presses on where the cost is flat along the parameter
    // at the scale of these steps (a break-away ratio beyond the range stopped 4 % short of its
    // top, and steps of 1e-3 saw no descent). Within kNearEnd of the box from an end, the end
    // itself is tried too: a lower RMS there is no minimum within the range.
    for (int k = 0; k < 2; ++k) {
      if (end_at[i][k] == kNone) continue;
      const double end = k == 0 ? 1.0 : 0.0;
      const double at_end = cost[end_at[i][k]];
      const double fall = (c0 - at_end) / std::max(c0, 1e-300);
      if (fall > 1e-5 && fall >= worst) {
        const ShapeParam& sp = par.params()[i];
        worst = fall;
        out.verified = false;
        out.reason = sp.name + " stopped at " + fmt(par.value(i, f.u[i])) + ", short of the " +
                     (end > 0.5 ? "upper" : "lower") + " end of its search range [" + fmt(sp.lo) +
                     ", " + fmt(sp.hi) + "] (" + sp.unit + "), where the training RMS is " +
                     fmt(100 * fall) + " % lower: not at a minimum within the range";
      }
    }
    // Pinned at an end of its search range: at the upper end, or at the lower end with the cost
    // rising inwards (a lower end where the parameter merely fades to nothing, e.g. a viscous
    // coefficient the data do not need, is not a pin). The data may want a value beyond the end,
    // which the search cannot reach. Said before anything else: it is the cause.
    const bool at_lo = f.u[i] <= h, at_hi = f.u[i] >= 1.0 - h;
    const double rise = side[0] / std::max(c0, 1e-300) - 1.0;
    if (pinned.empty() && (at_hi || (at_lo && rise > 1e-5))) {
      const ShapeParam& sp = par.params()[i];
      pinned = sp.name + " is pinned at the " + (at_hi ? "upper" : "lower") +
               " end of its search range [" + fmt(sp.lo) + ", " + fmt(sp.hi) + "] (" + sp.unit +
               "): the data may want a value beyond it, and the fit is the closest model within "
               "the range";
    }
  }
  if (!pinned.empty()) out.verified = false, out.reason = pinned, out.pinned = true;
  return out;
}

// A model fitted on the screened record, on all samples: one local search from its shape (the shape
// is found; more samples move it a little), kept when it lowers the RMS on all samples; f's
// training RMS is then the one on all samples.
void polish_on_all_samples(FitResult& f, const Dataset& full, const EffectContext& c,
                           const FitOptions& refit, const std::string& stage) {
  FitOptions fo = refit;
  fo.stage = stage;
  fo.polish_only = true;
  fo.rel_tol = 1e-5;
  FitResult p = fit_model(f.spec, full, c, fo, &f.u);
  f.rms_train = rms_on(f, full, c);
  if (p.rms_train < f.rms_train) f = std::move(p);
}

// The named effects are those the ablation credits (ablation.hpp): refits without each, from the
// final shape with the loop's refit budget, on the record the loop decided on; validation by the
// block test. A dropped effect's gain goes to the refit: the model without it is the final one
// (polished on all samples when the loop screened), and the stages and effects are those named.
void credit_by_ablation(IdentReport& rep, FitResult& cur, double& cur_val, const Dataset& train,
                        const Dataset& full, const Dataset& val, const EffectContext& c,
                        double floor, std::size_t every, const LoopOptions& o, bool count_may_grow,
                        const FitResult* from_data) {
  if (cur.spec.effects.empty() && cur.spec.elements < 2) return;
  std::vector<std::pair<Effect, Effect>> alternatives;
  for (const auto& rd : rep.rounds)
    if (rd.added)
      for (const auto& a : rd.attempts)
        if (a.effect != *rd.added && a.verdict.rfind("passed", 0) == 0) alternatives.emplace_back(*rd.added, a.effect);
  AblationOptions ao;
  ao.refit = o.refit;
  ao.refit.stage = "ablation";
  ao.from_data = o.base;
  ao.min_size = o.min_size;
  ao.count_may_grow = count_may_grow;
  AblationResult ab = ablate(cur, train, val, c, floor, alternatives, ao, from_data);
  rep.ablation = ab.table;
  const bool fewer_elements = std::any_of(ab.table.elements.begin(), ab.table.elements.end(),
                                          [](const ElementAblation& e) { return e.dropped; });
  if (ab.table.dropped.empty() && !fewer_elements && !ab.table.count_raised) {
    if (ab.model.rms_train < cur.rms_train && every == 1) cur = ab.model, cur_val = ab.rms_validation;
    rep.stages.back() = cur;
    return;
  }
  FitResult f = std::move(ab.model);
  if (every > 1) polish_on_all_samples(f, full, c, o.refit, "final refit of the credited model");
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

void LoopState::set_last_stage() {
  if (!rep.stages.empty()) rep.stages.back() = cur;
  if (!rep.rounds.empty())
    rep.rounds.back().rms_train_after = cur.rms_train,
    rep.rounds.back().rms_validation_after = cur_val;
}

LoopState::LoopState(const Dataset& train, const Dataset& validation, const FitSpec& base_spec,
                     const LoopOptions& options)
    : train_in(train), val_in(validation), base(base_spec), o(options), c(make_context(train)) {
  rep.noise = noise_level(train_in, c);
}

std::vector<double> LoopState::friction_force(const FitResult& f, const Dataset& d, bool straight) const {
  auto g = straight ? unit_friction(f, with_straight_steps(d), c) : unit_friction(f, d, c);
  const double fc = f.theta.empty() ? 1.0 : f.theta[0];
  for (auto& x : g) x *= fc;
  return g;
}

void LoopState::add_model_shares(NoiseEstimate& e, const FitResult& f, const Dataset& d) const {
  const auto ff = friction_force(f, d);
  add_quantisation(e, d, c, ff);
  add_sampling(e, d, ff, friction_force(f, d, true));
}

FitResult LoopState::fit_base_from_data(const Dataset& d, const Dataset& v) {
  FitResult f = fit_base(base, d, v, c, o.base);
  base_from_data.reset();
  base_from_data_on = nullptr;
  if (base.elements != 0) base_from_data = f, base_from_data_on = &d;
  return f;
}

void LoopState::add_shares() {
  rep.noise = noise_data;
  add_model_shares(rep.noise, cur, full());
  // The credit bound's second sampling estimate (no_effect_creditable).
  add_sampling_halving(
      rep.noise, full(), friction_force(cur, full()),
      friction_force(cur, decimated(full(), 2, rep.fine_path ? kFinePath : PathRule{})));
}

// A long record is screened on every k-th sample (at least screen_samples of them): the base fit
// and every decision of the loop on it, the floor and the final refit on all samples. The
// screened record must drive the friction as the full one does: the base fit's friction along
// both, compared at the kept samples, within a quarter of the noise. Else every k/2-th sample is
// tried (and so on), and the base fit is made again on the record that passes. (Slow motion at a
// steep Stribeck curve: the step velocities of a quantised position at the full rate and at
// every k-th sample give S(v) different means.)
void screen_record(LoopState& s) {
  const Dataset& train_in = s.train_in;
  const std::size_t want = s.o.screen_samples;
  s.every = want > 0 && train_in.size() >= 2 * want ? train_in.size() / want : 1;
  if (s.every > 1) s.screen_rec = decimated(train_in, s.every, PathRule{});
  s.cur = s.fit_base_from_data(s.every > 1 ? s.screen_rec : train_in, s.val_in);
  if (s.every == 1) return;
  const auto ff = s.friction_force(s.cur, train_in);
  auto difference = [&](std::size_t e, const Dataset& sc) {
    const auto fs = s.friction_force(s.cur, sc);
    double s2 = 0, n = 0;
    for (std::size_t k = 0; k < sc.size(); ++k)
      if (sc.use[k]) s2 += (fs[k] - ff[k * e]) * (fs[k] - ff[k * e]), n += 1;
    return n > 0 ? std::sqrt(s2 / n) : 0.0;
  };
  std::size_t e = s.every;
  double diff = difference(e, s.screen_rec);
  const double first_diff = diff;
  const double sigma = s.rep.noise.sigma;
  while (e > 1 && diff > 0.25 * sigma) {
    e /= 2;
    if (e > 1) s.screen_rec = decimated(train_in, e, PathRule{}), diff = difference(e, s.screen_rec);
  }
  if (e == s.every) return;
  s.rep.notes.push_back(
      "every " + ordinal(s.every) + " sample would change the base fit's friction by " +
      fmt(first_diff) + " N RMS (more than a quarter of the noise, " + fmt(0.25 * sigma) + " N): " +
      (e == 1 ? std::string("all samples used") : "screened on every " + ordinal(e) + " sample"));
  s.every = e;
  if (s.every == 1) s.screen_rec = Dataset{};
  s.cur = s.fit_base_from_data(s.every > 1 ? s.screen_rec : train_in, s.val_in);
}

// The path between samples. The adaptive path steps straight where the speed hardly changes;
// with a fast attraction (C h >> 1) the force at a sample follows the speed at that sample, and
// the straight step's mean speed is half a step late. When the base fit's friction along the
// fine path differs from it by more than a quarter of the noise, everything runs on the fine
// path (the base fit too: the element table found on the adaptive path bends to its error).
// Only a fast attraction makes the path within a step matter (a slipping element relaxes at
// C / S(v); at least a tenth of the way within the median step): on slow-relaxing records the
// difference is the base fit's own roughness, and the fine path costs 4x the time for nothing
// (path_difference stays 0: not measured). Then the report's header and the floor's
// quantisation and sampling shares through the base fit.
void choose_path(LoopState& s) {
  IdentReport& rep = s.rep;
  double relax = 1.0;  // relaxation per median step; models without C: only the difference decides
  const ModelInfo& fi = model_info(s.cur.friction.model);
  if (fi.scalar_index("C") >= 0 && fi.scalar_index("Fs") >= 0 && s.cur.friction.scalar("Fs") > 0)
    relax = s.cur.friction.scalar("C") / s.cur.friction.scalar("Fs") * s.c.h_med;
  if (relax >= 0.1) {
    s.train_fine = s.train_in;
    set_path(s.train_fine, kFinePath);
    const auto g0 = unit_friction(s.cur, s.train_in, s.c), g1 = unit_friction(s.cur, s.train_fine, s.c);
    const double fc = s.cur.theta.empty() ? 1.0 : s.cur.theta[0];
    double sum = 0, n = 0;
    for (std::size_t k = 0; k < s.train_in.size(); ++k)
      if (s.train_in.use[k]) sum += std::pow(fc * (g1[k] - g0[k]), 2), n += 1;
    rep.path_difference = n > 0 ? std::sqrt(sum / n) : 0.0;
    rep.fine_path = rep.path_difference > 0.25 * rep.noise.sigma;
    if (rep.fine_path) {
      s.val_fine = s.val_in;
      set_path(s.val_fine, kFinePath);
      if (s.every > 1) s.screen_rec = decimated(s.train_fine, s.every, kFinePath);
      s.cur = s.fit_base_from_data(s.every > 1 ? s.screen_rec : s.train_fine, s.val_fine);
    } else {
      s.train_fine = Dataset{};
    }
  }
  rep.screen_every = s.every;
  rep.model = s.base.model;
  rep.train_source = s.full().source;
  rep.validation_source = s.val().source;
  rep.train_samples = s.full().used();
  rep.validation_samples = s.val().used();
  rep.elements = s.cur.spec.elements;
  s.noise_data = rep.noise;
  s.add_shares();
}

// A GMS / Maxwell-slip base fit whose error stays 1.3-5x above the floor the data allow sits in a
// local minimum of the shape search (or the element table bent to one): it is fitted again from
// the next design points of other basins, and kept when its shape explains more.
// Both fits are judged by the grid cost at their shape with the additive effects (offset, drift,
// a force along the stroke, inertia) solved alongside: an effect the data holds makes any base
// fit miss the floor, and a shape that only mimics it is no better. Far above the floor (5x) the
// misfit is an effect the probes lack, not the shape: the loop deals with it, and a retry would
// only cost time.
void retry_base_fit(LoopState& s) {
  if (!has_linear_elements(s.base.model) || s.cur.u.empty()) return;
  const Dataset& train = s.train();
  const double p0 = grid_cost_at(with_additive_probes(s.cur.spec), train, s.c, s.cur.u);
  const double floor = s.rep.noise.floor();
  if (!(p0 > 1.3 * floor && p0 < 5.0 * floor)) return;
  FitOptions ro = s.o.base;
  ro.first_start = std::clamp(ro.starts, 1, 3);
  ro.stage = "base fit, retry from other starts";
  FitResult again = fit_base(s.base, train, s.val(), s.c, ro);
  s.rep.base_retried = true;
  if (!again.u.empty() && grid_cost_at(with_additive_probes(again.spec), train, s.c, again.u) < 0.98 * p0) {
    s.cur = std::move(again);
    s.rep.elements = s.cur.spec.elements;
    s.add_shares();
  }
}

// The final model with friction-scaling effects (g columns: the grid's linear element weights
// cannot carry them) whose softest element is pinned at the soft end of its range (a friction
// level drifting over the record, with the base shape fitted before the drift was in the model):
// refitted in the wider range from its own shape, a local search and least squares, on the
// record the final model was fitted on; kept when it lowers both the training and the validation
// RMS.
void widen_pinned_soft_element(LoopState& s, const EffectContext& wide) {
  FitResult& cur = s.cur;
  const Parameterization par(model_info(cur.spec.model), cur.spec.elements, s.c);
  if (par.size() != cur.u.size()) return;
  bool pinned = false;
  for (std::size_t i = 0; i < par.size(); ++i)
    pinned |= par.params()[i].name.starts_with("kappa[") && cur.u[i] <= 1e-3;
  if (!pinned) return;
  const Parameterization pw(model_info(cur.spec.model), cur.spec.elements, wide);
  std::vector<double> start(par.size());
  for (std::size_t i = 0; i < par.size(); ++i) start[i] = pw.box(i, par.value(i, cur.u[i]));
  FitOptions fo = s.o.refit, lso = s.o.refit;
  fo.stage = "final model with softer elements than the swing shows";
  lso.stage = fo.stage + ", least squares";
  const Dataset& rec = s.train();  // the record cur was fitted on (screened or all samples)
  FitResult f =
      polish_least_squares(fit_model(cur.spec, rec, wide, fo, &start), rec, wide, 40, lso);
  const double val = rms_on(f, s.val(), wide);
  if (!(f.rms_train < cur.rms_train && val < s.cur_val)) return;
  s.rep.notes.push_back(
      "the element range was widened to " + fmt(1e6 * wide.x_hi_factor * wide.x_ba) +
      " um (the final model's softest element was pinned at the soft end): validation RMS " +
      fmt(s.cur_val) + " -> " + fmt(val) + " N");
  cur = std::move(f), s.cur_val = val, s.c = wide, s.rep.range_widened = true;
  s.base_from_data.reset();
  s.rep.elements = cur.spec.elements;
  s.set_last_stage();
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
void widen_element_range(LoopState& s, bool before_rounds) {
  FitResult& cur = s.cur;
  IdentReport& rep = s.rep;
  const EffectContext& c = s.c;
  const Dataset& train = s.train();
  const Dataset& val = s.val();
  if (!has_linear_elements(s.base.model) || cur.u.empty()) return;
  const bool g_columns = std::any_of(cur.spec.effects.begin(), cur.spec.effects.end(), multiplies_friction);
  EffectContext wide = c;
  wide.x_hi_factor = std::min(c.x_hi_factor * std::pow(10.0, 1.5), c.x_half / std::max(c.x_ba, 1e-12));
  if (!(wide.x_hi_factor > 1.5 * c.x_hi_factor)) return;
  if (g_columns) {
    if (!before_rounds) widen_pinned_soft_element(s, wide);
    return;
  }
  const FitSpec probe = additive_probes_for(cur, train, c);
  const double c0 = grid_cost_at(probe, train, c, cur.u), c1 = grid_cost_at(probe, train, wide, cur.u);
  if (!(c1 < 0.98 * c0)) return;
  FitOptions wo = s.o.base;
  wo.stage = "element table on a wider range";
  FitResult again = regrid_elements(cur.spec, train, wide, wo, cur.u);
  const double again_val = rms_on(again, val, wide);
  // Before the rounds a soft element competes with the effects it can mimic (an offset
  // within a stroke, a force along it): when the effect that screens best at the current
  // shape, refitted, predicts the validation record as well (within 3 %), the loop decides.
  const bool better = again.rms_train < cur.rms_train && again_val < s.cur_val;
  bool effect_alike = false;
  if (before_rounds && better) {
    std::optional<Candidate> top;
    for (Effect e : s.o.candidates)
      if (e != Effect::TimeShift && e != Effect::SensorFilter && e != Effect::Backlash &&
          e != Effect::DwellStiction && effect_applicable(e, train, c)) {
        Candidate k = screen(e, cur, train, val, c, &cur.u);
        if (!top || k.screen_rms_validation < top->screen_rms_validation) top = std::move(k);
      }
    if (top) {
      FitOptions fo = s.o.refit;
      fo.stage = "element range or " + std::string(effect_name(top->effect)) + "?";
      const FitResult f = fit_model(with(cur.spec, top->effect), train, c, fo, &cur.u);
      effect_alike = rms_on(f, val, c) <= 1.03 * again_val;
    }
  }
  if (!better || effect_alike) return;
  rep.notes.push_back(
      "the element range was widened to " + fmt(1e6 * wide.x_hi_factor * wide.x_ba) +
      " um (softer elements than the swing after most reversals shows): validation RMS " +
      fmt(s.cur_val) + " -> " + fmt(again_val) + " N");
  cur = std::move(again), s.cur_val = again_val, s.c = wide, rep.range_widened = true;
  s.base_from_data.reset();
  rep.elements = cur.spec.elements;
  s.set_last_stage();
}

// The index of the last shape parameter `is` picks, or par.size() when none.
template <class Pred>
std::size_t shape_index(const Parameterization& par, Pred is) {
  std::size_t k = par.size();
  for (std::size_t i = 0; i < par.size(); ++i)
    if (is(par.params()[i])) k = i;
  return k;
}

// A Stribeck velocity beyond the record's speeds. The fits search Vs up to 2 x v_ref (the 95th
// percentile of |v|); a record that stays below Vs (slow sliding on the falling branch: Fig. 2C at
// 0.1 Hz, 0.31 mm/s against Vs = 1 mm/s) sees only the top of the Stribeck curve, where Fc, Vs,
// delta and the viscous term trade off along a narrow valley. There the base fit presses Vs against
// the top of its range, or gives the curve up with Vs below a hundredth of the record's speed
// scale (S = Fc at nearly every speed the record reaches, the falling branch mimicked by the
// other terms). Then the range's top
// goes up a decade (20 x v_ref), and the base model is refitted with the refit budget from its
// shape (and, where it gave the curve up, from its shape with Vs at 3 v_ref and Fs/Fc at 1.5), each
// polished by Levenberg-Marquardt along the valley (polish_least_squares, fit.hpp); the best is
// kept when it lowers both the training and the validation RMS.
void widen_stribeck_range(LoopState& s) {
  if (s.cur.u.empty()) return;
  const ModelInfo& info = model_info(s.cur.spec.model);
  const Parameterization par(info, s.cur.spec.elements, s.c);
  if (par.size() != s.cur.u.size()) return;
  const std::size_t iv = shape_index(par, [](const ShapeParam& p) { return p.unit == "m/s"; });
  if (iv == par.size()) return;
  // Pressed against the top: within a factor 1.2 of it (the search stops short of a bound it
  // presses on), or within a factor 3 of it while the base fit leaves more than twice the floor
  // on validation (a search that stopped short of the bound: on the noise-free Fig. 2C trace at
  // 0.1 Hz the base fit ends with Vs 1.17-1.20x below the top, and where it ended 1.2x below it
  // the loop was left 7x above the floor). Below a hundredth of the speed scale the fit has given
  // the Stribeck curve up (S = Fc at nearly every speed the record reaches): a start beyond the
  // speeds is tried too.
  const double vs_was = par.value(iv, s.cur.u[iv]);
  const ShapeParam& pv = par.params()[iv];
  const bool short_of_floor = s.cur_val > 2.0 * s.rep.noise.floor();
  const bool at_hi = vs_was >= pv.hi / 1.2 || (short_of_floor && vs_was >= pv.hi / 3.0),
             at_lo = vs_was <= 0.01 * s.c.v_ref;
  if (!at_hi && !at_lo) return;
  EffectContext wide = s.c;
  wide.vs_hi_factor = 10.0 * s.c.vs_hi_factor;
  const Parameterization pw(info, s.cur.spec.elements, wide);
  std::vector<std::vector<double>> starts(1, std::vector<double>(par.size()));
  for (std::size_t i = 0; i < par.size(); ++i) starts[0][i] = pw.box(i, par.value(i, s.cur.u[i]));
  if (at_lo) {
    starts.push_back(starts[0]);
    starts[1][iv] = pw.box(iv, 3.0 * wide.v_ref);
    for (std::size_t i = 0; i < par.size(); ++i)
      if (par.params()[i].name == "Fs/Fc") starts[1][i] = pw.box(i, 1.5);
  }
  const std::string top = fmt(wide.vs_hi_factor * wide.v_ref) + " m/s";
  FitOptions fo = s.o.refit, lso = s.o.refit;
  fo.stage = "base fit with the Stribeck velocity up to " + top;
  lso.stage = fo.stage + ", least squares";
  std::optional<FitResult> best;
  for (const auto& u : starts) {
    FitResult f = polish_least_squares(fit_model(s.cur.spec, s.train(), wide, fo, &u), s.train(),
                                       wide, 40, lso);
    if (!best || f.rms_train < best->rms_train) best = std::move(f);
  }
  FitResult f = std::move(*best);
  const double val = rms_on(f, s.val(), wide);
  const std::string where =
      fmt(vs_was) + " m/s, " +
      (at_hi ? "the top of its range" : "below a hundredth of the record's speeds");
  if (!(f.rms_train < s.cur.rms_train && val < s.cur_val)) {
    s.rep.notes.push_back("the base fit has Vs at " + where + "; a fit with Vs up to " + top +
                          " did not explain both records better" +
                          (at_hi ? ": Vs may lie beyond the speeds the record reaches" : ""));
    return;
  }
  s.rep.notes.push_back("the Stribeck velocity's range was widened to " + top +
                        " (the base fit had Vs at " + where +
                        "; the record stays on the falling branch of the Stribeck curve): Vs " +
                        fmt(pw.value(iv, f.u[iv])) + " m/s, validation RMS " + fmt(s.cur_val) +
                        " -> " + fmt(val) + " N");
  s.cur = std::move(f);
  s.cur_val = val;
  s.c = wide;
  s.rep.stribeck_range_widened = true;
  s.base_from_data.reset();
  s.rep.elements = s.cur.spec.elements;
  s.add_shares();
}

namespace {
constexpr double kWidestBreakAwayRatio = 125.0;  // the loop widens Fs/Fc's range up to this
constexpr double kPressing = 1.1;  // a fit within this factor of the top presses on it
}  // namespace

std::optional<std::string> beyond_widest_break_away_range(const FitResult& f,
                                                          const EffectContext& c) {
  const ModelInfo& info = model_info(f.spec.model);
  if (info.scalar_index("Fs") < 0 || info.scalar_index("Fc") < 0 ||
      c.fs_hi_factor < kWidestBreakAwayRatio)
    return std::nullopt;
  const double ratio = f.friction.scalar("Fs") / f.friction.scalar("Fc");
  if (!(ratio >= c.fs_hi_factor / kPressing)) return std::nullopt;
  return "Fs/Fc is " + fmt(ratio) + ", at the top of the widest range the loop searches [1, " +
         fmt(c.fs_hi_factor) +
         "] (-): the data may want a value beyond it, and the fit is the "
         "closest model within the range";
}

// A break-away ratio beyond its range. The fits search Fs/Fc in [1, fs_hi_factor] (5); friction
// that falls by more than that from break-away to sliding (the registry's ranges allow Fs/Fc up to
// 9) pins the base fit at the top, and the other terms bend to what the ratio cannot give. Where
// the base fit has Fs/Fc within a factor 1.1 of the top (the search can stop short of a bound it
// presses on), or within a factor 2 while it leaves more than 1.5x the floor on validation (a fit
// that settled on a higher Coulomb level), the range goes up five-fold and the base model is
// refitted with the refit budget from its shape and from its shape with the ratio 2.5x higher,
// each polished by Levenberg-Marquardt (polish_least_squares, fit.hpp); the best refit is
// kept when it lowers both the training and the validation RMS, and the range goes up once more
// (to 125) where the refit presses on the new top. Before the rounds only where the additive
// effects do not take up half the base fit's misfit; after them (before_rounds false: the final
// model, its effects included) where the final model presses on the top. A final fit that presses
// on 125 is not a verified minimum (beyond_widest_break_away_range).
void widen_break_away_range(LoopState& s, bool before_rounds) {
  const ModelInfo& info = model_info(s.cur.spec.model);
  // A base fit whose misfit the additive effects (offset, inertia, drift, a force along the
  // stroke) take up by half or more misfits for an effect the rounds look for, not for the ratio
  // (an actuator force's inertia pins a GMS base fit at any ratio): the final model is tested
  // instead.
  if (before_rounds && has_linear_elements(s.cur.spec.model) && !s.cur.u.empty()) {
    const double plain = grid_cost_at(s.cur.spec, s.train(), s.c, s.cur.u);
    const double probed = grid_cost_at(with_additive_probes(s.cur.spec), s.train(), s.c, s.cur.u);
    if (probed < 0.5 * plain) return;
  }
  while (s.c.fs_hi_factor < kWidestBreakAwayRatio && !s.cur.u.empty()) {
    const Parameterization par(info, s.cur.spec.elements, s.c);
    if (par.size() != s.cur.u.size()) return;
    const std::size_t ir = shape_index(par, [](const ShapeParam& p) { return p.name == "Fs/Fc"; });
    if (ir == par.size()) return;
    const double was = par.value(ir, s.cur.u[ir]);
    const double top = par.params()[ir].hi;
    const bool short_of_floor = before_rounds && s.cur_val > 1.5 * s.rep.noise.floor();
    if (!(was >= top / kPressing || (short_of_floor && was >= top / 2))) return;
    EffectContext wide = s.c;
    wide.fs_hi_factor = std::min(5.0 * s.c.fs_hi_factor, kWidestBreakAwayRatio);
    const Parameterization pw(info, s.cur.spec.elements, wide);
    // From the base fit's shape, and from it with the ratio 2.5 times higher: a fit that settled
    // on a higher Coulomb level below the top has the other basin far along the ratio.
    std::vector<std::vector<double>> starts(2, std::vector<double>(par.size()));
    for (std::size_t i = 0; i < par.size(); ++i) starts[0][i] = pw.box(i, par.value(i, s.cur.u[i]));
    starts[1] = starts[0];
    starts[1][ir] = pw.box(ir, 2.5 * was);
    FitOptions fo = s.o.refit, lso = s.o.refit;
    fo.stage = "base fit with Fs/Fc up to " + fmt(wide.fs_hi_factor);
    lso.stage = fo.stage + ", least squares";
    std::optional<FitResult> best;
    // The final model was refitted on all samples (final_refit).
    const Dataset& rec = before_rounds ? s.train() : s.full();
    for (const auto& u : starts) {
      FitResult f =
          polish_least_squares(fit_model(s.cur.spec, rec, wide, fo, &u), rec, wide, 40, lso);
      if (!best || f.rms_train < best->rms_train) best = std::move(f);
    }
    FitResult f = std::move(*best);
    const double val = rms_on(f, s.val(), wide);
    if (!(f.rms_train < s.cur.rms_train && val < s.cur_val)) {
      s.rep.notes.push_back("the base fit has Fs/Fc at " + fmt(was) +
                            ", near the top of its range, " + fmt(top) +
                            "; a fit with Fs/Fc up to " + fmt(wide.fs_hi_factor) +
                            " did not explain both records better");
      return;
    }
    s.rep.notes.push_back("the break-away ratio's range was widened to Fs/Fc <= " +
                          fmt(wide.fs_hi_factor) + " (the base fit had Fs/Fc at " + fmt(was) +
                          (was >= top / kPressing ? ", the top of its range"
                                                  : ", near the top of its range, and left " +
                                                        fmt(s.cur_val / s.rep.noise.floor()) +
                                                        "x the floor on validation") +
                          "): Fs/Fc " + fmt(pw.value(ir, f.u[ir])) + ", validation RMS " +
                          fmt(s.cur_val) + " -> " + fmt(val) + " N");
    s.cur = std::move(f);
    s.cur_val = val;
    s.c = wide;
    s.rep.break_away_range_widened = true;
    s.base_from_data.reset();
    s.rep.elements = s.cur.spec.elements;
    s.add_shares();
    if (!before_rounds) {
      s.optimum.reset();
      s.set_last_stage();
    }
  }
}

// The credit test names an effect by size when the validation MSE without it exceeds the MSE
// with it by at least the floor's variance (ablation.hpp). The most an effect can lower the
// model's validation MSE is what lies above the floor, cur_val^2 - floor^2: below floor^2 (within
// sqrt(2) x the floor) no effect can reach that rise, and the rounds - which would only add
// effects for the credit to drop - are not run. That holds only for a floor no model beats, so
// the bound takes the floor's parts that are measured or computed through the model (the noise
// only where it was measured at rests: without rests it is an upper bound) and is not used where
// the model already predicts the held-out record better than that floor (the estimate is then
// shown too high). The block test's other clause (z >= 3: a small but consistent gain) is not
// bounded by size, so round 1's screening runs first and the rounds are skipped only when no
// candidate's screening fit passes that clause on the validation record: where the sampling
// share makes the floor several times the noise, effects of 2-10x the noise lie within the size
// bound and are still resolved by the block test. That the rounds credit nothing where this
// bound skips them is checked on random records with effects of 1.5-50x the noise
// (IdentCreditBound): an effect of 34x the noise beside a floor estimate above the base fit's
// validation RMS was credited by the full rounds.
// A base fit above the bound is first refitted with the rounds' budget (round 1's control refit:
// what it gains is optimisation); when that is within the bound it becomes the model, else it is
// kept for round 1, which would make the same fit (a pure function of the same inputs: the base
// spec depends on no context value the round tunes).
bool no_effect_creditable(LoopState& s) {
  const NoiseEstimate& n = s.rep.noise;
  const double noise = n.from_rests ? n.sigma : 0.0;
  // The smaller of the two sampling estimates (structure.hpp: the straight-step bound overstates
  // the share up to 50x where the force follows the speed at each instant).
  const double sampling =
      n.sampling_halving >= 0 ? std::min(n.sampling, n.sampling_halving) : n.sampling;
  const double floor =
      std::sqrt(noise * noise + n.quantisation * n.quantisation + sampling * sampling);
  if (!s.o.credit_bound || !(floor > 0)) return false;
  auto within = [&](double val) {
    return val >= floor && val * val - floor * floor < floor * floor;
  };
  // A base fit that predicts the held-out record better than the floor shows the estimate too
  // high (a sampling share through a base model that misses an effect): no bound then.
  if (s.cur_val < floor) return false;
  if (!within(s.cur_val)) {
    // Far above the floor (5x, as the base-fit retry) a refit that only optimises will not reach
    // the bound, and round 1 makes its control refit only when an effect passes the gain.
    if (!s.cur.spec.effects.empty() || !(s.cur_val < 5.0 * floor)) return false;
    FitOptions co = serialised_progress(s.o.refit);
    co.stage = "round 1: control refit without a new effect";
    FitResult ctrl = fit_model(s.cur.spec, s.train(), s.c, co, &s.cur.u);
    const double val = ctrl.rms_train < s.cur.rms_train ? rms_on(ctrl, s.val(), s.c) : s.cur_val;
    if (!within(val)) {
      s.control = std::move(ctrl);
      return false;
    }
    s.cur = std::move(ctrl);
    s.cur_val = val;
    s.rep.stages.back() = s.cur;
    s.rep.rms_before_train = s.cur.rms_train;
    s.rep.rms_before_validation = s.cur_val;
  }
  // The bound holds for the credit's size clause only. Its block-test clause (z >= z_crit) is not
  // bounded by size: where a candidate's screening (its columns re-solved at the current shape)
  // already predicts the held-out record better by that test, the rounds run.
  if (const auto k = screening_resolves(s, AblationOptions{}.z_crit)) {
    s.rep.notes.push_back("the base fit is within " + fmt(s.cur_val / floor) + "x the floor of " +
                          fmt(floor) + " N, but the screening of " +
                          std::string(effect_name(k->effect)) +
                          " predicts the validation record better by the credit's block test (z " +
                          fmt(k->screen_z) + "): the rounds were run");
    return false;
  }
  s.rep.rounds_skipped =
      "no effect can pass the credit test (base within " + fmt(s.cur_val / floor) +
      "x the floor of " + fmt(floor) + " N: its validation MSE above the floor is below " +
      "the floor's variance, the rise the credit test needs to name an effect by size); " +
      "the rounds were not run";
  return true;
}

// The final model on all samples. Screened on every k-th sample: the element range tested there,
// then the final model refitted on all samples from its screened shape (and the first stage's
// training RMS taken on all). With effects added or after screening, a last refit of the final
// model from its shape and from the data-based guess (the control refit of a round, for the model
// the loop ends with): what it gains is optimisation.
void final_refit(LoopState& s) {
  IdentReport& rep = s.rep;
  FitResult& cur = s.cur;
  const Dataset& full = s.full();
  if (s.every > 1) {
    if (!rep.range_widened) widen_element_range(s, false);
    rep.rms_before_train = rms_on(rep.stages.front(), full, s.c);
    cur.rms_train = rms_on(cur, full, s.c);
    rep.stages.back().rms_train = cur.rms_train;
  }
  if (!rep.effects_added.empty() || s.every > 1) {
    FitOptions fo = s.o.refit;
    fo.stage = "final refit";
    // After screening: one local search from the screened shape on all samples (the shape is
    // found; more samples move it a little).
    fo.polish_only = s.every > 1;
    if (s.every > 1) fo.rel_tol = 1e-5;
    FitResult f = fit_model(cur.spec, full, s.c, fo, &cur.u);
    if (f.rms_train < cur.rms_train) {
      cur = std::move(f);
      s.cur_val = rms_on(cur, s.val(), s.c);
      s.set_last_stage();
    }
  }
  if (s.every == 1 && !rep.range_widened) widen_element_range(s, false);
}

// A count the credit raised (--elements auto: one more element explained an effect as well): the
// ablation's refit at that count starts from the smaller model's shape with an element split off,
// one local search, and can stay far from the data's minimum (gmslab's own two-element trace,
// noise-free: 23x the floor). The fit at that count from the data (the element grid, as a base fit
// with the count given) is run too, on the record the loop decided on, polished on all samples
// after screening, and kept when its training RMS is lower.
void refit_raised_count(LoopState& s) {
  if (!s.rep.ablation.count_raised || !has_linear_elements(s.cur.spec.model)) return;
  FitOptions fo = s.o.base;
  fo.stage =
      "base fit with the raised count of " + std::to_string(s.cur.spec.elements) + " elements";
  FitResult f = fit_model(s.cur.spec, s.train(), s.c, fo);
  if (f.u.empty()) return;
  if (s.every > 1)
    polish_on_all_samples(f, s.full(), s.c, s.o.refit, fo.stage + ", on all samples");
  if (!(f.rms_train < s.cur.rms_train)) return;
  s.rep.notes.push_back("the fit with " + std::to_string(f.spec.elements) +
                        " elements from the data explains the training record better (RMS " +
                        fmt(f.rms_train) + " N against " + fmt(s.cur.rms_train) +
                        " N) than the refit from the smaller model's shape; it is the final model");
  s.cur = std::move(f);
  s.cur_val = rms_on(s.cur, s.val(), s.c);
  s.rep.stages.back() = s.cur;
}

// The floor the credit is judged against: noise, and the quantisation and sampling shares
// through the final model (a base fit far from the data overstates the sampling share).
void credit(LoopState& s) {
  NoiseEstimate at_final = s.noise_data;
  s.add_model_shares(at_final, s.cur, s.full());
  s.credit_floor = at_final.floor();
  const bool same_record =
      s.base_from_data && s.rep.rounds.empty() && s.base_from_data_on == &s.train();
  credit_by_ablation(s.rep, s.cur, s.cur_val, s.train(), s.full(), s.val(), s.c, s.credit_floor,
                     s.every, s.o, s.base.elements == 0,
                     same_record ? &*s.base_from_data : nullptr);
  refit_raised_count(s);
}

// The final shape to a minimum the optimum test can verify. A derivative-free search stops where
// its own model of the cost stops promising progress; on a curved ridge or a cost made rough by
// the sampled path that can be short of a minimum by a fraction of a percent, and the optimum test
// (check_optimum: coordinate steps of 1e-3 of the unit box, the linear terms re-solved) then
// withholds every standard error. A pattern search (Hooke and Jeeves) continues from there: each
// coordinate stepped up, else down, a step kept when it lowers the training RMS by 1e-6
// relative at least; after a sweep that moved, the same move is repeated from the new point while
// it keeps lowering the RMS (so a ridge is followed in strides, not steps); a sweep that does not
// move halves the step, from 8e-3 down to the optimum test's own 1e-3. Within a bounded budget; the
// model, its validation RMS and the last stage follow when it moved. A fit with a shape parameter
// pinned at an end of its range is left as it is, and the search stops where a coordinate reaches
// the upper end (check_optimum then says the range binds). The effects and the element count are
// those the credit decided.
namespace {
struct PatternSearch {
  // The cost of a point, on worker 0 (this thread) or 1 (the second one).
  std::function<double(const std::vector<double>&, int)> cost;
  int evaluations = 0;
  int budget = 0;
  bool at_end = false;  // a kept step reached a coordinate's upper end
  // A step is kept when it lowers the RMS by a tenth of what the optimum test calls a descent
  // (1e-5 relative): crawling along a flat ridge for less would only spend the budget.
  static constexpr double kGain = 1e-6;

  // Coordinate steps of size h around x (cost fx); returns the point reached and its cost. Each
  // coordinate's step up is kept when it lowers the cost, else its step down; the two are costed
  // at once on two threads (the cost is a pure function of the point), so the search takes the
  // same steps and counts the same evaluations as costing the step down only when needed.
  std::pair<std::vector<double>, double> explore(std::vector<double> x, double fx, double h) {
    for (std::size_t i = 0; i < x.size() && evaluations < budget && !at_end; ++i) {
      std::vector<double> up = x, down = x;
      up[i] = std::clamp(x[i] + h, 0.0, 1.0);
      down[i] = std::clamp(x[i] - h, 0.0, 1.0);
      const bool try_up = up[i] != x[i], try_down = down[i] != x[i];
      double r_up = std::numeric_limits<double>::infinity(), r_down = r_up;
      if (try_up && try_down)
        run_both([&] { r_down = cost(down, 1); }, [&] { r_up = cost(up, 0); });
      else if (try_up)
        r_up = cost(up, 0);
      else if (try_down)
        r_down = cost(down, 0);
      evaluations += try_up;
      if (try_up && r_up < fx * (1.0 - kGain)) {
        at_end = up[i] >= 1.0 - 1e-3;
        x = std::move(up), fx = r_up;
        continue;
      }
      evaluations += try_down;
      if (try_down && r_down < fx * (1.0 - kGain)) {
        at_end = down[i] >= 1.0 - 1e-3;
        x = std::move(down), fx = r_down;
      }
    }
    return {std::move(x), fx};
  }

  void run(std::vector<double>& base, double& fbase) {
    for (double h = 8e-3; h >= 1e-3 && evaluations < budget && !at_end;) {
      auto [x, fx] = explore(base, fbase, h);
      if (!(fx < fbase * (1.0 - kGain))) {
        h /= 2;
        continue;
      }
      // Pattern moves: x + (x - base), explored, while they keep lowering the cost.
      while (evaluations < budget && !at_end) {
        std::vector<double> p(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) p[i] = std::clamp(2 * x[i] - base[i], 0.0, 1.0);
        base = x, fbase = fx;
        const double fp = cost(p, 0);
        ++evaluations;
        auto [y, fy] = explore(p, fp, h);
        if (!(fy < fbase * (1.0 - kGain))) break;
        x = std::move(y), fx = fy;
      }
      if (fx < fbase) base = std::move(x), fbase = fx;
    }
  }
};
}  // namespace

void descend_to_minimum(LoopState& s) {
  FitResult& cur = s.cur;
  if (cur.u.empty() || cur.time_limited) return;
  const Dataset& full = s.full();
  // Only a fit short of a minimum: at a pinned end the range binds, and sliding along the end
  // would only find a point the range shaped as much as the data.
  const OptimumCheck at = check_optimum(cur, full, s.c);
  s.optimum = at;  // the test of cur, kept for the report while cur does not move
  if (at.verified || at.pinned) return;
  PatternSearch ps;
  LinearRefit on[2] = {LinearRefit(cur.spec, full, s.c), LinearRefit(cur.spec, full, s.c)};
  ps.cost = [&on](const std::vector<double>& u, int worker) { return on[worker].rms(u); };
  // About 50 sweeps; each evaluation is one run along the record.
  ps.budget = 100 * static_cast<int>(cur.u.size());
  std::vector<double> u = cur.u;
  double best = ps.cost(u, 0);
  const double start = best;
  ps.run(u, best);
  if (!(best < start) || !(best < cur.rms_train)) return;
  FitResult f = on[0].fit(u);
  f.evaluations = cur.evaluations + ps.evaluations + 1;
  s.optimum.reset();
  cur = std::move(f);
  s.cur_val = rms_on(cur, s.val(), s.c);
  s.set_last_stage();
}

// Terms beyond the catalog (discovery.hpp): a sparse regression of the final model's residual on
// all training samples, judged on validation against the credit floor.
void discover_terms(LoopState& s) {
  DiscoveryOptions o;
  o.min_size = s.o.min_size;
  const auto ft = predict(s.cur, s.full(), s.c), fv = predict(s.cur, s.val(), s.c);
  s.rep.discovery = discover(s.full(), s.val(), s.c, ft, fv, s.credit_floor, o);
}

namespace {
// A record's identity for the memo below: its samples and the path between them (an FNV-1a
// style hash over the 64-bit words of t, x, v and the sub-steps; a word at a time, so hashing a
// record costs a small part of one run along it).
std::uint64_t record_key(const Dataset& d) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t w) { h = (h ^ w) * 1099511628211ull, h ^= h >> 29; };
  auto add = [&mix](const auto& v) {
    mix(v.size());
    for (const auto& e : v) {
      std::uint64_t w = 0;
      std::memcpy(&w, &e, sizeof e);
      mix(w);
    }
  };
  add(d.t), add(d.x), add(d.v), add(d.sub), add(d.sv), add(d.sh);
  return h;
}

// The model's force along a record, computed once per record: the discovered column is built
// by every refit of the joint model (a pattern-search step builds one), and each would otherwise
// run the model along the record again. The records a loop meets are few (training, its screen,
// validation); the memo keeps the last four. Safe to call from the fits' two threads.
std::function<std::vector<double>(const Dataset&)> memoised_force(const FitResult& f,
                                                                  const EffectContext& c) {
  struct Memo {
    FitResult model;
    EffectContext at;
    std::mutex m;
    std::vector<std::pair<std::uint64_t, std::shared_ptr<const std::vector<double>>>> kept;
  };
  auto memo = std::make_shared<Memo>();
  memo->model = f;
  memo->at = c;
  return [memo](const Dataset& d) {
    const std::uint64_t key = record_key(d);
    {
      std::lock_guard<std::mutex> lock(memo->m);
      for (const auto& [k, force] : memo->kept)
        if (k == key) return *force;
    }
    auto force = std::make_shared<const std::vector<double>>(predict(memo->model, d, memo->at));
    std::lock_guard<std::mutex> lock(memo->m);
    if (memo->kept.size() >= 4) memo->kept.erase(memo->kept.begin());
    memo->kept.emplace_back(key, force);
    return *force;
  };
}
}  // namespace

// The discovered terms in the model. Discovery fits its terms on the final model's residual, at a
// shape the catalog's effects bent to whatever the terms explain (a reversal transient read as a
// backlash or a sensor filter, a one-sided ripple as a position ripple). The model with the kept
// terms as one more effect (Effect::Discovered: each term as discovered, scaled by a coefficient
// of its own; the force-lag and |F v|-history terms on the final model's force as discovery had
// them) is refitted from the final shape with the refit budget on all training samples, and
// kept when it predicts the validation record better than the final model with the terms on its
// residual; then every effect, the terms included, is credited again by ablation (credit: a
// catalog effect that only stood in for the terms is no longer named) and the shape is taken to a
// minimum the optimum test verifies. The report says what the credit made of the terms.
void join_discovered(LoopState& s) {
  Discovery& ds = s.rep.discovery;
  if (!ds.found || s.cur.u.empty() || contains(s.cur.spec.effects, Effect::Discovered)) return;
  EffectContext joint = s.c;
  joint.discovered = ds.terms;
  // The force the terms were discovered on: the final model's, along any record.
  joint.discovered_force = memoised_force(s.cur, s.c);
  FitOptions fo = s.o.refit;
  fo.stage = "joint refit with the discovered terms";
  FitResult f = fit_model(with(s.cur.spec, Effect::Discovered), s.full(), joint, fo, &s.cur.u);
  const double val = rms_on(f, s.val(), joint);
  if (!(val < ds.rms_validation_after)) {
    s.rep.notes.push_back(
        "the model refitted jointly with the discovered terms predicts the "
        "validation record less well (" +
        fmt(val) + " N against " + fmt(ds.rms_validation_after) +
        " N with the terms on the final model's residual): the terms stay "
        "fitted on the residual");
    return;
  }
  const double residual_val = ds.rms_validation_after;
  s.c = joint;
  s.cur = std::move(f);
  s.cur_val = val;
  s.rep.effects_added = s.cur.spec.effects;
  s.rep.stages.push_back(s.cur);
  s.optimum.reset();
  credit(s);
  descend_to_minimum(s);
  const auto kept = terms_of(s.cur, Effect::Discovered);
  if (!contains(s.cur.spec.effects, Effect::Discovered)) {
    std::string why;
    for (const auto& d : s.rep.ablation.dropped)
      if (d.effect == Effect::Discovered) why = d.verdict;
    ds.found = false;
    ds.rms_validation_after = ds.rms_validation_before;
    ds.summary = "nothing discovered: " + discovered_formula(ds) +
                 " passed on the final model's residual, but fitted jointly with the model it "
                 "failed the credit test" +
                 (why.empty() ? std::string() : " (" + why + ")");
    return;
  }
  for (std::size_t i = 0; i < ds.terms.size() && i < kept.size(); ++i)
    ds.terms[i].coefficient *= kept[i].value;
  ds.joined = true;
  ds.rms_validation_after = s.cur_val;
  ds.summary = "discovered: " + discovered_formula(ds) + "  (fitted jointly with the model and " +
               "credited by ablation: validation " + fmt(ds.rms_validation_before) + " -> " +
               fmt(s.cur_val) + " N; " + fmt(residual_val) +
               " N with the terms on the final model's residual)";
}

// The final model's figures: parameter errors (only at a verified optimum) and what the
// validation residual still holds, against the validation record's own floor.
namespace {
// No standard error where the fit is not at a verified minimum, or where the base level is an
// extrapolation of the Stribeck curve (loop.hpp: stribeck_reach).
void withhold_errors(IdentReport& rep, const FitResult& f, const Dataset& train) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!rep.optimum.verified) {
    for (auto& p : rep.parameters) p.std_error = kNaN, p.no_error = "not converged";
    return;
  }
  const auto reach = stribeck_reach(f.friction, train, kStribeckReachLimit);
  if (!reach || !(reach->excess > kStribeckReachLimit)) return;
  const std::string why = "extrapolated: at the record's top sliding speed (" + fmt(reach->v_top) +
                          " m/s) the Stribeck curve still stands " + fmt(100 * reach->excess) +
                          " % above Fc; slide faster than " + fmt(reach->v_needed) +
                          " m/s to measure it";
  for (auto& p : rep.parameters)
    if (p.effect == "base" && (p.name == "Fc" || p.name == "sigma2"))
      p.std_error = kNaN, p.no_error = why;
}
}  // namespace

void finish_report(LoopState& s) {
  IdentReport& rep = s.rep;
  const FitResult& cur = s.cur;
  const EffectContext& c = s.c;
  const Dataset& full = s.full();
  const Dataset& val = s.val();
  rep.context = c;
  rep.rms_after_train = cur.rms_train;
  rep.rms_after_validation = s.cur_val;
  // Terms fitted on the residual (not joined) are added to the final model's prediction.
  const bool found = rep.discovery.found && !rep.discovery.joined;
  if (found) {
    const auto ft = predict(cur, full, c);
    const auto dt = discovered_force(rep.discovery, full, c, ft);
    std::vector<double> r(full.size());
    for (std::size_t k = 0; k < full.size(); ++k) r[k] = full.F[k] - ft[k] - dt[k];
    double q = 0, n = 0;
    for (std::size_t k = 0; k < full.size(); ++k)
      if (full.use[k]) q += r[k] * r[k], n += 1;
    rep.rms_after_train = n > 0 ? std::sqrt(q / n) : 0.0;
    rep.rms_after_validation = rep.discovery.rms_validation_after;
  }
  rep.parameters =
      parameter_estimates(cur, full, c, rep.fine_path ? kFinePath : PathRule{}, rep.noise.quantum);
  rep.optimum = s.optimum ? *s.optimum : check_optimum(cur, full, c);
  if (rep.optimum.verified)
    if (auto why = beyond_widest_break_away_range(cur, c))
      rep.optimum.verified = false, rep.optimum.reason = *why, rep.optimum.pinned = true;
  withhold_errors(rep, cur, full);
  auto rv = residual(cur, val, c);
  if (found) {
    const auto dv = discovered_force(rep.discovery, val, c, predict(cur, val, c));
    for (std::size_t k = 0; k < val.size(); ++k) rv[k] -= dv[k];
  }
  const auto gv = unit_friction(cur, val, c);
  NoiseEstimate nv = noise_level(val, c);
  if (nv.sigma <= 0 || (!nv.from_rests && rep.noise.from_rests)) nv = rep.noise;
  s.add_model_shares(nv, cur, val);
  rep.remaining = residual_structure(val, c, rv, gv, nv);
}

}  // namespace gmslab::ident::detail

namespace gmslab::ident {

std::optional<StribeckReach> stribeck_reach(const ModelParams& p, const Dataset& d, double limit) {
  const ModelInfo& info = model_info(p.model);
  for (const char* k : {"Fs", "Fc", "Vs", "delta"})
    if (info.scalar_index(k) < 0) return std::nullopt;
  std::vector<double> speeds;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) speeds.push_back(std::abs(d.v[k]));
  if (speeds.empty()) return std::nullopt;
  const auto top =
      speeds.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(speeds.size() - 1));
  std::nth_element(speeds.begin(), top, speeds.end());
  if (!(*top > 0)) return std::nullopt;
  const double Fs = p.scalar("Fs"), Fc = p.scalar("Fc"), Vs = p.scalar("Vs"),
               delta = p.scalar("delta");
  if (!(Fc > 0) || !(Vs > 0) || !(delta > 0)) return std::nullopt;
  StribeckReach r;
  r.v_top = *top;
  const double drop = (Fs - Fc) / Fc;  // the curve's whole drop over Fc
  r.excess = drop * std::exp(-std::pow(r.v_top / Vs, delta));
  r.v_needed = drop > limit ? Vs * std::pow(std::log(drop / limit), 1.0 / delta) : 0.0;
  return r;
}

}  // namespace gmslab::ident
