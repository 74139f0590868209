#include "core/ident/discovery.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "core/ident/evidence.hpp"

namespace gmslab::ident {

namespace {

std::string num(double x, const char* f = "%.3g") {
  char b[48];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

std::string length(double m) {
  if (m < 1e-3) return num(m * 1e6) + " um";
  if (m < 1.0) return num(m * 1e3) + " mm";
  return num(m) + " m";
}

double v_rest_of(const EffectContext& c) { return c.v_rest > 0 ? c.v_rest : 0.01 * c.v_ref; }

double sgn_moving(double v, double vr) { return std::abs(v) > vr ? (v > 0 ? 1.0 : -1.0) : 0.0; }

double rms_used(const Dataset& d, const std::vector<double>& r) {
  double s = 0, n = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) s += r[k] * r[k], n += 1;
  return n > 0 ? std::sqrt(s / n) : 0.0;
}

// Travel since the last reversal of the direction of motion [m].
std::vector<double> travel_since_reversal(const Dataset& d, double vr) {
  std::vector<double> s(d.size(), 0.0);
  double acc = 0, last = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const double sg = sgn_moving(d.v[k], vr);
    if (sg != 0 && sg != last) acc = 0, last = sg;
    if (k > 0) acc += std::abs(d.x[k] - d.x[k - 1]);
    s[k] = acc;
  }
  return s;
}

// Time since the last sample at rest [s].
std::vector<double> time_since_rest(const Dataset& d, double vr) {
  std::vector<double> s(d.size(), 0.0);
  double since = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (std::abs(d.v[k]) <= vr)
      since = 0;
    else if (k > 0)
      since += d.t[k] - d.t[k - 1];
    s[k] = since;
  }
  return s;
}

std::vector<double> low_pass(const Dataset& d, const std::vector<double>& u, double T) {
  std::vector<double> y(d.size(), 0.0);
  double state = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (k > 0) state += (1.0 - std::exp(-(d.t[k] - d.t[k - 1]) / T)) * (u[k] - state);
    y[k] = state;
  }
  return y;
}

// Strongest wavelength of r's position spectrum over the samples moving in `dir` (0: none).
double ripple_wavelength(const Dataset& train, const EffectContext& c, const std::vector<double>& r,
                         int dir) {
  Dataset d = train;
  const double vr = v_rest_of(c);
  std::size_t n = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    d.use[k] = d.use[k] && sgn_moving(d.v[k], vr) == dir;
    n += d.use[k];
  }
  if (n < 200) return 0;
  return position_spectrum(d, c, r).peak_wavelength;
}

}  // namespace

std::string family_name(LibraryFamily f) {
  switch (f) {
    case LibraryFamily::Velocity:
      return "velocity";
    case LibraryFamily::Acceleration:
      return "acceleration";
    case LibraryFamily::Position:
      return "position";
    case LibraryFamily::Sign:
      return "direction";
    case LibraryFamily::VelocitySquared:
      return "velocity squared";
    case LibraryFamily::Reversal:
      return "travel since reversal";
    case LibraryFamily::Rest:
      return "time since rest";
    case LibraryFamily::HistoryV:
      return "sliding history |v|";
    case LibraryFamily::HistoryFv:
      return "sliding history |F v|";
    case LibraryFamily::ForceLag:
      return "force-channel lag";
    case LibraryFamily::DirRippleSin:
    case LibraryFamily::DirRippleCos:
      return "direction-dependent ripple";
  }
  return "?";
}

std::string column_formula(const LibraryColumn& c) {
  const std::string gate = c.direction > 0 ? " [v > 0]" : " [v < 0]";
  switch (c.family) {
    case LibraryFamily::Velocity:
      return "v / v_ref";
    case LibraryFamily::Acceleration:
      return "a";
    case LibraryFamily::Position:
      return "(x - x_mid) / x_half";
    case LibraryFamily::Sign:
      return "sgn(v)";
    case LibraryFamily::VelocitySquared:
      return "v |v| / v_ref^2";
    case LibraryFamily::Reversal:
      return "sgn(v) exp(-s / " + length(c.scale) + ")";
    case LibraryFamily::Rest:
      return "sgn(v) exp(-tau_rest / " + num(c.scale) + " s)";
    case LibraryFamily::HistoryV:
      return "sgn(v) LP(|v| / v_ref, " + num(c.scale) + " s)";
    case LibraryFamily::HistoryFv:
      return "sgn(v) LP(|F v| / (F_level v_ref), " + num(c.scale) + " s)";
    case LibraryFamily::ForceLag:
      return "dF/dt";
    case LibraryFamily::DirRippleSin:
      return "sin(2 pi x / " + length(c.scale) + ")" + gate;
    case LibraryFamily::DirRippleCos:
      return "cos(2 pi x / " + length(c.scale) + ")" + gate;
  }
  return "?";
}

std::string coefficient_unit(const LibraryColumn& c) {
  switch (c.family) {
    case LibraryFamily::Acceleration:
      return "kg";
    case LibraryFamily::ForceLag:
      return "s";
    default:
      return "N";
  }
}

std::vector<LibraryColumn> discovery_library(const Dataset& train, const EffectContext& c,
                                             const std::vector<double>& r) {
  using F = LibraryFamily;
  std::vector<LibraryColumn> lib = {
      {F::Velocity}, {F::Acceleration}, {F::Position}, {F::Sign}, {F::VelocitySquared}};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < train.size(); ++k)
    lo = std::min(lo, train.x[k]), hi = std::max(hi, train.x[k]);
  const double stroke = std::max(hi - lo, 2e-6);
  for (double L = 1e-6; L <= stroke * 1.0001; L *= 2.0) lib.push_back({F::Reversal, L});
  const double step = std::sqrt(10.0);
  for (double T = 0.01; T <= 100.0 * 1.0001; T *= step) lib.push_back({F::Rest, T});
  for (double T = 0.1; T <= 100.0 * 1.0001; T *= step) lib.push_back({F::HistoryV, T});
  for (double T = 0.1; T <= 100.0 * 1.0001; T *= step) lib.push_back({F::HistoryFv, T});
  lib.push_back({F::ForceLag});
  for (int dir : {1, -1}) {
    const double lambda = ripple_wavelength(train, c, r, dir);
    if (lambda <= 0) continue;
    lib.push_back({F::DirRippleSin, lambda, dir});
    lib.push_back({F::DirRippleCos, lambda, dir});
  }
  return lib;
}

bool needs_model_force(const LibraryColumn& c) {
  return c.family == LibraryFamily::HistoryFv || c.family == LibraryFamily::ForceLag;
}

std::vector<double> library_values(const LibraryColumn& col, const Dataset& d,
                                   const EffectContext& c, const std::vector<double>& f) {
  using F = LibraryFamily;
  const std::size_t n = d.size();
  const double vr = v_rest_of(c), vref = c.v_ref > 0 ? c.v_ref : 1.0;
  std::vector<double> out(n, 0.0), u(n, 0.0);
  switch (col.family) {
    case F::Velocity:
      for (std::size_t k = 0; k < n; ++k) out[k] = d.v[k] / vref;
      break;
    case F::Acceleration:
      out = d.a;
      break;
    case F::Position:
      for (std::size_t k = 0; k < n; ++k) out[k] = (d.x[k] - c.x_mid) / c.x_half;
      break;
    case F::Sign:
      for (std::size_t k = 0; k < n; ++k) out[k] = sgn_moving(d.v[k], vr);
      break;
    case F::VelocitySquared:
      for (std::size_t k = 0; k < n; ++k) out[k] = d.v[k] * std::abs(d.v[k]) / (vref * vref);
      break;
    case F::Reversal: {
      const auto s = travel_since_reversal(d, vr);
      for (std::size_t k = 0; k < n; ++k)
        out[k] = sgn_moving(d.v[k], vr) * std::exp(-s[k] / col.scale);
      break;
    }
    case F::Rest: {
      const auto tau = time_since_rest(d, vr);
      for (std::size_t k = 0; k < n; ++k)
        out[k] = sgn_moving(d.v[k], vr) * std::exp(-tau[k] / col.scale);
      break;
    }
    case F::HistoryV:
    case F::HistoryFv: {
      const double fl = c.f_level > 0 ? c.f_level : 1.0;
      for (std::size_t k = 0; k < n; ++k)
        u[k] = col.family == F::HistoryV ? std::abs(d.v[k]) / vref
                                         : std::abs(f[k] * d.v[k]) / (fl * vref);
      const auto y = low_pass(d, u, col.scale);
      for (std::size_t k = 0; k < n; ++k) out[k] = sgn_moving(d.v[k], vr) * y[k];
      break;
    }
    case F::ForceLag:
      out = local_slope(d.t, f, 2);
      break;
    case F::DirRippleSin:
    case F::DirRippleCos:
      for (std::size_t k = 0; k < n; ++k) {
        if (sgn_moving(d.v[k], vr) != col.direction) continue;
        const double ph = 2 * std::numbers::pi * d.x[k] / col.scale;
        out[k] = col.family == F::DirRippleSin ? std::sin(ph) : std::cos(ph);
      }
      break;
  }
  return out;
}

namespace {

// Least squares of r on the chosen columns over the used samples.
std::vector<double> solve(const std::vector<std::vector<double>>& X,
                          const std::vector<std::size_t>& set, const std::vector<double>& r,
                          const Dataset& d) {
  const std::size_t m = set.size();
  Eigen::MatrixXd A =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m));
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (!d.use[k]) continue;
    for (std::size_t i = 0; i < m; ++i) {
      const double xi = X[set[i]][k];
      b(static_cast<Eigen::Index>(i)) += xi * r[k];
      for (std::size_t j = 0; j <= i; ++j)
        A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) += xi * X[set[j]][k];
    }
  }
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < i; ++j)
      A(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) =
          A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
  const Eigen::VectorXd th = A.completeOrthogonalDecomposition().solve(b);
  return std::vector<double>(th.data(), th.data() + th.size());
}

std::vector<double> after(const std::vector<std::vector<double>>& X,
                          const std::vector<std::size_t>& set, const std::vector<double>& theta,
                          const std::vector<double>& r) {
  std::vector<double> out = r;
  for (std::size_t i = 0; i < set.size(); ++i)
    for (std::size_t k = 0; k < out.size(); ++k) out[k] -= theta[i] * X[set[i]][k];
  return out;
}

// Next column of the forward path: the most correlated with the residual (normalised columns).
std::size_t next_column(const std::vector<std::vector<double>>& X, const std::vector<double>& norm,
                        const std::vector<std::size_t>& set, const std::vector<double>& r,
                        const Dataset& d) {
  std::size_t best = X.size();
  double best_score = 0;
  for (std::size_t j = 0; j < X.size(); ++j) {
    if (norm[j] <= 0 || std::find(set.begin(), set.end(), j) != set.end()) continue;
    double s = 0;
    for (std::size_t k = 0; k < d.size(); ++k)
      if (d.use[k]) s += X[j][k] * r[k];
    const double score = std::abs(s) / norm[j];
    if (score > best_score) best_score = score, best = j;
  }
  return best;
}

std::vector<std::vector<double>> matrix(const std::vector<LibraryColumn>& lib, const Dataset& d,
                                        const EffectContext& c, const std::vector<double>& f) {
  std::vector<std::vector<double>> X;
  X.reserve(lib.size());
  for (const auto& col : lib) X.push_back(library_values(col, d, c, f));
  return X;
}

}  // namespace

Discovery discover(const Dataset& train, const Dataset& val, const EffectContext& c,
                   const std::vector<double>& f_train, const std::vector<double>& f_val,
                   double floor, const DiscoveryOptions& o) {
  Discovery s;
  s.floor = floor;
  s.z_crit = o.z_crit;
  std::vector<double> rt(train.size()), rv(val.size());
  for (std::size_t k = 0; k < train.size(); ++k) rt[k] = train.F[k] - f_train[k];
  for (std::size_t k = 0; k < val.size(); ++k) rv[k] = val.F[k] - f_val[k];
  s.rms_validation_before = s.rms_validation_after = rms_used(val, rv);
  if (!(s.rms_validation_before > o.near_floor * floor)) {
    s.summary = "not run: no structure remains (validation " + num(s.rms_validation_before) +
                " N, within " + num(o.near_floor) + "x the floor " + num(floor) + " N)";
    return s;
  }
  s.ran = true;
  s.library = discovery_library(train, c, rt);
  s.library_size = s.library.size();
  const auto Xt = matrix(s.library, train, c, f_train), Xv = matrix(s.library, val, c, f_val);
  std::vector<double> norm(Xt.size(), 0.0);
  for (std::size_t j = 0; j < Xt.size(); ++j) {
    double q = 0;
    for (std::size_t k = 0; k < train.size(); ++k)
      if (train.use[k]) q += Xt[j][k] * Xt[j][k];
    norm[j] = std::sqrt(q);
  }
  // The forward path.
  std::vector<std::size_t> set;
  std::vector<std::vector<double>> thetas, res_val;
  std::vector<double> r = rt;
  for (std::size_t step = 0; step < o.max_terms; ++step) {
    const std::size_t j = next_column(Xt, norm, set, r, train);
    if (j >= Xt.size()) break;
    set.push_back(j);
    const auto th = solve(Xt, set, rt, train);
    r = after(Xt, set, th, rt);
    res_val.push_back(after(Xv, set, th, rv));
    thetas.push_back(th);
    s.path.push_back({set, rms_used(train, r), rms_used(val, res_val.back())});
  }
  if (s.path.empty()) {
    s.summary = "nothing discovered: no library column varies over the training record";
    return s;
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < s.path.size(); ++i)
    if (s.path[i].rms_validation < s.path[best].rms_validation) best = i;
  std::size_t pick = best;
  for (std::size_t i = 0; i < best; ++i)
    if (block_test(val, res_val[i], res_val[best], o.blocks).z < o.z_crit) {
      pick = i;
      break;
    }
  const DiscoveryStep& p = s.path[pick];
  for (std::size_t i = 0; i < p.columns.size(); ++i)
    s.terms.push_back({s.library[p.columns[i]], thetas[pick][i]});
  std::vector<double> contrib(train.size(), 0.0);
  for (std::size_t i = 0; i < p.columns.size(); ++i)
    for (std::size_t k = 0; k < train.size(); ++k)
      contrib[k] += thetas[pick][i] * Xt[p.columns[i]][k];
  s.contribution = rms_used(train, contrib);
  s.test = block_test(val, rv, res_val[pick], o.blocks);
  const bool resolved =
      s.test.mse_difference > 0 && (s.test.z >= o.z_crit || s.test.mse_difference >= floor * floor);
  const bool large = s.contribution >= o.min_size * floor;
  const std::string z = std::isfinite(s.test.z) ? num(s.test.z, "%.2g") : std::string("inf");
  const std::string gain = "(validation " + num(s.rms_validation_before) + " -> " +
                           num(p.rms_validation) + " N, z = " + z + ")";
  if (resolved && large) {
    s.found = true;
    s.rms_validation_after = p.rms_validation;
    s.summary = "discovered: " + discovered_formula(s) + "  " + gain;
    return s;
  }
  std::string why = !resolved ? "z = " + z + " < " + num(o.z_crit) +
                                    " and the MSE rise below the floor's variance"
                              : "contribution " + num(s.contribution) + " N < " + num(o.min_size) +
                                    "x the floor " + num(floor) + " N";
  s.summary = "nothing discovered: best candidate " + discovered_formula(s) + " " + gain +
              " failed the credit test (" + why + ")";
  return s;
}

std::vector<double> discovered_force(const Discovery& s, const Dataset& d, const EffectContext& c,
                                     const std::vector<double>& f) {
  std::vector<double> out(d.size(), 0.0);
  if (!s.found) return out;
  for (const auto& t : s.terms) {
    const auto col = library_values(t.column, d, c, f);
    for (std::size_t k = 0; k < d.size(); ++k) out[k] += t.coefficient * col[k];
  }
  return out;
}

std::string discovered_formula(const Discovery& s) {
  std::string out;
  for (const auto& t : s.terms) {
    if (!out.empty()) out += " ";
    out += (t.coefficient < 0 ? "-" : "+") + num(std::abs(t.coefficient)) + " " +
           coefficient_unit(t.column) + " * " + column_formula(t.column);
  }
  return out;
}

nlohmann::json to_json(const Discovery& s) {
  nlohmann::json j;
  j["ran"] = s.ran;
  j["found"] = s.found;
  j["summary"] = s.summary;
  j["library_size"] = s.library_size;
  nlohmann::json lib = nlohmann::json::array();
  for (const auto& c : s.library) lib.push_back(column_formula(c));
  j["library"] = lib;
  nlohmann::json path = nlohmann::json::array();
  for (const auto& p : s.path) {
    nlohmann::json cols = nlohmann::json::array();
    for (std::size_t i : p.columns) cols.push_back(column_formula(s.library[i]));
    path.push_back(
        {{"terms", cols}, {"rms_train_N", p.rms_train}, {"rms_validation_N", p.rms_validation}});
  }
  j["path"] = path;
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& t : s.terms)
    terms.push_back({{"family", family_name(t.column.family)},
                     {"formula", column_formula(t.column)},
                     {"coefficient", t.coefficient},
                     {"unit", coefficient_unit(t.column)},
                     {"scale", t.column.scale}});
  j["terms"] = terms;
  j["kept"] = s.found;
  j["joined"] = s.joined;
  j["test"] = {{"description",
                "validation MSE without against with the terms over time blocks; kept when z >= " +
                    num(s.z_crit) +
                    " (or the rise is at least the floor's variance) and the "
                    "contribution is at least half the floor"},
               {"z", std::isfinite(s.test.z) ? nlohmann::json(s.test.z) : nlohmann::json("inf")},
               {"mse_difference_N2", s.test.mse_difference},
               {"std_error_N2", s.test.std_error},
               {"blocks", s.test.blocks},
               {"contribution_N", s.contribution},
               {"floor_N", s.floor}};
  j["validation_rms_before_N"] = s.rms_validation_before;
  j["validation_rms_after_N"] = s.rms_validation_after;
  return j;
}

}  // namespace gmslab::ident
