#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/ident/evidence.hpp"
#include "core/ident/loop_stages.hpp"
#include "core/ident/parallel.hpp"

namespace gmslab::ident::detail {

namespace {

double chi2_tail_large(double x, double dof) {
  // Wilson-Hilferty: chi^2 tail through the normal tail (enough for a screening threshold).
  if (dof <= 0) return 1.0;
  const double z = (std::cbrt(x / dof) - (1 - 2 / (9 * dof))) / std::sqrt(2 / (9 * dof));
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

}  // namespace

Candidate screen(Effect e, const FitResult& cur, const Dataset& train, const Dataset& val,
                 const EffectContext& c, const std::vector<double>* shape,
                 const std::vector<double>* r_val) {
  Candidate k;
  k.effect = e;
  if (shape && shape->size() != cur.u.size()) shape = nullptr;  // not a shape of cur's parameterization
  const auto lin = refit_linear(with(cur.spec, e), train, c, shape ? *shape : cur.u);
  k.screen_rms_train = lin.rms_train;
  k.explained = cur.rms_train > 0 ? 1.0 - std::pow(lin.rms_train / cur.rms_train, 2) : 0.0;
  const std::vector<double> r = residual(lin, val, c);
  k.screen_rms_validation = rms_of(val, r);
  if (r_val) k.screen_z = block_test(val, *r_val, r).z;
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

namespace {

// Golden section on [a, b] for `iters` steps or until the bracket is narrower than `tol`: the
// better of the last two points and its cost.
template <class Cost>
std::pair<double, double> golden_section(double a, double b, int iters, double tol, Cost&& cost) {
  const double gr = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = b - gr * (b - a), x2 = a + gr * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int i = 0; i < iters && b - a > tol; ++i) {
    if (f1 < f2)
      b = x2, x2 = x1, f2 = f1, x1 = b - gr * (b - a), f1 = cost(x1);
    else
      a = x1, x1 = x2, f1 = f2, x2 = a + gr * (b - a), f2 = cost(x2);
  }
  return f1 < f2 ? std::pair{x1, f1} : std::pair{x2, f2};
}

// The dwell decay length s0 (a few multiples of x_ba) and rise rho (of Fs/Fc per unit phi, a grid
// of 0.01 to 10, log-spaced) whose linear refit at the current shape leaves the lowest training
// RMS; rho then refined by golden section in log within 3x of the best grid value.
void choose_dwell_shape(const FitResult& cur, const Dataset& train, EffectContext& c) {
  const FitSpec spec = with(cur.spec, Effect::DwellStiction);
  auto cost = [&](double s0, double rho) {
    c.dwell_s0 = s0, c.dwell_rise = rho;
    return refit_linear(spec, train, c, cur.u).rms_train;
  };
  const double rises[] = {0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0};
  double best = std::numeric_limits<double>::infinity(), best_s0 = c.dwell_s0,
         best_rho = c.dwell_rise;
  for (double m : {0.1, 0.2, 0.4, 0.7, 1.0, 2.0, 4.0, 8.0})
    for (double rho : rises)
      if (const double r = cost(m * c.x_ba, rho); r < best)
        best = r, best_s0 = m * c.x_ba, best_rho = rho;
  const auto [lr, fr] = golden_section(std::log(best_rho / 3.0), std::log(best_rho * 3.0), 10, 0.0,
                                       [&](double l) { return cost(best_s0, std::exp(l)); });
  c.dwell_s0 = best_s0;
  c.dwell_rise = fr < best ? std::exp(lr) : best_rho;
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
  const auto [xr, fr] = golden_section(a, b, 20, 1e-4 * std::abs(grid[bi]), cost);
  c.*field = fr < best ? xr : grid[bi];
}

// A scalar that trades off against the shape (a softer presliding shape mimics a lost motion, so
// a linear refit at the shape of one value prefers values near it): golden section on log v
// between v0 / 5 and 5 v0 (the coarse grid's neighbours), each value scored by a short shape
// refit warm-started from the best shape so far. Sets c.*field and `best` to the best value's fit.
void refine_with_shape(const FitSpec& spec, const Dataset& train, EffectContext& c,
                       double EffectContext::*field, double v0, const FitOptions& fo,
                       std::optional<FitResult>& best) {
  FitOptions so = fo;
  so.max_evaluations = std::min(fo.max_evaluations, 80);
  double best_v = v0;
  auto cost = [&](double lv) {
    EffectContext cv = c;
    cv.*field = std::exp(lv);
    FitResult f = fit_model(spec, train, cv, so, &best->u);
    const double r = f.rms_train;
    if (r < best->rms_train) best_v = cv.*field, best = std::move(f);
    return r;
  };
  golden_section(std::log(v0 / 5), std::log(v0 * 5), 8, 0.0, cost);
  c.*field = best_v;
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
    if (e == Effect::Backlash) {
      refine_with_shape(spec, train, c, field, bv, fo, bf);
    } else {
      std::vector<double> grid;  // fine grid within the neighbours of the best coarse value
      for (double m : {0.4, 0.55, 0.75, 0.9, 1.0, 1.12, 1.3, 1.6, 2.0}) grid.push_back(bv * m);
      tune_scalar(*bf, train, c, e, field, grid);
    }
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
  // The lost motion from a hundredth of the break-away displacement (x_ba, estimated after
  // reversals, follows the softest elements; a play can be far below it) to five times it or a
  // tenth of the stroke, whichever is longer (a play larger than the break-away widens the swing
  // that x_ba is read from, and x_ba is a poor guide there): geometric grids, coarse by 5x for
  // the shape refits, fine by 1.6x for the linear refits.
  const double b_lo = 0.01 * c.x_ba, b_hi = std::max(5.0 * c.x_ba, 0.2 * c.x_half);
  auto geometric = [&](double ratio) {
    std::vector<double> g;
    for (double b = b_lo; b < b_hi * ratio; b *= ratio) g.push_back(std::min(b, b_hi));
    return g;
  };
  run(Effect::Backlash, &EffectContext::backlash, geometric(5.0), geometric(1.6));
  return shapes;
}

// One round of the loop (loop.hpp, steps 2 and 3): the context tuned to the current residual,
// every applicable catalog effect screened, the most promising refitted and judged, the best
// kept one added.
class RoundRun {
 public:
  RoundRun(LoopState& s, int round)
      : s_(s), o_(s.o), train_(s.train()), val_(s.val()), round_(round),
        refit_o_(serialised_progress(s.o.refit)), stage_("round " + std::to_string(round) + ": "),
        n_val_(static_cast<double>(std::max<std::size_t>(1, s.val().used()))) {}

  std::optional<Candidate> screening_only(double z_crit) {
    tune_context();
    screen_candidates(false);
    for (const auto& k : rd_.candidates)  // sorted by their screening validation RMS
      if (k.screen_z >= z_crit && k.screen_rms_validation < s_.cur_val) return k;
    return std::nullopt;
  }

  bool run() {
    rd_.rms_train_before = s_.cur.rms_train;
    rd_.rms_validation_before = s_.cur_val;
    tune_context();
    screen_candidates();
    start_fits_ahead();
    try_candidates();
    try_by_training_residual();
    if (best_) add_best();
    rd_.rms_train_after = s_.cur.rms_train;
    rd_.rms_validation_after = s_.cur_val;
    s_.control.reset();  // made for this round's starting model only
    const bool added = rd_.added.has_value();
    s_.rep.rounds.push_back(std::move(rd_));
    return added;
  }

 private:
  // The residual at the current model, the ripple wavelengths, the dwell decay length, the
  // viscous share and the channel effects' scalars.
  void tune_context() {
    FitResult& cur = s_.cur;
    EffectContext& c = s_.c;
    r_ = residual(cur, train_, c);
    r_val_ = residual(cur, val_, c);
    g_ = unit_friction(cur, train_, c);
    // The ripple search on all samples: the shortest wavelength it can resolve is 3 position steps.
    rs_ = s_.every > 1 ? ripple_search(s_.full(), c, residual(cur, s_.full(), c), unit_friction(cur, s_.full(), c))
                       : ripple_search(train_, c, r_, g_);
    if (round_ == 1) s_.rep.ripples = rs_;
    if (!contains(cur.spec.effects, Effect::PositionPeriodic)) {
      c.wavelengths.clear();
      for (const auto& p : rs_.peaks) c.wavelengths.push_back(p.wavelength);
      if (c.wavelengths.size() > 3) c.wavelengths.resize(3);
    }
    if (!contains(cur.spec.effects, Effect::DwellStiction) && effect_applicable(Effect::DwellStiction, train_, c))
      choose_dwell_shape(cur, train_, c);
    for (const auto& t : cur.terms)  // the viscous share the channel effects carry along
      if (t.effect == "base" && t.name == "sigma2" && !cur.theta.empty() && cur.theta[0] > 0)
        c.viscous_ratio = t.value / cur.theta[0];
    shapes_ = tune_measurement_effects(cur, train_, c, o_.candidates, false, o_.refit);
  }

  const std::vector<double>* shape_of(Effect e) const {
    const auto it = shapes_.find(e);
    return it == shapes_.end() ? &s_.cur.u : &it->second;
  }

  // deep: where no screening comes near the floor, the channel effects' scalars are searched
  // again with shape refits and those effects screened at their own shapes.
  void screen_candidates(bool deep = true) {
    const FitResult& cur = s_.cur;
    EffectContext& c = s_.c;
    double best_val = s_.cur_val;
    for (Effect e : o_.candidates) {
      if (contains(cur.spec.effects, e) || !effect_applicable(e, train_, c)) continue;
      if (o_.base.cancel && o_.base.cancel->load()) throw Cancelled();
      Candidate k = screen(e, cur, train_, val_, c, shape_of(e), &r_val_);
      k.evidence = evidence(e, cur, c);
      best_val = std::min(best_val, k.screen_rms_validation);
      rd_.candidates.push_back(std::move(k));
      ++screened_;
    }
    // No screened effect brings the validation error near the noise: the channel effects, which
    // the current shape partly mimics, get shape refits in their scalar search and are screened
    // again at their own shapes.
    if (deep && s_.floor > 0 && best_val > 1.15 * s_.floor) {
      shapes_ = tune_measurement_effects(cur, train_, c, o_.candidates, true, o_.refit, &s_.deep_done);
      for (auto& k : rd_.candidates)
        if (shapes_.count(k.effect)) {
          Candidate k2 = screen(k.effect, cur, train_, val_, c, shape_of(k.effect), &r_val_);
          k2.evidence = evidence(k.effect, cur, c);
          k = std::move(k2);
        }
    }
    // Most promising first: the lowest validation RMS of the screening fit (held-out data decides
    // between effects that look alike on the training record, e.g. offset and a level asymmetry).
    std::stable_sort(rd_.candidates.begin(), rd_.candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.screen_rms_validation < b.screen_rms_validation;
    });
  }

  // What the report shows of the candidate (evidence.hpp); backlash with the current model along
  // the contact's motion through the dead band of the tuned lost motion.
  nlohmann::json evidence(Effect e, const FitResult& cur, const EffectContext& c) const {
    if (e != Effect::Backlash) return effect_evidence(e, train_, c, r_, g_, rs_);
    const auto gb = unit_friction(cur, through_dead_band(train_, c.backlash), c);
    return effect_evidence(e, train_, c, r_, g_, rs_, &gb);
  }

  // Worth a refit at all: explains something of the training residual and hints at a lower
  // validation RMS.
  bool worth_a_refit(const Candidate& k) const {
    return k.explained >= o_.min_explained && k.screen_rms_validation < s_.cur_val;
  }

  std::future<FitResult> fit_ahead(FitSpec spec, std::vector<double> warm, std::string stage) const {
    FitOptions fo = refit_o_;
    fo.stage = std::move(stage);
    return std::async(std::launch::async, [&train = train_, spec = std::move(spec), warm = std::move(warm),
                                           fo = std::move(fo), cc = s_.c] { return fit_model(spec, train, cc, fo, &warm); });
  }

  // Fits ahead, for wall time only: the round's first candidate the filters let through, the
  // control refit when that candidate's screening already passes the gain, and the next
  // candidate when it screens within 1.5x of the first, each started at once on its own threads.
  // A fit is a pure function of its inputs (taken by value here), so the numbers and decisions
  // are those of fitting when needed; a fit started for nothing costs time, not results. All
  // fits of the round share one progress lock.
  void start_fits_ahead() {
    std::vector<const Candidate*> next;
    for (const auto& k : rd_.candidates) {
      if (next.size() == 2) break;
      if (!worth_a_refit(k)) continue;
      if (!next.empty() && k.screen_rms_validation > 1.5 * next.front()->screen_rms_validation) break;
      next.push_back(&k);
    }
    for (const Candidate* k : next)
      ahead_.emplace(k->effect, fit_ahead(with(s_.cur.spec, k->effect), *shape_of(k->effect),
                                          stage_ + "refit with " + std::string(effect_name(k->effect))));
    if (!next.empty() && next.front()->screen_rms_validation <= (1.0 - o_.min_gain) * s_.cur_val &&
        !s_.control)
      ahead_control_ = fit_ahead(s_.cur.spec, s_.cur.u, stage_ + "control refit without a new effect");
  }

  // Whether the current model lags along the sampled path: a refit with inertia whose mass comes
  // out negative (-M a is what a model half a step late leaves). Its validation RMS, once per
  // round (from the round's inertia attempt when there is one).
  std::optional<double> lagging_model_fit() {
    if (lag_done_) return lag_val_;
    lag_done_ = true;
    if (contains(s_.cur.spec.effects, Effect::Inertia)) return lag_val_;
    auto negative = [](const std::vector<LinearTerm>& ts) {
      return std::any_of(ts.begin(), ts.end(), [](const LinearTerm& t) { return t.name == "M" && t.value < 0; });
    };
    for (const auto& x : rd_.attempts)
      if (x.effect == Effect::Inertia) {
        if (negative(x.terms)) lag_val_ = x.rms_validation;
        return lag_val_;
      }
    FitOptions fo = refit_o_;
    fo.stage = stage_ + "inertia refit (does the model lag along the sampled path?)";
    const FitResult f = fit_model(with(s_.cur.spec, Effect::Inertia), train_, s_.c, fo, &s_.cur.u);
    if (negative(terms_of(f, Effect::Inertia))) lag_val_ = rms_on(f, val_, s_.c);
    return lag_val_;
  }

  // Control: the current model refitted with the same budget and starts. What it gains is
  // optimisation, not the effect; the effect must beat it by the same margin.
  void control_refit(const FitOptions& fo) {
    control_done_ = true;
    FitOptions co = fo;
    co.stage = stage_ + "control refit without a new effect";
    FitResult ctrl = s_.control       ? std::move(*s_.control)
                     : ahead_control_ ? ahead_control_->get()
                                      : fit_model(s_.cur.spec, train_, s_.c, co, &s_.cur.u);
    s_.control.reset();
    if (ctrl.rms_train < s_.cur.rms_train) {
      s_.cur = std::move(ctrl);
      s_.cur_val = rms_on(s_.cur, val_, s_.c);
      s_.rep.stages.back() = s_.cur;
      if (round_ == 1) s_.rep.rms_before_train = s_.cur.rms_train, s_.rep.rms_before_validation = s_.cur_val;
      rd_.rms_train_before = s_.cur.rms_train;
      rd_.rms_validation_before = s_.cur_val;
    }
  }

  // The verdict on an attempt that lowered the validation RMS enough; returns whether a guard
  // refused it (the effect cannot be what the refit found).
  // `f`: the refit with the effect (its sampling share is what the lag guard compares with).
  bool judge(Attempt& a, const Candidate& k, const FitResult& f) {
    // BIC on the validation record: n ln(SSR / n) + p ln n with the effect's columns.
    a.bic_change = n_val_ * std::log(std::pow(a.rms_validation / std::max(s_.cur_val, 1e-300), 2)) +
                   static_cast<double>(k.columns) * std::log(n_val_);
    // The floor is an estimate; a model that predicts the held-out record better than it shows
    // it lower (e.g. a sampling share taken from a base fit that bent to the missing effect).
    const double fl = std::min(s_.floor, a.rms_validation);
    const bool big = fl <= 0 || a.size >= o_.min_size * fl;
    bool guarded = false;
    const bool signature = k.p_value * static_cast<double>(screened_) <= o_.max_p;
    if (!a.kept) a.verdict = "validation RMS not lowered by " + std::to_string(o_.min_gain * 100).substr(0, 4) + " %";
    else if (!signature) a.kept = false, a.verdict = "no signature in the training residual (F-test)";
    else if (a.bic_change >= 0) a.kept = false, a.verdict = "validation BIC not lowered";
    else if (!big) a.kept = false, guarded = true, a.verdict = "contribution below " + std::to_string(o_.min_size).substr(0, 4) + " x the noise floor";
    else if (fl > 0 && a.size < o_.sure_size * fl) {
      // A small contribution must explain a good share of what lies above the floor.
      const double e0 = s_.cur_val * s_.cur_val - fl * fl, e1 = a.rms_validation * a.rms_validation - fl * fl;
      if (!(e0 > 0) || (e0 - e1) / e0 < o_.min_excess)
        a.kept = false, guarded = true, a.verdict = "small (below " + std::to_string(o_.sure_size).substr(0, 3) +
                                    " x the floor) and explains less than " + std::to_string(o_.min_excess).substr(0, 4) +
                                    " of the validation error above the floor";
    }
    if (a.kept) {  // terms that cannot be the effect: a negative mass, a backlash level far from Fc
      if (const std::string why = unphysical(f.terms, k.effect); !why.empty())
        a.kept = false, guarded = true, a.verdict = why;
    }
    const bool lag_like = k.effect == Effect::Inertia || k.effect == Effect::TimeShift ||
                          k.effect == Effect::SensorFilter;
    if (const double sampling = a.kept && lag_like ? sampling_through(f, k.effect) : 0.0;
        a.size < 1.5 * sampling) {
      // Lag-like effects (a force leading or lagging the motion) are what the unmeasured path
      // between samples also changes: below 1.5 x that share along the effect's contribution
      // they cannot be told from it, and the loop says so instead of naming one.
      a.kept = false, guarded = true;
      a.verdict = "contribution " + std::to_string(a.size) +
                  " N is within 1.5 x what the path between samples "
                  "changes (" +
                  std::to_string(sampling) + " N): cannot be told from the sampling";
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
    return guarded;
  }

  // The sampling share (structure.hpp, add_sampling) through f on the whole training record (as
  // the floor's), at most the floor's: that comes through a base fit that may have bent to the
  // missing effect, and then overstates what the path between samples changes. Of the path's
  // change only the part along effect e's contribution u can pass for the effect: the share is
  // that projection's RMS, (<df, u> / <u, u>) u with df the cubic less the straight path's
  // friction, over sqrt(3) as the share (the path anywhere between the two), at most the share.
  double sampling_through(const FitResult& f, Effect e) const {
    NoiseEstimate est;
    const Dataset& d = s_.full();
    const auto fc = s_.friction_force(f, d), fs = s_.friction_force(f, d, true);
    add_sampling(est, d, fc, fs);
    const auto u = contribution(f, e, d, s_.c);
    double du = 0.0, uu = 0.0, n = 0.0;
    for (std::size_t k = 0; k < d.size(); ++k)
      if (d.use[k]) du += (fc[k] - fs[k]) * u[k], uu += u[k] * u[k], n += 1.0;
    const double along = uu > 0.0 && n > 0.0 ? std::abs(du) / std::sqrt(uu * n * 3.0) : 0.0;
    return std::min({along, est.sampling, s_.rep.noise.sampling});
  }

  // Refits one candidate with its effect and judges it; returns false when a guard said the
  // effect cannot be what the refit found (too small, a negative mass, within the sampling):
  // such an attempt does not use up one of the round's tries.
  bool attempt(const Candidate& k) {
    FitOptions fo = refit_o_;
    fo.stage = stage_ + "refit with " + std::string(effect_name(k.effect));
    const auto started = ahead_.find(k.effect);
    FitResult f = started != ahead_.end() ? started->second.get()
                                          : fit_model(with(s_.cur.spec, k.effect), train_, s_.c, fo, shape_of(k.effect));
    Attempt a;
    a.effect = k.effect, a.rms_train = f.rms_train, a.rms_validation = rms_on(f, val_, s_.c);
    a.terms = terms_of(f, k.effect);
    a.size = contribution_rms(f, k.effect, train_, s_.c);
    a.kept = a.rms_validation <= (1.0 - o_.min_gain) * s_.cur_val;
    if (a.kept && !control_done_) {
      control_refit(fo);
      a.kept = a.rms_validation <= (1.0 - o_.min_gain) * s_.cur_val;
    }
    const bool guarded = judge(a, k, f);
    rd_.attempts.push_back(a);
    if (a.kept && (!best_ || a.rms_validation < best_->second.rms_validation)) best_.emplace(std::move(f), a);
    return !guarded;
  }

  bool attempted(Effect e) const {
    return std::any_of(rd_.attempts.begin(), rd_.attempts.end(), [e](const Attempt& a) { return a.effect == e; });
  }

  void try_candidates() {
    const int max_attempts = 2 * o_.tries_per_round;
    int tries = 0;
    for (const auto& k : rd_.candidates) {
      if (tries >= o_.tries_per_round || static_cast<int>(rd_.attempts.size()) >= max_attempts) break;
      if (!worth_a_refit(k)) continue;
      // Far behind an effect already kept: a refit lowers the screening RMS, but not by half.
      if (best_ && k.screen_rms_validation > 1.5 * best_->second.rms_validation) continue;
      // A close second is tried too once one is kept; otherwise the first kept ends the round.
      if (attempt(k)) ++tries;
    }
  }

  // Nothing kept while the model stays well above the floor: the current shape may have bent
  // to the missing effect, so that its screening at that shape shows no validation gain (a
  // quadratic drag taken up by the Stribeck curve, a level asymmetry by the elements). The
  // candidates that explain most of the *training* residual get a refit too (shape included).
  void try_by_training_residual() {
    if (best_ || !(s_.floor > 0) || !(s_.cur_val > o_.refit_above_floor * s_.floor)) return;
    const int max_attempts = 2 * o_.tries_per_round;
    std::vector<const Candidate*> by_train;
    for (const auto& k : rd_.candidates)
      if (!attempted(k.effect) && k.explained >= o_.min_explained &&
          k.p_value * static_cast<double>(screened_) <= o_.max_p && k.screen_rms_train < rd_.rms_train_before)
        by_train.push_back(&k);
    std::stable_sort(by_train.begin(), by_train.end(), [](const Candidate* a, const Candidate* b) {
      return a->screen_rms_train < b->screen_rms_train;
    });
    int more = 0;
    for (const Candidate* k : by_train) {
      if (more >= o_.train_tries || static_cast<int>(rd_.attempts.size()) >= max_attempts + o_.train_tries) break;
      if (attempt(*k)) ++more;
    }
  }

  // The best kept attempt, polished, becomes the current model.
  void add_best() {
    auto& [f, a] = *best_;
    for (auto& x : rd_.attempts) x.kept = x.effect == a.effect && x.kept;
    for (auto& x : rd_.attempts)
      if (!x.kept && x.verdict.rfind("kept", 0) == 0) x.verdict = "passed, but " + std::string(effect_name(a.effect)) + " explains more";
    FitOptions po = o_.refit;  // polish the kept model before the next round screens against it
    po.starts = 1;
    po.data_start = false;
    po.stage = "round " + std::to_string(round_) + ": polish";
    FitResult p = fit_model(f.spec, train_, s_.c, po, &f.u);
    if (p.rms_train < f.rms_train) {
      f = std::move(p);
      for (auto& x : rd_.attempts)
        if (x.effect == a.effect) {
          x.rms_train = f.rms_train;
          x.rms_validation = rms_on(f, val_, s_.c);
          x.terms = terms_of(f, a.effect);
          a = x;
        }
    }
    s_.cur = f;
    s_.cur_val = a.rms_validation;
    rd_.added = a.effect;
    s_.rep.stages.push_back(s_.cur);
    s_.rep.effects_added.push_back(a.effect);
    // Effects that fit the data alike: said, not hidden.
    for (const auto& x : rd_.attempts)
      if (x.effect != a.effect && x.rms_validation <= a.rms_validation * 1.005 && x.verdict.rfind("passed", 0) == 0)
        s_.rep.notes.push_back("round " + std::to_string(round_) + ": " + std::string(effect_name(a.effect)) + " and " +
                               std::string(effect_name(x.effect)) +
                               " fit the validation record alike (within 0.5 %); the data cannot tell them apart");
  }

  LoopState& s_;
  const LoopOptions& o_;
  const Dataset& train_;
  const Dataset& val_;
  const int round_;
  const FitOptions refit_o_;
  const std::string stage_;
  const double n_val_;
  Round rd_;
  std::vector<double> r_, g_;  // the training residual and unit friction at the current model
  std::vector<double> r_val_;  // the validation residual at the current model
  RippleSearch rs_;
  std::map<Effect, std::vector<double>> shapes_;  // the channel effects' warm starts
  std::size_t screened_ = 0;
  bool control_done_ = false;
  std::optional<std::pair<FitResult, Attempt>> best_;
  std::map<Effect, std::future<FitResult>> ahead_;
  std::optional<std::future<FitResult>> ahead_control_;
  bool lag_done_ = false;
  std::optional<double> lag_val_;
};

}  // namespace

bool run_round(LoopState& s, int round) { return RoundRun(s, round).run(); }

std::optional<Candidate> screening_resolves(LoopState& s, double z_crit) {
  const EffectContext c = s.c;
  const std::set<Effect> deep = s.deep_done;
  const RippleSearch ripples = s.rep.ripples;
  std::optional<Candidate> k = RoundRun(s, 1).screening_only(z_crit);
  s.c = c;
  s.deep_done = deep;
  s.rep.ripples = ripples;
  return k;
}

}  // namespace gmslab::ident::detail
