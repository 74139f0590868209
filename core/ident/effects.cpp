#include "core/ident/effects.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>

#include "core/error.hpp"

namespace gmslab::ident {

namespace {

constexpr std::size_t kMaxDiscovered = 4;  // DiscoveryOptions::max_terms

struct Entry {
  Effect e;
  std::string_view name;
  std::string_view meaning;
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> v = {
      {Effect::Inertia, "inertia", "m a in the measured force (actuator force, not a force sensor)"},
      {Effect::Offset, "offset", "constant force: gravity on an inclined axis, cables, level asymmetry"},
      {Effect::DirectionAsymmetry, "direction_asymmetry", "viscous slope different per direction"},
      {Effect::PositionPeriodic, "position_periodic",
       "ripple locked to position: cogging, screw or ball recirculation"},
      {Effect::PositionDependent, "position_dependent", "slow variation of force along the stroke"},
      {Effect::TimeDrift, "time_drift", "slow change with time: warm-up, wear"},
      {Effect::VelocityExtra, "velocity_extra",
       "velocity dependence beyond the model: quadratic drag, other low-speed (Stribeck) shape"},
      {Effect::DwellStiction, "dwell_stiction", "break-away force growing with the time at rest"},
      {Effect::NormalLoad, "normal_load", "friction proportional to the measured normal force"},
      {Effect::TimeShift, "time_shift",
       "force channel shifted in time against the position channel (separate filters, delays)"},
      {Effect::SensorFilter, "sensor_filter", "first-order low-pass on the force channel (sensor, amplifier)"},
      {Effect::Backlash, "backlash", "lost motion between encoder and contact at reversals (play, compliance)"},
  };
  return v;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double sgn(double v) { return static_cast<double>((v > 0.0) - (v < 0.0)); }

// Legendre polynomials P1..P3 of xi clipped to [-1.2, 1.2].
double legendre(int n, double xi) {
  xi = std::clamp(xi, -1.2, 1.2);
  switch (n) {
    case 1: return xi;
    case 2: return 0.5 * (3 * xi * xi - 1);
    default: return 0.5 * (5 * xi * xi * xi - 3 * xi);
  }
}

using Fill = std::function<void(const Dataset&, const EffectContext&, std::span<const double>,
                                std::span<double>)>;

Column col(std::string name, std::string unit, bool uses_g, Fill f) {
  return {std::move(name), std::move(unit), uses_g, std::move(f)};
}

// Coulomb level and break-away displacement from the data.
void estimate_levels(const Dataset& d, EffectContext& c) {
  // Sliding samples: F ~ c0 + Fc sgn v + Fv v + M a (the static inverse model).
  double fv = 0.0, m = 0.0;  // its viscous and inertia terms, taken out of the swing below
  bool estimated = false;    // the Coulomb level from the sliding samples (else the median |F|)
  std::vector<std::size_t> idx;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k] && std::abs(d.v[k]) > 0.2 * c.v_ref) idx.push_back(k);
  if (idx.size() >= 8) {
    // The viscous term only where the sliding speeds spread (10th to 90th percentile of |v| over
    // at least a fifth of the median): at one speed, v is sgn v times a constant and the split
    // between the two is arbitrary (a back-and-forth ramp at constant rate).
    std::vector<double> speeds;
    for (const auto k : idx) speeds.push_back(std::abs(d.v[k]));
    const double p50 = percentile(speeds, 0.5);
    const bool viscous = p50 > 0 && percentile(speeds, 0.9) - percentile(speeds, 0.1) >= 0.2 * p50;
    Eigen::MatrixXd A(idx.size(), 4);
    Eigen::VectorXd y(idx.size());
    for (std::size_t i = 0; i < idx.size(); ++i) {
      const auto k = idx[i];
      A.row(static_cast<Eigen::Index>(i)) << 1.0, sgn(d.v[k]), viscous ? d.v[k] / c.v_ref : 0.0, d.a[k];
      y(static_cast<Eigen::Index>(i)) = d.F[k];
    }
    const Eigen::VectorXd th = viscous ? Eigen::VectorXd(A.colPivHouseholderQr().solve(y)) : [&] {
      Eigen::MatrixXd B(A.rows(), 3);
      B << A.col(0), A.col(1), A.col(3);
      const Eigen::Vector3d t3 = B.colPivHouseholderQr().solve(y);
      return Eigen::VectorXd(Eigen::Vector4d(t3(0), t3(1), 0.0, t3(2)));
    }();
    if (std::isfinite(th(1)) && th(1) > 0) c.f_level = th(1), estimated = true;
    if (th.allFinite()) fv = th(2) / c.v_ref, m = th(3);
  }
  if (!estimated)
    c.f_level = std::max(1e-6, percentile(
                                   [&] {
                                     std::vector<double> a;
                                     for (double f : d.F) a.push_back(std::abs(f));
                                     return a;
                                   }(),
                                   0.5));
  // Break-away displacement: travel after a reversal until the friction has swung by 80 % of 2 Fc.
  std::vector<double> xs;
  double last_dir = 0.0;
  std::size_t rev = 0;
  bool searching = false;
  for (std::size_t k = 1; k < d.size(); ++k) {
    if (sgn(d.v[k]) != sgn(d.v[k - 1])) rev = k;
    if (std::abs(d.v[k]) > 0.1 * c.v_ref) {
      const double dir = sgn(d.v[k]);
      if (last_dir != 0.0 && dir != last_dir) searching = true;
      last_dir = dir;
    }
    if (searching && rev > 0 && k > rev) {
      // The swing of the friction alone: a large viscous term jumps with the velocity's sign and
      // would end the search at once.
      const double swing = d.F[k] - fv * d.v[k] - m * d.a[k] - (d.F[rev - 1] - fv * d.v[rev - 1] - m * d.a[rev - 1]);
      if (last_dir * swing >= 1.6 * c.f_level) {
        xs.push_back(std::abs(d.x[k] - d.x[rev]));
        searching = false;
      }
    }
  }
  const double stroke = *std::max_element(d.x.begin(), d.x.end()) -
                        *std::min_element(d.x.begin(), d.x.end());
  c.x_ba = xs.empty() ? 1e-3 * stroke : percentile(xs, 0.5);
  c.x_ba = std::clamp(c.x_ba, 1e-8, std::max(1e-8, 0.05 * stroke));
}


}  // namespace

void shifted(const Dataset& d, std::span<const double> y, double tau, std::span<double> out) {
  const std::size_t n = d.size();
  std::size_t j = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = d.t[k] - tau;
    if (t <= d.t.front()) { out[k] = y[0]; continue; }
    if (t >= d.t.back()) { out[k] = y[n - 1]; continue; }
    if (tau > 0) { while (j + 1 < n && d.t[j + 1] <= t) ++j; }
    else { j = std::max(j, k); while (j + 1 < n && d.t[j + 1] <= t) ++j; }
    const double w = (t - d.t[j]) / (d.t[j + 1] - d.t[j]);
    out[k] = y[j] + w * (y[j + 1] - y[j]);
  }
}

void lowpass(const Dataset& d, std::span<const double> y, double T, std::span<double> out) {
  if (!(T > 0)) {
    std::copy_n(y.begin(), d.size(), out.begin());
    return;
  }
  double s = y[0];
  double h_last = std::numeric_limits<double>::quiet_NaN(), e = 0.0;  // steps repeat: exp once each
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (k > 0) {
      const double h = d.t[k] - d.t[k - 1];
      if (!(h == h_last)) h_last = h, e = std::exp(-h / T);
      s = y[k] + (s - y[k]) * e;
    }
    out[k] = s;
  }
}

// A force-channel effect's column: the channel transform of the friction g (and of the viscous
// share through v) minus the untransformed signal, so its coefficient is the level it explains.
template <class Transform>
Column channel_column(std::string name, Transform tf) {
  return {std::move(name), "N", true,
          [tf](const Dataset& d, const EffectContext& c, std::span<const double> g, std::span<double> o) {
            tf(d, g, c, o);
            std::vector<double> v(d.size());
            tf(d, d.v, c, v);
            for (std::size_t k = 0; k < d.size(); ++k) o[k] += -g[k] + c.viscous_ratio * (v[k] - d.v[k]);
          }};
}

Dataset through_dead_band(const Dataset& d, double b) {
  Dataset out = d;
  const std::size_t n = d.size();
  if (n == 0) return out;
  const double half = 0.5 * std::max(b, 0.0);
  double xc = d.x[0];  // the contact, at the start in the middle of the band
  out.v[0] = half > 0.0 ? 0.0 : d.v[0];
  for (std::size_t k = 1; k < n; ++k) {
    double xm = d.x[k - 1];  // the encoder, moving by the step's displacement
    bool moved = false;      // whether the contact moved in the step's last part
    auto part = [&](double& v, double h) {
      xm += v * h;
      const double xn = std::clamp(xc, xm - half, xm + half);
      v = h > 0.0 ? (xn - xc) / h : 0.0;
      moved = xn != xc;
      xc = xn;
    };
    if (!d.sub.empty() && d.sub[k + 1] > d.sub[k]) {
      for (std::uint32_t j = d.sub[k]; j < d.sub[k + 1]; ++j) part(out.sv[j], d.sh[j]);
    } else {
      part(out.vstep[k], d.h[k]);
    }
    out.x[k] = xc;
    out.v[k] = moved ? d.v[k] : 0.0;
  }
  return out;
}

Dataset shifted_motion(const Dataset& d, double tau) {
  Dataset out = d;
  const std::size_t n = d.size();
  if (n < 2 || !(tau > 0.0)) return out;
  // The path as segments of constant velocity: a rest of tau before the start, then each step
  // (or its substeps); segment i starts at ts[i] at position xs[i].
  std::vector<double> ts, xs, vs;
  ts.push_back(d.t[0] - tau), xs.push_back(d.x[0]), vs.push_back(0.0);
  for (std::size_t k = 1; k < n; ++k) {
    double t = d.t[k - 1], x = d.x[k - 1];
    auto part = [&](double v, double h) {
      if (!(h > 0.0)) return;
      ts.push_back(t), xs.push_back(x), vs.push_back(v);
      t += h, x += v * h;
    };
    if (!d.sub.empty() && d.sub[k + 1] > d.sub[k]) {
      for (std::uint32_t j = d.sub[k]; j < d.sub[k + 1]; ++j) part(d.sv[j], d.sh[j]);
    } else {
      part(d.vstep[k], d.h[k]);
    }
  }
  const std::size_t m = ts.size();
  auto linear = [&](const std::vector<double>& y, double t, std::size_t& j) {
    while (j + 2 < n && d.t[j + 1] <= t) ++j;
    const double w = (t - d.t[j]) / (d.t[j + 1] - d.t[j]);
    return y[j] + w * (y[j + 1] - y[j]);
  };
  // The positions at the shifted times, on the path; v and a interpolated (at rest before the
  // start).
  std::size_t i = 0, jv = 0, ja = 0;
  const double start = d.t[0] - 1e-9 * (d.t[1] - d.t[0]);  // the first sample, up to a rounding
  for (std::size_t k = 0; k < n; ++k) {
    const double s = d.t[k] - tau;
    while (i + 1 < m && ts[i + 1] <= s) ++i;
    out.x[k] = xs[i] + vs[i] * (s - ts[i]);
    out.v[k] = s < start ? 0.0 : linear(d.v, s, jv);
    out.a[k] = s < start ? 0.0 : linear(d.a, s, ja);
    for (std::size_t at : {jv, jv + 1})  // at a sample of d up to a rounding: that sample's values
      if (at < n && std::abs(d.t[at] - s) <= 1e-9 * d.h[std::max<std::size_t>(at, 1)])
        out.x[k] = d.x[at], out.v[k] = d.v[at], out.a[k] = d.a[at];
  }
  // The path between the shifted samples: the cubic through their positions and slopes (as
  // set_path makes it), in as many parts as the most any step of d it overlaps has, so the model
  // runs along it at d's own resolution (straight where d is straight).
  auto parts_of = [&](std::size_t j) {
    return d.sub.empty() ? std::uint32_t{1} : std::max<std::uint32_t>(1, d.sub[j + 1] - d.sub[j]);
  };
  out.sub.assign(n + 1, 0);
  out.sv.clear(), out.sh.clear();
  std::size_t j = 1;  // the step of d (from sample j - 1 to j) the shifted step starts in
  for (std::size_t k = 1; k < n; ++k) {
    out.sub[k] = static_cast<std::uint32_t>(out.sv.size());
    const double h = d.h[k], s0 = d.t[k - 1] - tau, s1 = d.t[k] - tau;
    out.vstep[k] = h > 0.0 ? (out.x[k] - out.x[k - 1]) / h : 0.0;
    if (!(h > 0.0)) continue;
    // A shifted sample within 1e-9 of a step of a sample time is at that sample (a whole-sample
    // shift gives d's own steps, not their neighbours' by a rounding).
    const double eps = 1e-9 * h;
    while (j + 1 < n && d.t[j] <= s0 + eps) ++j;
    std::uint32_t parts = s1 > d.t[0] + eps ? parts_of(j) : 1;
    for (std::size_t jj = j + 1; jj < n && d.t[jj - 1] < s1 - eps; ++jj)
      parts = std::max(parts, parts_of(jj));
    if (parts <= 1) continue;
    const double x0 = out.x[k - 1], x1 = out.x[k], m0 = out.v[k - 1] * h, m1 = out.v[k] * h;
    double prev = x0;
    for (std::uint32_t p = 1; p <= parts; ++p) {
      const double u = static_cast<double>(p) / parts, u2 = u * u, u3 = u2 * u;
      const double x = p == parts ? x1
                                  : (2 * u3 - 3 * u2 + 1) * x0 + (u3 - 2 * u2 + u) * m0 +
                                        (3 * u2 - 2 * u3) * x1 + (u3 - u2) * m1;
      out.sv.push_back((x - prev) / (h / parts));
      out.sh.push_back(h / parts);
      prev = x;
    }
  }
  out.sub[n] = static_cast<std::uint32_t>(out.sv.size());
  if (out.sv.empty()) out.sub.clear();
  return out;
}

std::vector<ExtraOutput> extra_outputs(const std::vector<Effect>& effects) {
  const auto has = [&](Effect e) {
    return std::find(effects.begin(), effects.end(), e) != effects.end();
  };
  std::vector<ExtraOutput> out;
  if (has(Effect::DwellStiction)) out.push_back(ExtraOutput::Dwell);
  if (has(Effect::TimeShift)) out.push_back(ExtraOutput::Shifted);
  if (has(Effect::Backlash)) out.push_back(ExtraOutput::Contact);
  return out;
}

std::span<const double> column_input(const Column& col, std::span<const double> outputs,
                                     std::size_t n, const std::vector<ExtraOutput>& ex,
                                     std::vector<double>& scratch) {
  if (col.extra == ExtraOutput::None) return outputs;
  const auto at = std::find(ex.begin(), ex.end(), col.extra);
  if (at == ex.end() || outputs.size() < n * (2 + static_cast<std::size_t>(at - ex.begin())))
    throw InternalError("column " + col.name +
                        " without the extra output it takes (fit.hpp, unit_outputs)");
  const std::size_t block = 1 + static_cast<std::size_t>(at - ex.begin());
  if (block == 1) return outputs.first(2 * n);
  scratch.resize(2 * n);
  std::copy_n(outputs.begin(), n, scratch.begin());
  std::copy_n(outputs.begin() + static_cast<std::ptrdiff_t>(block * n), n,
              scratch.begin() + static_cast<std::ptrdiff_t>(n));
  return scratch;
}

namespace {

// The velocity at the samples of a record's motion seen through a transmission (through_dead_band
// for a lost motion b, shifted_motion for a lag tau: its v), kept while the record's motion and
// the scalar are those it was made for (the column is filled at every evaluation of a fit on one
// record).
class MotionVelocityCache {
 public:
  using Make = Dataset (*)(const Dataset&, double);
  explicit MotionVelocityCache(Make make) : make_(make) {}
  std::vector<double> velocity(const Dataset& d, double p) {
    std::lock_guard<std::mutex> lock(m_);
    if (p_ != p || x_ != d.x || v_ != d.v) {
      vm_ = make_(d, p).v;
      p_ = p, x_ = d.x, v_ = d.v;
    }
    return vm_;
  }

 private:
  Make make_;
  std::mutex m_;
  double p_ = -1.0;
  std::vector<double> x_, v_, vm_;
};

// A transmission effect's column (time_shift, backlash): the model along the record's motion seen
// through the transmission (`make` at the context's scalar; the column's extra output, the last n
// values of g) less the model, and the viscous share at that motion's velocity less that at the
// record's, so its coefficient is the level it explains.
Column transmission_column(std::string name, double EffectContext::*scalar,
                           MotionVelocityCache::Make make, ExtraOutput extra, std::string what) {
  Column out{std::move(name), "N", true,
             [cache = std::make_shared<MotionVelocityCache>(make), scalar, what](
                 const Dataset& d, const EffectContext& c, std::span<const double> g,
                 std::span<double> o) {
               const std::size_t n = d.size();
               if (g.size() < 2 * n)
                 throw InternalError("column without " + what + " (fit.hpp, unit_outputs)");
               const std::span<const double> gm = g.last(n);
               const std::vector<double> vm = cache->velocity(d, c.*scalar);
               for (std::size_t k = 0; k < n; ++k)
                 o[k] = gm[k] - g[k] + c.viscous_ratio * (vm[k] - d.v[k]);
             }};
  out.extra = extra;
  return out;
}

}  // namespace

const std::vector<Effect>& effect_catalog() {
  static const std::vector<Effect> v = [] {
    std::vector<Effect> r;
    for (const auto& e : entries()) r.push_back(e.e);
    return r;
  }();
  return v;
}

std::string_view effect_name(Effect e) {
  if (e == Effect::Discovered) return "discovered";
  for (const auto& x : entries())
    if (x.e == e) return x.name;
  return "?";
}

std::string_view effect_meaning(Effect e) {
  if (e == Effect::Discovered) return "terms beyond the catalog, found by sparse regression";
  for (const auto& x : entries())
    if (x.e == e) return x.meaning;
  return "?";
}

Effect effect_from_name(std::string_view name) {
  std::string all;
  for (const auto& x : entries()) {
    if (x.name == name) return x.e;
    all += (all.empty() ? "" : ", ") + std::string(x.name);
  }
  throw InputError("unknown effect '" + std::string(name) + "'; the catalog has: " + all);
}

EffectContext make_context(const Dataset& d) {
  EffectContext c;
  std::vector<double> xs, ts, vs;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) {
      xs.push_back(d.x[k]);
      ts.push_back(d.t[k]);
      vs.push_back(std::abs(d.v[k]));
    }
  const auto [xl, xh] = std::minmax_element(xs.begin(), xs.end());
  c.x_mid = 0.5 * (*xl + *xh);
  c.x_half = std::max(1e-9, 0.5 * (*xh - *xl));
  c.t_mid = 0.5 * (ts.front() + ts.back());
  c.t_half = std::max(1e-9, 0.5 * (ts.back() - ts.front()));
  c.v_ref = std::max(1e-9, percentile(vs, 0.95));
  c.v_rest = 0.02 * c.v_ref;
  {
    std::vector<double> h;
    for (std::size_t k = 1; k < d.size(); ++k) h.push_back(d.t[k] - d.t[k - 1]);
    c.h_med = std::max(1e-9, percentile(h, 0.5));
  }
  estimate_levels(d, c);
  c.dwell_s0 = 3.0 * c.x_ba;
  if (d.has_Fn) {
    double s = 0.0;
    for (double f : d.Fn) s += f;
    c.Fn0 = s / static_cast<double>(d.Fn.size());
  }
  return c;
}

std::vector<double> travel_since_reversal(const Dataset& d, const EffectContext& c,
                                          std::vector<std::size_t>* turn) {
  std::vector<double> s(d.size(), 0.0);
  if (turn) turn->assign(d.size(), 0);
  if (d.size() == 0) return s;
  // The turning points: the extreme position before each change of direction.
  std::vector<std::size_t> turns = {0};
  double dir = 0.0, x_ext = d.x.front();
  std::size_t k_ext = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (std::abs(d.v[k]) > c.v_rest) {
      const double dk = sgn(d.v[k]);
      if (dir != 0.0 && dk != dir) turns.push_back(k_ext), x_ext = d.x[k], k_ext = k;
      dir = dk;
    }
    if (dir != 0.0 && dir * (d.x[k] - x_ext) > 0) x_ext = d.x[k], k_ext = k;
  }
  std::size_t i = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    while (i + 1 < turns.size() && turns[i + 1] <= k) ++i;
    s[k] = std::abs(d.x[k] - d.x[turns[i]]);
    if (turn) (*turn)[k] = turns[i];
  }
  return s;
}

double standstill(const EffectContext& c) { return 0.05 * c.v_rest; }

std::vector<MotionStart> motion_starts(const Dataset& d, const EffectContext& c) {
  // A rest: |v| below v_rest, and standing still (|v| below a twentieth of that) for half of
  // dwell_min at a stretch in it (a slow presliding oscillation also stays below v_rest, but
  // passes through zero only for instants). The rest the record begins in counts from the record's
  // start, and only where the position stays within two encoder counts (the record's smallest
  // step) until the start: a presliding sweep of micrometres is motion, and leaves the length of
  // the rest before it unknown.
  const double still = standstill(c);
  std::vector<MotionStart> out;
  double rest_since = d.t.front();
  bool resting = std::abs(d.v.front()) < c.v_rest, first = true;
  double count = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < d.size(); ++k)
    if (const double dx = std::abs(d.x[k] - d.x[k - 1]); dx > 0.0) count = std::min(count, dx);
  double stood = 0.0, run = 0.0;  // the longest and the current time standing still [s]
  // The rest's length counts from its first sample standing still (the slow tail of the stroke
  // before it, below v_rest, is still motion).
  double still_since = std::abs(d.v.front()) < still ? d.t.front() : NAN;
  for (std::size_t k = 1; k < d.size(); ++k) {
    const bool r = std::abs(d.v[k]) < c.v_rest;
    if (r && !resting) rest_since = d.t[k], stood = run = 0.0, still_since = NAN;
    if (r && std::isnan(still_since) && std::abs(d.v[k]) < still) still_since = d.t[k];
    run = r && std::abs(d.v[k]) < still ? run + (d.t[k] - d.t[k - 1]) : 0.0;
    stood = std::max(stood, run);
    if (!r && resting) {
      // The motion began before |v| crossed v_rest: walk back to where it left (near) zero.
      std::size_t j = k;
      while (j > 0 && d.t[j - 1] > rest_since && std::abs(d.v[j - 1]) > still &&
             sgn(d.v[j - 1]) == sgn(d.v[k]))
        --j;
      bool known = !first;
      if (first) {
        double span = 0.0;
        for (std::size_t i = 0; i < j; ++i) span = std::max(span, std::abs(d.x[i] - d.x.front()));
        known = span <= 2.0 * count * (1.0 + 1e-9);
      }
      if (stood >= 0.5 * c.dwell_min && known && d.t[j] - rest_since >= c.dwell_min)
        out.push_back({j, d.t[j] - still_since, sgn(d.v[k])});
      first = false;
    }
    resting = r;
  }
  return out;
}

std::vector<double> dwell_weight(const Dataset& d, const EffectContext& c) {
  const std::size_t n = d.size();
  std::vector<double> w(n, 0.0);
  for (const auto& s : motion_starts(d, c)) {
    const double phi = std::log(1.0 + s.dwell / c.dwell_tau);
    for (std::size_t k = s.k > 0 ? s.k - 1 : 0; k < n; ++k) {
      if (k > s.k + 1 && std::abs(d.v[k]) < standstill(c)) break;  // at rest again
      const double q = std::abs(d.x[k] - d.x[s.k]) / c.dwell_s0;
      if (q > 30.0) break;
      w[k] = phi * std::exp(-q);
    }
  }
  return w;
}

bool effect_applicable(Effect e, const Dataset& d, const EffectContext& c) {
  switch (e) {
    case Effect::NormalLoad: return d.has_Fn && c.Fn0 != 0.0;
    case Effect::DwellStiction: return motion_starts(d, c).size() >= 3;
    case Effect::PositionPeriodic: return !c.wavelengths.empty();
    case Effect::TimeShift: return c.time_shift != 0.0;
    case Effect::SensorFilter: return c.filter_T > 0.0;
    case Effect::Backlash: {
      std::vector<std::size_t> turn;
      travel_since_reversal(d, c, &turn);
      return c.backlash > 0.0 && !turn.empty() && turn.back() > 0;
    }
    default: return true;
  }
}

std::vector<Column> effect_columns(Effect e) {
  using D = const Dataset&;
  using C = const EffectContext&;
  using G = std::span<const double>;
  using O = std::span<double>;
  std::vector<Column> v;
  switch (e) {
    case Effect::Inertia:
      v.push_back(col("M", "kg", false, [](D d, C, G, O o) {
        std::copy(d.a.begin(), d.a.end(), o.begin());
      }));
      break;
    case Effect::Offset:
      v.push_back(col("F0", "N", false, [](D, C, G, O o) { std::fill(o.begin(), o.end(), 1.0); }));
      break;
    case Effect::DirectionAsymmetry:
      v.push_back(col("dF", "N", true, [](D d, C, G g, O o) {
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = std::abs(g[k]);
      }));
      v.push_back(col("dFv", "N s/m", false, [](D d, C, G, O o) {
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = std::abs(d.v[k]);
      }));
      break;
    case Effect::PositionPeriodic:
      // Four columns per wavelength found (at most 3): additive and friction-level ripple.
      for (std::size_t i = 0; i < 3; ++i)
        for (int m = 0; m < 4; ++m) {
          const std::string nm = std::string(m < 2 ? "ripple" : "ripple_g") + std::to_string(i + 1) +
                                 (m % 2 ? "_cos" : "_sin");
          v.push_back(col(nm, "N", m >= 2, [i, m](D d, C c, G g, O o) {
            std::fill(o.begin(), o.end(), 0.0);
            if (i >= c.wavelengths.size()) return;
            const double w = 2 * std::numbers::pi / c.wavelengths[i];
            for (std::size_t k = 0; k < d.size(); ++k) {
              const double p = w * (d.x[k] - c.x_mid);
              o[k] = (m % 2 ? std::cos(p) : std::sin(p)) * (m >= 2 ? g[k] : 1.0);
            }
          }));
        }
      break;
    case Effect::PositionDependent:
      for (int n = 1; n <= 3; ++n)
        v.push_back(col("pos_P" + std::to_string(n), "N", false, [n](D d, C c, G, O o) {
          for (std::size_t k = 0; k < d.size(); ++k) o[k] = legendre(n, (d.x[k] - c.x_mid) / c.x_half);
        }));
      for (int n = 1; n <= 2; ++n)
        v.push_back(col("pos_gP" + std::to_string(n), "N", true, [n](D d, C c, G g, O o) {
          for (std::size_t k = 0; k < d.size(); ++k)
            o[k] = g[k] * legendre(n, (d.x[k] - c.x_mid) / c.x_half);
        }));
      break;
    case Effect::TimeDrift:
      v.push_back(col("drift", "N", false, [](D d, C c, G, O o) {
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = (d.t[k] - c.t_mid) / c.t_half;
      }));
      v.push_back(col("drift_g", "N", true, [](D d, C c, G g, O o) {
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = g[k] * (d.t[k] - c.t_mid) / c.t_half;
      }));
      break;
    case Effect::VelocityExtra:
      v.push_back(col("drag", "N", false, [](D d, C c, G, O o) {
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = d.v[k] * std::abs(d.v[k]) / c.v_ref;
      }));
      v.push_back(col("low_speed", "N", true, [](D d, C c, G g, O o) {
        for (std::size_t k = 0; k < d.size(); ++k)
          o[k] = g[k] * std::exp(-std::abs(d.v[k]) / (0.2 * c.v_ref));
      }));
      break;
    case Effect::DwellStiction:
      // Raised break-away level after a rest, fading with travel: the model simulated with
      // Fs/Fc raised by rho w (the second n values of g) less the model, and w g.
      v.push_back(col("dwell_response", "N", true, [](D d, C, G g, O o) {
        const std::size_t n = d.size();
        for (std::size_t k = 0; k < n; ++k) o[k] = g.size() >= 2 * n ? g[n + k] : 0.0;
      }));
      v.back().extra = ExtraOutput::Dwell;
      v.push_back(col("dwell_level", "N", true, [](D d, C c, G g, O o) {
        const std::vector<double> w = dwell_weight(d, c);
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = w[k] * g[k];
      }));
      break;
    case Effect::NormalLoad:
      v.push_back(col("mu_load", "N", true, [](D d, C c, G g, O o) {
        if (d.Fn.size() < d.size() || !(c.Fn0 != 0.0))
          throw InputError(d.source +
                           ": the normal_load effect needs a normal-force column (Fn, "
                           "e.g. --columns Fn=Fn_N) with a nonzero mean");
        for (std::size_t k = 0; k < d.size(); ++k) o[k] = g[k] * (d.Fn[k] / c.Fn0 - 1.0);
      }));
      break;
    case Effect::TimeShift:
      // The model along the motion tau earlier less the model, with the viscous share.
      v.push_back(transmission_column("shift_level", &EffectContext::time_shift, &shifted_motion,
                                      ExtraOutput::Shifted, "the model along the shifted motion"));
      break;
    case Effect::SensorFilter:
      v.push_back(channel_column("filter_level", [](D d, std::span<const double> y, C c, O o) {
        lowpass(d, y, c.filter_T, o);
      }));
      break;
    case Effect::Backlash:
      // The model along the contact's motion less the model, with the viscous share.
      v.push_back(transmission_column("backlash_level", &EffectContext::backlash,
                                      &through_dead_band, ExtraOutput::Contact,
                                      "the model along the contact's motion"));
      break;
    case Effect::Discovered:
      for (std::size_t i = 0; i < kMaxDiscovered; ++i)
        v.push_back(col("term" + std::to_string(i + 1), "-", false, [i](D d, C c, G, O o) {
          std::fill(o.begin(), o.end(), 0.0);
          if (i >= c.discovered.size()) return;
          const DiscoveredTerm& t = c.discovered[i];
          std::vector<double> f;
          if (needs_model_force(t.column)) {
            if (!c.discovered_force)
              throw InternalError("discovered term " + column_formula(t.column) +
                                  " without the model force it was discovered on");
            f = c.discovered_force(d);
          }
          const std::vector<double> y = library_values(t.column, d, c, f);
          for (std::size_t k = 0; k < d.size(); ++k) o[k] = t.coefficient * y[k];
        }));
      break;
  }
  return v;
}

}  // namespace gmslab::ident
