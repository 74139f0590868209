#include "core/ident/fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <nlopt.hpp>
#include <random>

#include "core/error.hpp"
#include "core/friction/gms_path.hpp"
#include "core/ident/element_fit.hpp"
#include "core/ident/parallel.hpp"

namespace gmslab::ident {

// ------------------------------------------------------------------------------------------------
// Parameterization
// ------------------------------------------------------------------------------------------------

namespace {

bool force_like(std::string_view unit) { return unit.find('N') != std::string_view::npos; }

// Bounds of a shape parameter from its unit (values relative to a unit force level).
ShapeParam shape_for(const ParamSpec& s, double def, double def_ref, const EffectContext& c) {
  ShapeParam p;
  p.name = std::string(s.key);
  p.log = true;
  const std::string_view u = s.unit;
  if (u == "N") {
    if (s.key == "Fs") {
      p.name = "Fs/Fc", p.unit = "-", p.lo = 1.0, p.hi = c.fs_hi_factor, p.init = 1.3;
    } else {
      p.name += "/Fref", p.unit = "-";
      p.init = def_ref > 0 && def > 0 ? def / def_ref : 1.0;
      p.lo = p.init / 10, p.hi = p.init * 10;
    }
  } else if (u == "N/m") {
    p.name += "/Fc", p.unit = "1/m", p.init = 1.0 / c.x_ba, p.lo = p.init / 300, p.hi = p.init * 300;
  } else if (u == "N/s") {
    p.name += "/Fc", p.unit = "1/s", p.init = 50.0, p.lo = 0.5, p.hi = 1e5;
  } else if (u == "N s/m") {
    p.name += "/Fc", p.unit = "s/m";
    p.init = def_ref > 0 && def > 0 ? def / def_ref : 1.0 / c.v_ref;
    p.lo = p.init / 1e3, p.hi = p.init * 1e3;
  } else if (u == "m/s") {
    p.unit = "m/s", p.init = 0.1 * c.v_ref, p.lo = 1e-4 * c.v_ref, p.hi = c.vs_hi_factor * c.v_ref;
  } else if (u == "m") {
    p.unit = "m", p.init = 0.3 * c.x_ba, p.lo = p.init / 100, p.hi = p.init * 100;
  } else {
    p.unit = std::string(u);
    p.log = false;
    p.lo = s.lo + (s.lo_open ? 1e-3 * std::max(1.0, std::abs(s.lo)) : 0.0);
    p.hi = std::min(s.hi, p.lo + 10.0);
    p.init = std::clamp(def, p.lo, p.hi);
  }
  return p;
}

}  // namespace

Parameterization::Parameterization(const ModelInfo& info, std::size_t elements,
                                   const EffectContext& c)
    : info_(info), elements_(info.columns.empty() ? 0 : elements) {
  base_ = info.defaults();
  if (!info.columns.empty()) {
    if (elements_ < info.min_elements || elements_ > info.max_elements)
      throw InputError("--elements " + std::to_string(elements) + ": model '" +
                       std::string(info.tag) + "' accepts " + std::to_string(info.min_elements) +
                       " to " + std::to_string(info.max_elements) + " elements");
    const auto rows = base_.elements;
    base_.elements.assign(elements_, rows.empty() ? std::vector<double>(info.columns.size(), 0.0)
                                                  : rows.front());
  }
  ref_ = static_cast<int>(info.scalar_index("Fc"));
  for (std::size_t i = 0; ref_ < 0 && i < info.scalars.size(); ++i)
    if (info.scalars[i].unit == "N") ref_ = static_cast<int>(i);
  viscous_ = static_cast<int>(info.scalar_index("sigma2"));
  alpha_ = static_cast<int>(info.column_index("alpha"));
  const double def_ref = ref_ >= 0 ? base_.scalars[static_cast<std::size_t>(ref_)] : 1.0;
  for (std::size_t i = 0; i < info.scalars.size(); ++i) {
    const int ii = static_cast<int>(i);
    if (ii == ref_) { base_.scalars[i] = 1.0; continue; }
    if (ii == viscous_) { base_.scalars[i] = 0.0; continue; }
    auto p = shape_for(info.scalars[i], base_.scalars[i], def_ref, c);
    p.scalar = ii;
    params_.push_back(p);
  }
  // Element table. Without a reference scalar the first force-like cell of row 0 is the reference.
  int ref_col = -1;
  if (ref_ < 0)
    for (std::size_t j = 0; j < info.columns.size(); ++j)
      if (info.columns[j].unit == "N" && ref_col < 0) ref_col = static_cast<int>(j);
  // Element stiffnesses are searched as kappa = k / (element level) [1/m]: the inverse of the
  // element's break-away displacement at Fc, independent of its weight (element_fit.hpp); the
  // unit model multiplies by the normalised weight (GMS alpha) or the slip force (Maxwell-slip,
  // Leuven W). Bounds: the grid range of break-away displacements (element_fit.cpp).
  for (std::size_t j = 0; j < info.columns.size(); ++j) {
    if (info.columns[j].unit == "N/m") stiff_ = static_cast<int>(j);
    if (info.columns[j].unit == "N" && level_col_ < 0) level_col_ = static_cast<int>(j);
  }
  if (alpha_ >= 0) level_col_ = alpha_;
  const auto [x_lo, x_hi] = element_x_range(c);
  for (std::size_t r = 0; r < elements_; ++r) {
    // Element break-away displacements spread geometrically from 0.15 x_ba to x_ba.
    const double frac = elements_ > 1 ? static_cast<double>(elements_ - 1 - r) /
                                            (static_cast<double>(elements_) - 1)
                                      : 0.0;
    const double xr = 0.5 * c.x_ba * std::pow(0.15, frac);  // x_ba spans a full swing
    for (std::size_t j = 0; j < info.columns.size(); ++j) {
      const auto& s = info.columns[j];
      const int jj = static_cast<int>(j);
      auto& cell = base_.elements[r][j];
      if (jj == alpha_) {
        cell = 1.0;
        if (r == 0) continue;
        ShapeParam p{"w[" + std::to_string(r) + "]/w[0]", "-", 1e-3, 1e2, 1.0, true};
        p.row = static_cast<int>(r), p.column = jj;
        params_.push_back(p);
        continue;
      }
      if (s.key == "sigma") { cell = 0.0; continue; }
      if (jj == ref_col && r == 0) { cell = 1.0; continue; }
      auto p = shape_for(s, cell, def_ref, c);
      if (jj == stiff_) {
        p.unit = "1/m";
        p.init = std::clamp(1.0 / xr, 1.0 / x_hi, 1.0 / x_lo);
        p.lo = 1.0 / x_hi, p.hi = 1.0 / x_lo;
        p.name = "kappa[" + std::to_string(r) + "]";
      } else {
        if (s.unit == "N") p.init = 1.0, p.lo = 1e-3, p.hi = 1e2;
        p.name = std::string(s.key) + "[" + std::to_string(r) + "]" +
                 (force_like(s.unit) ? "/" + std::string(s.key) + "[0]" : "");
      }
      p.row = static_cast<int>(r), p.column = jj;
      params_.push_back(p);
    }
  }
}

std::pair<double, double> element_x_range(const EffectContext& c) {
  const double hi = std::max(c.x_hi_factor * c.x_ba, 1e-9);
  return {std::max(4e-4 * c.x_ba, 1e-10), hi};
}

double Parameterization::box(std::size_t i, double value) const {
  const auto& p = params_[i];
  const double u = p.log ? std::log(std::max(value, 1e-300) / p.lo) / std::log(p.hi / p.lo)
                         : (value - p.lo) / (p.hi - p.lo);
  return std::clamp(u, 0.0, 1.0);
}

double Parameterization::value(std::size_t i, double u) const {
  const auto& p = params_[i];
  u = std::clamp(u, 0.0, 1.0);
  return p.log ? p.lo * std::pow(p.hi / p.lo, u) : p.lo + (p.hi - p.lo) * u;
}

std::vector<double> Parameterization::initial() const {
  std::vector<double> u;
  for (std::size_t i = 0; i < params_.size(); ++i) u.push_back(box(i, params_[i].init));
  return u;
}

ModelParams Parameterization::unit_model(const std::vector<double>& u) const {
  ModelParams m = base_;
  for (std::size_t i = 0; i < params_.size(); ++i) {
    const auto& p = params_[i];
    const double v = value(i, u[i]);
    if (p.scalar >= 0) m.scalars[static_cast<std::size_t>(p.scalar)] = v;
    else m.elements[static_cast<std::size_t>(p.row)][static_cast<std::size_t>(p.column)] = v;
  }
  if (alpha_ >= 0) {
    double s = 0.0;
    for (const auto& row : m.elements) s += row[static_cast<std::size_t>(alpha_)];
    for (auto& row : m.elements) row[static_cast<std::size_t>(alpha_)] /= s;
  }
  if (stiff_ >= 0 && level_col_ >= 0)  // k = kappa x element level
    for (auto& row : m.elements)
      row[static_cast<std::size_t>(stiff_)] *= row[static_cast<std::size_t>(level_col_)];
  return m;
}

ModelParams Parameterization::physical(const std::vector<double>& u, double level,
                                       double viscous) const {
  ModelParams m = unit_model(u);
  for (std::size_t i = 0; i < m.scalars.size(); ++i)
    if (force_like(info_.scalars[i].unit)) m.scalars[i] *= level;
  for (auto& row : m.elements)
    for (std::size_t j = 0; j < row.size(); ++j)
      if (force_like(info_.columns[j].unit)) row[j] *= level;
  if (viscous_ >= 0) m.scalars[static_cast<std::size_t>(viscous_)] = std::max(0.0, viscous);
  return m;
}

// ------------------------------------------------------------------------------------------------
// Variable-projection cost
// ------------------------------------------------------------------------------------------------

void simulate_along(const FrictionModel& m, const Dataset& d, std::vector<double>& out) {
  std::vector<double> state(m.state_size());
  m.reset(state);
  out.assign(d.size(), 0.0);
  for (std::size_t k = 1; k < d.size(); ++k)
    for_each_step(d, k, [&](double v, double h) { out[k] = m.step(state, {v, h, 0.0, 0.0}); });
}

GmsPath gms_path(const Dataset& d) {
  GmsPath p;
  p.samples = 1;
  for (std::size_t k = 1; k < d.size(); ++k) {
    for_each_step(d, k, [&](double v, double h) { p.add_step(v, h); });
    p.end_sample();
  }
  if (d.size() == 0) p.samples = 0;
  return p;
}

void simulate_gms_along(const GmsParams& g, const GmsPath& p, GmsPathRunner& runner,
                        std::vector<double>& out) {
  out.assign(p.samples, 0.0);
  runner.prepare(g.S, g.C, p);
  std::vector<double> sk(g.k.size());
  for (std::size_t i = 0; i < sk.size(); ++i) sk[i] = g.sigma[i] / g.k[i];
  runner.run(p, g.alpha, g.k, sk, g.sigma2, {}, 1.0, nullptr, out);
}

namespace {

// Per step of `path` (gms_path(d)), the dwell weight phi e^(-s / s0) of the motion that started
// after the last rest (phi = ln(1 + T_d / c.dwell_tau), s0 = c.dwell_s0): s is the travel along
// the path's steps since the start, reversals included, so that a rise confined to the first
// micrometres fades within a sample's steps as it does along the motion. From the steps before the
// sample ahead of the start until the motion comes to rest again (as dwell_weight) or s / s0 > 30.
std::vector<double> dwell_weight_steps(const Dataset& d, const EffectContext& c,
                                       const GmsPath& path) {
  std::vector<double> w(path.v.size(), 0.0);
  const double still = standstill(c);
  for (const auto& s : motion_starts(d, c)) {
    const double phi = std::log(1.0 + s.dwell / c.dwell_tau);
    double travel = 0.0;
    bool far = false;
    for (std::size_t kk = std::max<std::size_t>(s.k, 2) - 1; kk < path.samples && !far; ++kk) {
      if (kk > s.k + 1 && std::abs(d.v[kk]) < still) break;  // at rest again
      for (std::size_t j = kk >= 2 ? path.last[kk - 2] : 0; j < path.last[kk - 1]; ++j) {
        travel += std::abs(path.v[j]) * path.h[j];
        const double q = travel / c.dwell_s0;
        if (q > 30.0) {
          far = true;
          break;
        }
        w[j] = phi * std::exp(-q);
      }
    }
  }
  return w;
}

struct Term {
  Column column;
  std::string effect;
};

std::vector<Term> design(const FitSpec& spec, const Parameterization& par) {
  std::vector<Term> t;
  t.push_back({{"Fc", "N", true,
                [](const Dataset&, const EffectContext&, std::span<const double> g,
                   std::span<double> o) { std::copy_n(g.begin(), o.size(), o.begin()); }},
               "base"});
  if (par.has_viscous())
    t.push_back({{"sigma2", "N s/m", false,
                  [](const Dataset& d, const EffectContext&, std::span<const double>,
                     std::span<double> o) { std::copy(d.v.begin(), d.v.end(), o.begin()); }},
                 "base"});
  for (Effect e : spec.effects)
    for (auto& c : effect_columns(e)) t.push_back({std::move(c), std::string(effect_name(e))});
  return t;
}

// Weighted LS of y on columns (fixed part precomputed), cost = RMS over used samples.
class Evaluator {
 public:
  Evaluator(const FitSpec& spec, const Parameterization& par, const Dataset& d,
            const EffectContext& c)
      : spec_(spec),
        par_(par),
        d_(d),
        c_(c),
        terms_(design(spec, par)),
        extras_(extra_outputs(spec.effects)) {
    for (std::size_t k = 0; k < d.size(); ++k)
      if (d.use[k]) rows_.push_back(k);
    const auto nu = static_cast<Eigen::Index>(rows_.size());
    y_.resize(nu);
    for (Eigen::Index i = 0; i < nu; ++i) y_(i) = d.F[rows_[static_cast<std::size_t>(i)]];
    yy_ = y_.squaredNorm();
    for (std::size_t j = 0; j < terms_.size(); ++j) (terms_[j].column.uses_g ? dyn_ : fix_).push_back(j);
    Af_.resize(nu, static_cast<Eigen::Index>(fix_.size()));
    std::vector<double> full(d.size());
    for (std::size_t j = 0; j < fix_.size(); ++j) {
      terms_[fix_[j]].column.fill(d, c, {}, full);
      gather(full, Af_.col(static_cast<Eigen::Index>(j)));
    }
    Gff_ = Af_.transpose() * Af_;
    bf_ = Af_.transpose() * y_;
    Ad_.resize(nu, static_cast<Eigen::Index>(dyn_.size()));
  }

  const std::vector<Term>& terms() const { return terms_; }
  double null_rms() const { return std::sqrt(yy_ / static_cast<double>(rows_.size())); }

  // Simulates g for shape u; false when the model cannot be built or diverges. g then carries the
  // extra outputs the spec's effects take, n values each in extra_outputs order (effects.hpp): the
  // dwell response, the model along the motion tau earlier, the model along the contact's motion
  // through the dead band.
  bool simulate(const std::vector<double>& u, std::vector<double>& g) const {
    try {
      auto mp = par_.unit_model(u);
      sim(mp, d_, path_, runner_, g);
      for (ExtraOutput x : extras_) switch (x) {
          case ExtraOutput::Dwell: {  // first in extras_: g holds the unit output alone here
            std::vector<double> g2;
            dwell_response(mp, g, g2);
            g.insert(g.end(), g2.begin(), g2.end());
            break;
          }
          case ExtraOutput::Shifted:
            along(mp, shifted_, c_.time_shift, &shifted_motion, g);
            break;
          case ExtraOutput::Contact:
            along(mp, contact_, c_.backlash, &through_dead_band, g);
            break;
          case ExtraOutput::None:
            break;
        }
    } catch (const InputError&) {  // a shape the model rejects (e.g. W sum below Fs): a bad point
      return false;
    } catch (const SimulationError&) {
      return false;
    }
    for (double x : g)
      if (!std::isfinite(x)) return false;
    return true;
  }

  // Cost for shape u: RMS [N]; theta in term order.
  double cost(const std::vector<double>& u, Eigen::VectorXd* theta = nullptr) {
    if (!simulate(u, g_)) return bad();
    return solve(theta);
  }

  double solve(Eigen::VectorXd* theta) {
    std::vector<double> full(d_.size());
    for (std::size_t j = 0; j < dyn_.size(); ++j) {
      const Column& col = terms_[dyn_[j]].column;
      col.fill(d_, c_, column_input(col, g_, d_.size(), extras_, scratch_), full);
      gather(full, Ad_.col(static_cast<Eigen::Index>(j)));
    }
    const auto pd = static_cast<Eigen::Index>(dyn_.size());
    const auto pf = static_cast<Eigen::Index>(fix_.size());
    const Eigen::Index p = pd + pf;
    Eigen::MatrixXd G(p, p);
    Eigen::VectorXd b(p);
    G.topLeftCorner(pd, pd) = Ad_.transpose() * Ad_;
    G.topRightCorner(pd, pf) = Ad_.transpose() * Af_;
    G.bottomLeftCorner(pf, pd) = G.topRightCorner(pd, pf).transpose();
    G.bottomRightCorner(pf, pf) = Gff_;
    b.head(pd) = Ad_.transpose() * y_;
    b.tail(pf) = bf_;
    Eigen::VectorXd s = G.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    Eigen::MatrixXd Gs = s.asDiagonal() * G * s.asDiagonal();
    Gs.diagonal().array() += 1e-12;
    Eigen::VectorXd z = Gs.ldlt().solve(s.asDiagonal() * b);
    Eigen::VectorXd th_internal = s.asDiagonal() * z;
    const double sse = yy_ - 2 * th_internal.dot(b) + th_internal.dot(G * th_internal);
    Eigen::VectorXd th(p);
    for (Eigen::Index j = 0; j < pd; ++j) th(static_cast<Eigen::Index>(dyn_[static_cast<std::size_t>(j)])) = th_internal(j);
    for (Eigen::Index j = 0; j < pf; ++j) th(static_cast<Eigen::Index>(fix_[static_cast<std::size_t>(j)])) = th_internal(pd + j);
    if (theta) *theta = th;
    if (!th.allFinite() || !(th(0) > 0)) return bad();  // the force level must be positive
    return std::sqrt(std::max(0.0, sse) / static_cast<double>(rows_.size()));
  }

  // The residual y - A theta on the used samples after cost(u, &theta) (its columns at u), with
  // the terms in their order; false after a bad point.
  bool residual_after_cost(const Eigen::VectorXd& theta, Eigen::VectorXd& r) const {
    if (theta.size() != static_cast<Eigen::Index>(terms_.size())) return false;
    r = y_;
    for (std::size_t j = 0; j < fix_.size(); ++j)
      r -= theta(static_cast<Eigen::Index>(fix_[j])) * Af_.col(static_cast<Eigen::Index>(j));
    for (std::size_t j = 0; j < dyn_.size(); ++j)
      r -= theta(static_cast<Eigen::Index>(dyn_[j])) * Ad_.col(static_cast<Eigen::Index>(j));
    return r.allFinite();
  }

  // Prediction on every sample for shape u and coefficients theta.
  std::vector<double> predict(const std::vector<double>& u, const std::vector<double>& theta) {
    std::vector<double> out(d_.size(), 0.0), full(d_.size());
    if (!simulate(u, g_)) g_.assign((1 + extras_.size()) * d_.size(), 0.0);
    for (std::size_t j = 0; j < terms_.size(); ++j) {
      const Column& col = terms_[j].column;
      col.fill(d_, c_,
               col.uses_g ? column_input(col, g_, d_.size(), extras_, scratch_)
                          : std::span<const double>{},
               full);
      for (std::size_t k = 0; k < d_.size(); ++k) out[k] += theta[j] * full[k];
    }
    return out;
  }

 private:
  double bad() const { return 2.0 * null_rms() + 1.0; }
  // The model along record d: GMS through the path runner (d's path built at the first GMS
  // simulation), other models step by step.
  static void sim(const ModelParams& mp, const Dataset& d, GmsPath& path, GmsPathRunner& runner,
                  std::vector<double>& out) {
    const auto model = build_model(mp);  // validates the parameters (throws on a bad shape)
    if (mp.model != "gms") return simulate_along(*model, d, out);
    if (path.samples != d.size()) path = gms_path(d);
    simulate_gms_along(GmsParams::from(mp), path, runner, out);
  }
  // The model with its break-away ratio Fs/Fc raised by rho w (rho = c.dwell_rise), less the
  // model g: GMS along the path with the raised level per step of the path (w =
  // dwell_weight_steps); other models with Fs the linearised response (a 1 % difference) times
  // the rise per sample (w = dwell_weight); models without Fs the rise times g.
  void dwell_response(ModelParams mp, const std::vector<double>& g,
                      std::vector<double>& out) const {
    const std::size_t n = d_.size();
    const auto fs = model_info(mp.model).scalar_index("Fs");
    if (mp.model != "gms" && (dwell_w_.size() != n || dwell_w_s0_ != c_.dwell_s0))
      dwell_w_ = dwell_weight(d_, c_), dwell_w_s0_ = c_.dwell_s0;
    if (mp.model == "gms") {
      const GmsParams gp = GmsParams::from(mp);
      if (path_.samples != n) path_ = gms_path(d_);
      if (dwell_ws_.size() != path_.v.size() || dwell_ws_s0_ != c_.dwell_s0)
        dwell_ws_ = dwell_weight_steps(d_, c_, path_), dwell_ws_s0_ = c_.dwell_s0;
      std::vector<double> rise(dwell_ws_.size());
      for (std::size_t j = 0; j < rise.size(); ++j)
        rise[j] = c_.dwell_rise * gp.S.Fc * dwell_ws_[j];
      dwell_runner_.prepare_raised_steps(gp.S, gp.C, path_, rise);
      std::vector<double> sk(gp.k.size());
      for (std::size_t i = 0; i < sk.size(); ++i) sk[i] = gp.sigma[i] / gp.k[i];
      out.assign(n, 0.0);
      dwell_runner_.run(path_, gp.alpha, gp.k, sk, gp.sigma2, {}, 1.0, nullptr, out);
      for (std::size_t k = 0; k < n; ++k) out[k] -= g[k];
    } else if (fs >= 0) {
      const double ratio = mp.scalars[static_cast<std::size_t>(fs)];
      mp.scalars[static_cast<std::size_t>(fs)] = ratio * 1.01;
      sim(mp, d_, path_, runner_, out);
      for (std::size_t k = 0; k < n; ++k)
        out[k] = (out[k] - g[k]) / (0.01 * ratio) * c_.dwell_rise * dwell_w_[k];
    } else {
      out.assign(n, 0.0);
      for (std::size_t k = 0; k < n; ++k) out[k] = c_.dwell_rise * dwell_w_[k] * g[k];
    }
  }
  void gather(const std::vector<double>& full, Eigen::Ref<Eigen::VectorXd> out) const {
    for (std::size_t i = 0; i < rows_.size(); ++i) out(static_cast<Eigen::Index>(i)) = full[rows_[i]];
  }

  const FitSpec& spec_;
  const Parameterization& par_;
  const Dataset& d_;
  const EffectContext& c_;
  std::vector<Term> terms_;
  std::vector<std::size_t> rows_, fix_, dyn_;
  Eigen::VectorXd y_, bf_;
  Eigen::MatrixXd Af_, Ad_, Gff_;
  double yy_ = 0;
  std::vector<double> g_;
  std::vector<ExtraOutput> extras_;      // in the order simulate appends them to g
  mutable std::vector<double> scratch_;  // column_input's copy of g and an extra output
  mutable std::vector<double> dwell_w_;  // dwell_weight of d_, for the decay length dwell_w_s0_
  mutable double dwell_w_s0_ = 0.0;
  mutable std::vector<double> dwell_ws_;  // dwell_weight_steps along path_, for dwell_ws_s0_
  mutable double dwell_ws_s0_ = 0.0;
  mutable GmsPathRunner dwell_runner_;
  mutable GmsPath path_;
  mutable GmsPathRunner runner_;
  // The record's motion through a transmission (made by `make` for the scalar p) and the model's
  // path along it, made again when p changes.
  struct Motion {
    Dataset rec;
    double p = std::numeric_limits<double>::quiet_NaN();
    GmsPath path;
    GmsPathRunner runner;
  };
  // Appends the model mp along m's motion for p to g.
  void along(const ModelParams& mp, Motion& m, double p, Dataset (*make)(const Dataset&, double),
             std::vector<double>& g) const {
    if (!(m.p == p) || m.rec.size() != d_.size()) {
      m.rec = make(d_, p);
      m.path = GmsPath{};
      m.runner = GmsPathRunner{};  // a path made again in place: a fresh runner
      m.p = p;
    }
    std::vector<double> gm;
    sim(mp, m.rec, m.path, m.runner, gm);
    g.insert(g.end(), gm.begin(), gm.end());
  }
  mutable Motion contact_;  // behind the backlash dead band, b = c_.backlash
  mutable Motion shifted_;  // tau = c_.time_shift earlier (time_shift)
};

FitResult make_result(const FitSpec& spec, const Parameterization& par, const Evaluator& ev,
                      const std::vector<double>& u, const Eigen::VectorXd& th, double rms,
                      int evals) {
  FitResult r;
  r.spec = spec;
  r.u = u;
  r.theta.assign(th.data(), th.data() + th.size());
  for (std::size_t j = 0; j < ev.terms().size(); ++j) {
    const auto& t = ev.terms()[j];
    r.terms.push_back({t.effect, t.column.name, t.column.unit, r.theta[j]});
  }
  const double viscous = par.has_viscous() ? r.theta[1] : 0.0;
  r.friction = par.physical(u, std::max(r.theta[0], 1e-12), viscous);
  r.rms_train = rms;
  r.evaluations = evals;
  return r;
}

}  // namespace

FitResult polish_least_squares(const FitResult& f, const Dataset& train, const EffectContext& c,
                               int max_iterations, const FitOptions& o) {
  const Parameterization par(model_info(f.spec.model), f.spec.elements, c);
  const std::size_t p = par.size();
  if (p == 0 || f.u.size() != p) return f;
  Evaluator ev(f.spec, par, train, c);
  const double bad = 2.0 * ev.null_rms() + 1.0;
  int evals = 0;
  // The residual at u with the linear terms solved there; false at a bad point.
  auto residual = [&](const std::vector<double>& u, Eigen::VectorXd& r, Eigen::VectorXd& th) {
    if (o.stop_requested()) throw Cancelled();
    ++evals;
    return ev.cost(u, &th) < bad && ev.residual_after_cost(th, r);
  };
  std::vector<double> u = f.u;
  Eigen::VectorXd r, th;
  if (!residual(u, r, th)) return f;
  double sse = r.squaredNorm();
  double lambda = 1e-3;
  Eigen::MatrixXd J(r.size(), static_cast<Eigen::Index>(p));
  Eigen::VectorXd rj, tj;
  for (int it = 0; it < max_iterations; ++it) {
    // Forward differences in the unit box (backward at the upper end).
    for (std::size_t j = 0; j < p; ++j) {
      std::vector<double> w = u;
      const double step = u[j] + 1e-6 <= 1.0 ? 1e-6 : -1e-6;
      w[j] += step;
      if (residual(w, rj, tj))
        J.col(static_cast<Eigen::Index>(j)) = (rj - r) / step;
      else
        J.col(static_cast<Eigen::Index>(j)).setZero();
    }
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool moved = false;
    for (int tries = 0; tries < 8 && !moved; ++tries) {
      Eigen::MatrixXd Al = A;
      Al.diagonal() += lambda * A.diagonal() + Eigen::VectorXd::Constant(A.rows(), 1e-300);
      const Eigen::VectorXd step = -Al.ldlt().solve(g);
      std::vector<double> w = u;
      for (std::size_t j = 0; j < p; ++j)
        w[j] = std::clamp(u[j] + step(static_cast<Eigen::Index>(j)), 0.0, 1.0);
      if (step.allFinite() && residual(w, rj, tj) && rj.squaredNorm() < sse) {
        moved = true;
        // Converged when a step gains less than 1e-10 relative.
        const bool small = rj.squaredNorm() > (1.0 - 1e-10) * sse;
        u = std::move(w), r = rj, th = tj, sse = r.squaredNorm();
        lambda = std::max(1e-9, lambda / 5);
        if (small) it = max_iterations;
      } else {
        lambda *= 8;
      }
    }
    if (o.progress)
      o.progress({o.stage, evals, std::sqrt(sse / static_cast<double>(r.size())),
                  max_iterations * (static_cast<int>(p) + 8)});
    if (!moved) break;
  }
  if (!residual(u, r, th)) return f;  // the columns and the terms at the point kept
  const double rms = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
  if (!(rms < f.rms_train)) return f;
  return make_result(f.spec, par, ev, u, th, rms, f.evaluations + evals);
}

namespace {

nlopt::algorithm algorithm_of(const std::string& m) {
  if (m == "bobyqa") return nlopt::LN_BOBYQA;
  if (m == "sbplx") return nlopt::LN_SBPLX;
  if (m == "neldermead") return nlopt::LN_NELDERMEAD;
  throw InputError("--method '" + m + "': expected bobyqa, sbplx or neldermead");
}

}  // namespace

namespace {

// Element models whose effects do not multiply g: variable projection with the element weights
// linear (element_fit.hpp): over an element grid, or from the warm start. Empty where the model or
// its effects need the general shape search.
std::optional<FitResult> fit_by_elements(const FitSpec& spec, const Dataset& train,
                                         const EffectContext& c, const FitOptions& o,
                                         const std::vector<double>* warm) {
  if (!has_linear_elements(spec.model) || spec.elements <= 0) return std::nullopt;
  bool g_free = true;
  for (Effect e : spec.effects)
    for (const auto& col : effect_columns(e)) g_free &= !col.uses_g;
  if (!g_free) return std::nullopt;
  if (!warm) return fit_elements(spec, train, c, o);
  if (warm->size() != Parameterization(model_info(spec.model), spec.elements, c).size())
    return std::nullopt;
  // From the warm start, and with the element table chosen afresh on the grid at the warm shape:
  // a new effect can free the table from what it had bent itself into (e.g. a soft element
  // standing in for an offset).
  if (!o.data_start || o.polish_only) return polish_elements(spec, train, c, o, *warm);
  FitResult w, g;
  const FitOptions po = serialised_progress(o);
  run_both([&] { g = regrid_elements(spec, train, c, po, *warm); },
           [&] { w = polish_elements(spec, train, c, po, *warm); });
  const int evals = w.evaluations + g.evaluations;
  FitResult& best = g.rms_train < w.rms_train ? g : w;
  best.evaluations = evals;
  return best;
}

// Start points: the warm start (if any), the data-based guess, then jittered copies of the first.
std::vector<std::vector<double>> start_points(const Parameterization& par, const FitOptions& o,
                                              const std::vector<double>* warm, bool polish_only) {
  std::vector<std::vector<double>> starts;
  if (warm && warm->size() == par.size()) starts.push_back(*warm);
  if (starts.empty() || (o.data_start && !polish_only)) starts.push_back(par.initial());
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  while (!polish_only && static_cast<int>(starts.size()) < std::max(1, o.starts)) {
    auto x = starts.front();
    for (auto& xi : x) xi = std::clamp(xi + jitter(rng), 0.0, 1.0);
    starts.push_back(x);
  }
  return starts;
}

// One local search's outcome: the first best point it saw (as one shared search over all starts
// would keep it), its evaluations, whether it hit the time budget.
struct SearchRun {
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_u;
  int evals = 0;
  bool time_limited = false;
};

// The settings every local search of one fit shares.
struct SearchSettings {
  nlopt::algorithm alg;
  std::size_t n;
  const FitOptions* o;   // the caller's options (time budget, cancel)
  const FitOptions* so;  // with serialised progress
  std::chrono::steady_clock::time_point t_start;
  int max_evaluations, polish_evaluations, budget;
};

// One bounded local search (NLopt) on the unit box from x.
SearchRun local_search(const SearchSettings& ss, Evaluator& e, std::vector<double> x, bool polish,
                       const std::string& stage) {
  SearchRun run;
  const std::size_t n = ss.n;
  if (n == 0) return run;
  nlopt::opt opt(ss.alg, static_cast<unsigned>(n));
  if (ss.o->max_seconds > 0) {
    const double left =
        ss.o->max_seconds -
        std::chrono::duration<double>(std::chrono::steady_clock::now() - ss.t_start).count();
    if (left <= 0) {
      run.time_limited = true;
      return run;
    }
    opt.set_maxtime(left);
  }
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(polish ? ss.polish_evaluations : ss.max_evaluations);
  opt.set_ftol_rel(ss.o->rel_tol);
  opt.set_initial_step(std::vector<double>(n, polish ? 0.03 : 0.1));
  struct Ctx {
    Evaluator* ev;
    const FitOptions* o;
    SearchRun* run;
    int budget;
    const std::string* stage;
  } ctx{&e, ss.so, &run, ss.budget, &stage};
  opt.set_min_objective(
      [](const std::vector<double>& u, std::vector<double>&, void* p) -> double {
        auto& cx = *static_cast<Ctx*>(p);
        if (cx.o->stop_requested()) throw nlopt::forced_stop();
        const double f = cx.ev->cost(u);
        ++cx.run->evals;
        if (f < cx.run->best) cx.run->best = f, cx.run->best_u = u;
        if (cx.o->progress && cx.run->evals % 25 == 0)
          cx.o->progress({*cx.stage, cx.run->evals, cx.run->best, cx.budget});
        return f;
      },
      &ctx);
  double f = 0;
  try {
    if (opt.optimize(x, f) == nlopt::MAXTIME_REACHED) run.time_limited = true;
  } catch (const nlopt::forced_stop&) {
  } catch (const Error&) {
    throw;  // gmslab's typed errors (input, simulation, I/O, internal) are never swallowed
  } catch (const std::invalid_argument& e) {  // NLopt rejected the problem it was given: a bug here
    throw InternalError(std::string("fit: NLopt rejected the search's settings: ") + e.what());
  } catch (const std::runtime_error&) {  // roundoff-limited etc.: keep the best seen
  }
  if (ss.o->stop_requested()) throw Cancelled();
  return run;
}

}  // namespace

FitResult fit_model(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                    const FitOptions& o, const std::vector<double>* warm) {
  if (auto r = fit_by_elements(spec, train, c, o, warm)) return std::move(*r);
  // Effects that multiply the friction (g columns) on an element model with a warm start: the
  // element polish with g frozen at the warm shape (a stand-in that moves little when an effect is
  // added; its final linear solve, refit_linear, uses the true g), competing with the shape search.
  const bool with_frozen = !o.polish_only && has_linear_elements(spec.model) && spec.elements > 0 && warm &&
                           warm->size() == Parameterization(model_info(spec.model), spec.elements, c).size();
  const Parameterization par(model_info(spec.model), spec.elements, c);
  Evaluator ev(spec, par, train, c);
  const std::size_t n = par.size();
  std::vector<double> best_u = par.initial();
  Eigen::VectorXd best_th;
  double best = ev.cost(best_u, &best_th);
  // The starts, then a polishing restart from the best point found.
  const bool polish_only = o.polish_only && warm && warm->size() == n;
  const auto starts = start_points(par, o, warm, polish_only);
  const int total = static_cast<int>(starts.size()) + 1;
  const int polish_evaluations = std::max(100, o.max_evaluations / 3);
  const FitOptions so = serialised_progress(o);
  const SearchSettings ss{algorithm_of(o.method),
                          n,
                          &o,
                          &so,
                          std::chrono::steady_clock::now(),
                          o.max_evaluations,
                          polish_evaluations,
                          (total - 1) * o.max_evaluations + polish_evaluations};
  // The frozen-g polish and the starts are independent searches: on two workers (parallel.hpp),
  // each with its own evaluator; merged in the order one thread would have run them.
  std::optional<FitResult> frozen;
  const std::size_t first_start = with_frozen ? 1 : 0;
  const std::size_t tasks = first_start + (n > 0 ? starts.size() : 0);
  std::vector<SearchRun> runs(starts.size());
  std::optional<Evaluator> ev2;
  if (tasks >= 2 && t_parallel_depth == 0 && n > 0) ev2.emplace(spec, par, train, c);
  run_tasks(tasks, [&](std::size_t t, int worker) {
    if (t < first_start) {
      FitResult wr;
      wr.spec = spec;
      wr.u = *warm;
      EffectContext cg = c;
      cg.g_frozen = unit_outputs(wr, spec, train, c);
      frozen = polish_elements(spec, train, cg, so, *warm);
      return;
    }
    const std::size_t s = t - first_start;
    runs[s] = local_search(
        ss, worker == 1 ? *ev2 : ev, starts[s], polish_only,
        o.stage + ", start " + std::to_string(s + 1) + "/" + std::to_string(total - 1));
  });
  int evals = 1;
  bool time_limited = false;
  for (const auto& run : runs) {
    evals += run.evals;
    time_limited |= run.time_limited;
    if (run.best < best) best = run.best, best_u = run.best_u;
  }
  if (n > 0 && !time_limited && !polish_only) {
    const SearchRun run = local_search(ss, ev, best_u, true, o.stage + ", polish");
    evals += run.evals;
    time_limited |= run.time_limited;
    if (run.best < best) best = run.best, best_u = run.best_u;
  }
  best = ev.cost(best_u, &best_th);
  if (o.progress) o.progress({o.stage + ", done", evals, best, ss.budget});
  FitResult r = make_result(spec, par, ev, best_u, best_th, best, evals);
  r.time_limited = time_limited;
  if (frozen && frozen->rms_train < r.rms_train) {
    frozen->evaluations += r.evaluations;
    return *frozen;
  }
  return r;
}

FitResult refit_linear(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                       const std::vector<double>& u) {
  const Parameterization par(model_info(spec.model), spec.elements, c);
  Evaluator ev(spec, par, train, c);
  Eigen::VectorXd th;
  const double rms = ev.cost(u, &th);
  return make_result(spec, par, ev, u, th, rms, 1);
}

struct LinearRefit::Impl {
  FitSpec spec;
  Parameterization par;
  Evaluator ev;
  Impl(const FitSpec& s, const Dataset& d, const EffectContext& c)
      : spec(s), par(model_info(s.model), s.elements, c), ev(spec, par, d, c) {}
};

LinearRefit::LinearRefit(const FitSpec& spec, const Dataset& train, const EffectContext& c)
    : impl_(std::make_unique<Impl>(spec, train, c)) {}
LinearRefit::~LinearRefit() = default;

double LinearRefit::rms(const std::vector<double>& u) { return impl_->ev.cost(u); }

FitResult LinearRefit::fit(const std::vector<double>& u) {
  Eigen::VectorXd th;
  const double rms = impl_->ev.cost(u, &th);
  return make_result(impl_->spec, impl_->par, impl_->ev, u, th, rms, 1);
}

std::vector<double> shape_without_element(const FitResult& f, std::size_t row, const EffectContext& c) {
  const ModelInfo& info = model_info(f.spec.model);
  const auto alpha = info.column_index("alpha");
  if (f.spec.elements < 2 || row >= f.spec.elements || alpha < 0) return {};
  const Parameterization from(info, f.spec.elements, c), to(info, f.spec.elements - 1, c);
  if (f.u.size() != from.size()) return {};
  const ModelParams m = from.unit_model(f.u);  // normalised weights, k = kappa x weight
  // The new first row's weight is fixed at the parameterization's own value: the others are
  // expressed against it (the normalisation restores the shares).
  const std::size_t first = row == 0 ? 1 : 0;
  // The raw (unnormalised) weight of the first row: from any searched weight and the shares.
  const std::vector<double> mid(to.size(), 0.5);
  const ModelParams base = to.unit_model(mid);
  double fixed = 1.0;
  for (std::size_t i = 0; i < to.size(); ++i) {
    const auto& p = to.params()[i];
    if (p.scalar < 0 && p.column == alpha && p.row > 0) {
      const double share = base.elements[static_cast<std::size_t>(p.row)][static_cast<std::size_t>(alpha)];
      if (share > 0) fixed = to.value(i, 0.5) * base.elements.front()[static_cast<std::size_t>(alpha)] / share;
      break;
    }
  }
  const double a_first = m.elements[first][static_cast<std::size_t>(alpha)];
  std::vector<double> u(to.size(), 0.5);
  std::size_t si = 0;
  std::vector<double> scalars;
  for (std::size_t i = 0; i < from.size(); ++i)
    if (from.params()[i].scalar >= 0) scalars.push_back(f.u[i]);
  for (std::size_t i = 0; i < to.size(); ++i) {
    const auto& p = to.params()[i];
    if (p.scalar >= 0) {
      u[i] = si < scalars.size() ? scalars[si++] : 0.5;
      continue;
    }
    const std::size_t r_old = static_cast<std::size_t>(p.row) + (static_cast<std::size_t>(p.row) >= row ? 1 : 0);
    const auto& cells = m.elements[r_old];
    const double w = cells[static_cast<std::size_t>(alpha)];
    double v = cells[static_cast<std::size_t>(p.column)];
    if (p.column == alpha) v = w / a_first * fixed;
    else if (info.columns[static_cast<std::size_t>(p.column)].unit == "N/m") v = w > 0 ? v / w : v;  // kappa
    u[i] = to.box(i, v);
  }
  return u;
}

std::vector<double> predict(const FitResult& r, const Dataset& d, const EffectContext& c) {
  const Parameterization par(model_info(r.spec.model), r.spec.elements, c);
  Evaluator ev(r.spec, par, d, c);
  return ev.predict(r.u, r.theta);
}

std::vector<double> unit_friction(const FitResult& r, const Dataset& d, const EffectContext& c) {
  const Parameterization par(model_info(r.spec.model), r.spec.elements, c);
  std::vector<double> g(d.size(), 0.0);
  const auto mp = par.unit_model(r.u);
  const auto model = build_model(mp);
  if (mp.model == "gms") {  // as the fit's Evaluator simulates it
    GmsPathRunner runner;
    simulate_gms_along(GmsParams::from(mp), gms_path(d), runner, g);
  } else {
    simulate_along(*model, d, g);
  }
  return g;  // the unit output only (no sensitivity)
}

std::vector<double> unit_outputs(const FitResult& r, const FitSpec& spec, const Dataset& d,
                                 const EffectContext& c) {
  std::vector<double> g = unit_friction(r, d, c);
  for (ExtraOutput x : extra_outputs(spec.effects)) {
    std::vector<double> gx;
    if (x == ExtraOutput::Dwell) {  // the dwell response, as the fit's Evaluator has it
      const Parameterization par(model_info(r.spec.model), r.spec.elements, c);
      const FitSpec dwell{r.spec.model, r.spec.elements, {Effect::DwellStiction}};
      const Evaluator ev(dwell, par, d, c);
      if (!ev.simulate(r.u, gx) || gx.size() != 2 * d.size())
        throw SimulationError("the dwell response of the fitted model could not be simulated");
      gx.erase(gx.begin(), gx.begin() + static_cast<std::ptrdiff_t>(d.size()));
    } else if (x == ExtraOutput::Shifted) {
      gx = unit_friction(r, shifted_motion(d, c.time_shift), c);
    } else if (x == ExtraOutput::Contact) {
      gx = unit_friction(r, through_dead_band(d, c.backlash), c);
    }
    g.insert(g.end(), gx.begin(), gx.end());
  }
  return g;
}

double rms_on(const FitResult& r, const Dataset& d, const EffectContext& c) {
  const auto p = predict(r, d, c);
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) s += (d.F[k] - p[k]) * (d.F[k] - p[k]), ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : 0.0;
}

LinearSolution least_squares(const std::vector<std::vector<double>>& columns,
                             const std::vector<double>& y, const std::vector<std::uint8_t>& use) {
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < y.size(); ++k)
    if (use[k]) rows.push_back(k);
  Eigen::MatrixXd A(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(columns.size()));
  Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < columns.size(); ++j)
      A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = columns[j][rows[i]];
    b(static_cast<Eigen::Index>(i)) = y[rows[i]];
  }
  const Eigen::VectorXd th = A.colPivHouseholderQr().solve(b);
  LinearSolution s;
  s.coef.assign(th.data(), th.data() + th.size());
  s.rms = rows.empty() ? 0.0 : std::sqrt((A * th - b).squaredNorm() / static_cast<double>(rows.size()));
  return s;
}

}  // namespace gmslab::ident
