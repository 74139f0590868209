#include "core/control/limit_cycles.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>

#include "core/error.hpp"

namespace gmslab::control {

namespace {
constexpr double kStickVelocity = 1e-4;  // [m/s], AssemblySimulation::kSlipVelocity
// Where Newton stalls, a residual up to this many times the step's resolution 2 pi dt / T (a slip's
// events move faster than the mean rate 2 pi / T), and never above kMaxResidual, is accepted.
constexpr double kResolutionFactor = 8.0;
constexpr double kMaxResidual = 0.02;

bool has_integrator(const LeadCompensator& c) {
  for (int i = 0; i < c.sections(); ++i)
    if (c.section(i).p == 0.0) return true;
  return false;
}

LoopStepper make_stepper(const ClosedLoop& L, double scale, double horizon) {
  LoopConfig c = L.config;
  c.C.Kc *= scale;
  c.duration = horizon;
  return L.assembly ? loop_stepper(*L.assembly, L.port, c, horizon)
                    : loop_stepper(L.scenario, c, horizon);
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// One run of the section map from a state on the section to the next upward crossing.
struct MapRun {
  bool crossed = false;
  std::vector<double> z;      // state on the section at the crossing
  std::vector<double> range;  // per entry: max - min over the run
  double period = 0.0, amplitude = 0.0, mean = 0.0, stick = 0.0;
};

// Upward crossings of the level by the output, armed once the output fell below
// level - 0.1 x its last excursion above the level (or when it starts below the level); continuous:
// interpolated inside the step; sampled: at the first sample instant after the crossing.
class CrossingWatch {
 public:
  CrossingWatch(double level, bool sampled, long long every)
      : level_(level), sampled_(sampled), every_(every) {}
  void reset(double y) {
    ys_prev_ = y;
    armed_ = y < level_;
    above_ = last_above_ = 0.0;
  }
  // After a step from y0 to y1 (the stepper now at step index k): the interpolation weight of the
  // crossing in (0, 1], or -1 when none.
  double check(double y0, double y1, long long k) {
    if (y1 >= level_) {
      above_ = std::max(above_, y1 - level_);
    } else if (y0 >= level_) {  // down through the level: that excursion sets the hysteresis
      last_above_ = above_;
      above_ = 0.0;
    }
    if (last_above_ > 0.0 && y1 < level_ - 0.1 * last_above_) armed_ = true;
    if (sampled_) {
      if (k % every_ != 0) return -1.0;
      const bool up = armed_ && ys_prev_ < level_ && y1 >= level_;
      ys_prev_ = y1;
      return up ? 1.0 : -1.0;
    }
    if (armed_ && y0 < level_ && y1 >= level_) return (level_ - y0) / (y1 - y0);
    return -1.0;
  }
  void rearm() {
    armed_ = false;
    last_above_ = 0.0;
  }

 private:
  double level_;
  bool sampled_;
  long long every_;
  double ys_prev_ = 0.0, above_ = 0.0, last_above_ = 0.0;
  bool armed_ = false;
};

// The section map of the loop at one gain scale.
class SectionMap {
 public:
  SectionMap(const ClosedLoop& L, double scale, double level, double max_period, int returns)
      : st_(make_stepper(L, scale, max_period + 1.0)),
        level_(level),
        returns_(returns),
        mask_(st_.continuous_mask()),
        out_(st_.output_index()),
        vel_(st_.velocity_index()),
        max_steps_(std::llround(max_period / L.config.dt)),
        sampled_(L.config.sample_time > 0.0) {}

  // Interpolates the state between the step's start zp and end zc with weight th (flags from zc).
  void interpolate(const std::vector<double>& zp, const std::vector<double>& zc, double th,
                   std::vector<double>& z) const {
    z = zc;
    for (std::size_t i = 0; i < z.size(); ++i)
      if (mask_[i]) z[i] = zp[i] + th * (zc[i] - zp[i]);
    z[out_] = sampled_ ? z[out_] : level_;
  }

  // From z0 (on the section, step index 0) to the next crossing. The state is kept every
  // kCheckpoint steps (the entries' ranges are taken there); at the crossing the run goes back to
  // the last checkpoint and steps to the crossing again to have the state before its step.
  MapRun run(const std::vector<double>& z0) {
    constexpr long long kCheckpoint = 32;
    ++evaluations;
    MapRun r;
    st_.set_state(z0, 0);
    CrossingWatch watch(level_, sampled_, st_.sample_every());
    watch.reset(z0[out_]);
    std::vector<double> lo = z0, hi = z0;
    zk_ = z0;
    long long k_check = 0;
    int crossed = 0;
    double ymin = z0[out_], ymax = z0[out_], sum = 0.0, stick = 0.0, y0 = z0[out_];
    const double h = st_.dt();
    for (long long k = 0; k < max_steps_; ++k) {
      st_.step();
      const double y = st_.output();
      ymin = std::min(ymin, y), ymax = std::max(ymax, y);
      sum += y;
      stick += std::abs(st_.velocity()) < kStickVelocity;
      double th = watch.check(y0, y, st_.step_index());
      y0 = y;
      if (th > 0.0 && ++crossed < returns_) {  // one of the period's earlier crossings
        watch.rearm();
        th = -1.0;
      }
      if (th > 0.0) {
        // Back to the checkpoint, forward to the state before the crossing's step.
        st_.set_state(zk_, k_check);
        while (st_.step_index() < k) st_.step();
        st_.state_into(zp_);
        st_.step();
        st_.state_into(zc_);
        interpolate(zp_, zc_, th, r.z);
        r.crossed = true;
        r.period = (static_cast<double>(k) + th) * h;
        const double n = static_cast<double>(k + 1);
        r.mean = sum / n, r.stick = stick / n, r.amplitude = 0.5 * (ymax - ymin);
        break;
      }
      if ((k + 1) % kCheckpoint == 0) {
        st_.state_into(zk_);
        k_check = k + 1;
        for (std::size_t i = 0; i < zk_.size(); ++i)
          lo[i] = std::min(lo[i], zk_[i]), hi[i] = std::max(hi[i], zk_[i]);
      }
    }
    r.range.resize(lo.size());
    for (std::size_t i = 0; i < lo.size(); ++i) r.range[i] = hi[i] - lo[i];
    return r;
  }

  LoopStepper st_;
  double level_;
  int returns_;  // upward crossings per period
  std::vector<std::uint8_t> mask_;
  std::size_t out_, vel_;
  long long max_steps_;
  bool sampled_;
  int evaluations = 0;

 private:
  std::vector<double> zp_, zc_, zk_;
};

// Newton (after fixed-point iterations) on P(z) - z over the unknown entries.
class OrbitSolver {
 public:
  OrbitSolver(SectionMap& map, const OrbitOptions& opt) : map_(map), opt_(opt) {}
  double last_residual = 0.0, last_resolution = 0.0;  // of the last solve
  bool last_drift = false;  // the last solve's solution drifted (not periodic)

  // From z (on the section); `warm`: a neighbouring orbit whose unknowns, scales and Jacobian
  // start the iteration (quasi-Newton: Broyden's update after each accepted step).
  std::optional<PeriodicOrbit> solve(std::vector<double> z, const PeriodicOrbit* warm = nullptr) {
    MapRun r = map_.run(z);
    if (!r.crossed) return std::nullopt;
    const bool reuse = warm && warm->scale.size() == z.size() && !warm->unknowns.empty() &&
                       warm->jacobian.size() == warm->unknowns.size() * warm->unknowns.size();
    if (reuse)
      unknowns_ = warm->unknowns, scale_ = warm->scale;
    else
      choose_unknowns(r);
    double res = residual(z, r);
    for (int it = 0; !warm && it < opt_.fixed_point && res > opt_.tolerance; ++it) {
      MapRun r2 = map_.run(r.z);
      if (!r2.crossed) break;
      z = r.z, r = std::move(r2);
      res = residual(z, r);
    }
    // The map is only as smooth as one step resolves its events (a break-away one step later moves
    // the orbit by about 2 pi dt / T of its range): Newton stops there when it cannot do better.
    // (A sampled controller resolves them to its sample period.)
    const double resolution = map_.sampled_
                                  ? map_.st_.dt() * static_cast<double>(map_.st_.sample_every())
                                  : map_.st_.dt();
    const double step_noise = 2.0 * std::numbers::pi * resolution / r.period;
    // Differences over a few such steps, so that one event a step early or late does not dominate.
    // A sampled loop's map jumps by whole sample periods: wider central differences.
    central_ = map_.sampled_;
    fd_ = std::max(opt_.fd_step, (central_ ? 16.0 : 4.0) * step_noise);
    const auto n = static_cast<Eigen::Index>(unknowns_.size());
    Eigen::MatrixXd M =
        reuse ? Eigen::Map<const Eigen::MatrixXd>(warm->jacobian.data(), n, n) : jacobian(z, r);
    bool fresh = !reuse;
    for (int it = 0; it < opt_.newton && res > opt_.tolerance; ++it) {
      if (newton_step(z, r, res, M)) {
        fresh = false;
      } else if (!fresh) {
        M = jacobian(z, r), fresh = true;
      } else {
        break;
      }
    }
    last_residual = res, last_resolution = step_noise;
    if (res > std::max(opt_.tolerance, std::min(kResolutionFactor * step_noise, kMaxResidual)))
      return std::nullopt;
    if (!fresh && opt_.fresh_multipliers) M = jacobian(z, r), fresh = true;
    PeriodicOrbit o = orbit(z, r, M, res, fresh);
    if (!o.stable) check_by_iteration(o, M, std::max(0.02, 4.0 * step_noise));
    if (!warm && o.stable && drifts(o)) {
      last_drift = true;
      return std::nullopt;
    }
    return o;
  }

 private:
  void choose_unknowns(const MapRun& r) {
    unknowns_.clear();
    scale_.assign(r.z.size(), 1.0);
    for (std::size_t i = 0; i < r.z.size(); ++i) {
      scale_[i] = r.range[i];
      if (map_.mask_[i] && r.range[i] > 0.0 && (map_.sampled_ || i != map_.out_))
        unknowns_.push_back(i);
    }
  }
  double residual(const std::vector<double>& z, const MapRun& r) const {
    double res = 0.0;
    for (std::size_t i : unknowns_) res = std::max(res, std::abs(r.z[i] - z[i]) / scale_[i]);
    return res;
  }
  // dP/dz in the scaled unknowns (forward differences).
  Eigen::MatrixXd jacobian(const std::vector<double>& z, const MapRun& r) {
    const std::size_t n = unknowns_.size();
    Eigen::MatrixXd M =
        Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    for (std::size_t j = 0; j < n; ++j) {
      std::vector<double> zj = z;
      const double e = fd_ * scale_[unknowns_[j]];
      zj[unknowns_[j]] += e;
      const MapRun rj = map_.run(zj);
      if (!rj.crossed) continue;  // a column left zero: the perturbed orbit did not return
      const MapRun* base = &r;
      MapRun rm;
      if (central_) {
        zj[unknowns_[j]] -= 2.0 * e;
        rm = map_.run(zj);
        if (!rm.crossed) continue;
        base = &rm;
      }
      const double width = central_ ? 2.0 * fd_ : fd_;
      for (std::size_t i = 0; i < n; ++i)
        M(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            (rj.z[unknowns_[i]] - base->z[unknowns_[i]]) / scale_[unknowns_[i]] / width;
    }
    return M;
  }
  // (M - I) du = -(P(z) - z), with a backtracking line search on the residual.
  // Quasi-Newton step (M - I) du = -(P(z) - z) with a backtracking line search on the residual;
  // M takes Broyden's rank-one update from the accepted step.
  bool newton_step(std::vector<double>& z, MapRun& r, double& res, Eigen::MatrixXd& M) {
    const auto n = static_cast<Eigen::Index>(unknowns_.size());
    const auto scaled = [&](const std::vector<double>& v) {
      Eigen::VectorXd out(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        const std::size_t k = unknowns_[static_cast<std::size_t>(i)];
        out(i) = v[k] / scale_[k];
      }
      return out;
    };
    const Eigen::VectorXd g = scaled(r.z) - scaled(z);
    const Eigen::VectorXd du =
        (M - Eigen::MatrixXd::Identity(n, n)).colPivHouseholderQr().solve(-g);
    if (!du.allFinite()) return false;
    for (double lam = 1.0; lam > 0.2; lam *= 0.5) {
      std::vector<double> zn = z;
      for (Eigen::Index i = 0; i < n; ++i) {
        const std::size_t k = unknowns_[static_cast<std::size_t>(i)];
        zn[k] += lam * du(i) * scale_[k];
      }
      MapRun rn = map_.run(zn);
      if (!rn.crossed) continue;
      const double rr = residual(zn, rn);
      if (rr < res) {
        const Eigen::VectorXd s = lam * du, dP = scaled(rn.z) - scaled(r.z);
        if (s.squaredNorm() > 0.0) M += (dP - M * s) * s.transpose() / s.squaredNorm();
        z = std::move(zn), r = std::move(rn), res = rr;
        return true;
      }
    }
    return false;
  }
  // A solution accepted at the step's resolution may be a slowly decaying oscillation: over
  // kDriftReturns more returns of the map its amplitude and period stay within 2 %, or it is none.
  bool drifts(const PeriodicOrbit& o) {
    constexpr int kDriftReturns = 8;
    std::vector<double> z = o.section_state;
    for (int it = 0; it < kDriftReturns; ++it) {
      const MapRun r = map_.run(z);
      if (!r.crossed || std::abs(r.amplitude - o.amplitude) > 0.02 * o.amplitude ||
          std::abs(r.period - o.period) > 0.02 * o.period)
        return true;
      z = r.z;
    }
    return false;
  }

 public:  // the branch tracer (hunting_map) sets the unknowns and scales and builds orbits here
  // The multipliers say unstable: the second method, iterating the map from the orbit displaced
  // by `size` (scaled) along the dominant eigenvector. The displacement's growth per period over
  // kIterations returns, (d_n / d_0)^(1/n), is kept; below 1 + 1e-2 (no growth: an attracting
  // orbit, or a family of orbits whose never-slipping elements keep any offset, multiplier 1) the
  // orbit is stable, the finite differences having straddled an event (a break-away a step earlier
  // or later).
  void check_by_iteration(PeriodicOrbit& o, const Eigen::MatrixXd& M, double size) {
    constexpr int kIterations = 6;
    const auto n = static_cast<Eigen::Index>(unknowns_.size());
    if (n == 0) return;
    Eigen::EigenSolver<Eigen::MatrixXd> es(M, true);
    Eigen::Index imax = 0;
    for (Eigen::Index i = 1; i < n; ++i)
      if (std::abs(es.eigenvalues()(i)) > std::abs(es.eigenvalues()(imax))) imax = i;
    Eigen::VectorXd dir = es.eigenvectors().col(imax).real();
    if (dir.cwiseAbs().maxCoeff() == 0.0) dir = es.eigenvectors().col(imax).imag();
    dir *= size / dir.cwiseAbs().maxCoeff();
    std::vector<double> z = o.section_state;
    for (Eigen::Index i = 0; i < n; ++i)
      z[unknowns_[static_cast<std::size_t>(i)]] +=
          dir(i) * scale_[unknowns_[static_cast<std::size_t>(i)]];
    double d = size;
    for (int it = 0; it < kIterations; ++it) {
      const MapRun r = map_.run(z);
      if (!r.crossed) return;  // left the section's reach: unstable as the multipliers say
      z = r.z;
    }
    d = 0.0;
    for (std::size_t k : unknowns_)
      d = std::max(d, std::abs(z[k] - o.section_state[k]) / scale_[k]);
    o.growth = std::pow(d / size, 1.0 / kIterations);
    o.stable = o.growth < 1.0 + 1e-2;
  }

  PeriodicOrbit orbit(const std::vector<double>& z, const MapRun& r, const Eigen::MatrixXd& M,
                      double res, bool fresh) const {
    PeriodicOrbit o;
    o.unknowns = unknowns_;
    o.scale = scale_;
    o.jacobian.assign(M.data(), M.data() + M.size());
    o.multipliers_fresh = fresh;
    o.amplitude = r.amplitude, o.period = r.period, o.mean = r.mean, o.stick_fraction = r.stick;
    o.residual = res;
    o.section_state = z;
    o.level = map_.level_;
    o.returns = map_.returns_;
    if (M.size() > 0) {
      const Eigen::VectorXcd ev = Eigen::EigenSolver<Eigen::MatrixXd>(M, false).eigenvalues();
      for (Eigen::Index i = 0; i < ev.size(); ++i) o.multipliers.push_back(ev(i));
    }
    std::sort(o.multipliers.begin(), o.multipliers.end(),
              [](const auto& a, const auto& b) { return std::abs(a) > std::abs(b); });
    o.stable = o.multipliers.empty() || std::abs(o.multipliers.front()) < 1.0;
    return o;
  }

  SectionMap& map_;
  const OrbitOptions& opt_;
  std::vector<std::size_t> unknowns_;
  std::vector<double> scale_;
  double fd_ = 1e-4;
  bool central_ = false;
};

// The short simulation from a state at step 0: the state at its last upward crossing of the level
// (after opt.seed_crossings of them), with the time between the last two; nullopt when it crossed
// fewer than two times.
struct Seed {
  std::vector<double> z;
  double period = 0.0;  // of `returns` crossings [s]
  int crossings = 0;
  int returns = 1;  // crossings per period (the cycle may cross the level several times upward)
  double stopped_at = 0.0;  // > 0: the crossings stopped then (the loop came to rest) [s]
};
// The crossings per period k (1..4) whose state returns closest, the smallest one within twice the
// best distance plus `slack`; the distance: max over continuous entries of |z_last - z_last-k| /
// range.
struct Return {
  int k = 1;
  double dist = 1e300;
};
Return best_return(const std::vector<std::vector<double>>& zs, const std::vector<double>& lo,
                   const std::vector<double>& hi, const std::vector<std::uint8_t>& mask,
                   double slack) {
  const std::size_t n = zs.size();
  const auto dist = [&](std::size_t k) {
    double d = 0.0;
    for (std::size_t i = 0; i < zs[n - 1].size(); ++i)
      if (mask[i] && hi[i] > lo[i])
        d = std::max(d, std::abs(zs[n - 1][i] - zs[n - 1 - k][i]) / (hi[i] - lo[i]));
    return d;
  };
  Return r;
  const std::size_t kmax = std::min<std::size_t>(4, n - 1);
  double best = 1e300;
  for (std::size_t k = 1; k <= kmax; ++k) best = std::min(best, dist(k));
  for (std::size_t k = 1; k <= kmax; ++k)
    if (const double d = dist(k); d <= 2.0 * best + slack) return {static_cast<int>(k), d};
  return r;
}

// The short simulation: from z0 (or rest) until the crossings repeat (the best return within
// kSeedSettled of the entries' ranges between the last five crossings) or opt.seed_duration.
Seed seed_run(const ClosedLoop& L, double level, const std::vector<double>* z0,
              const OrbitOptions& opt) {
  constexpr double kSeedSettled = 0.01;
  constexpr double kSeedMinTime = 10.0;  // [s]: a transient may look periodic for a while
  LoopStepper st = make_stepper(L, 1.0, opt.seed_duration + 1.0);
  if (z0) st.set_state(*z0, 0);
  const std::vector<std::uint8_t> mask = st.continuous_mask();
  const bool sampled = L.config.sample_time > 0.0;
  const double resolution = L.config.dt * static_cast<double>(st.sample_every());
  CrossingWatch watch(level, sampled, st.sample_every());
  std::vector<double> zp = st.state(), zc;
  std::vector<double> lo = zp, hi = zp, seg_lo = zp, seg_hi = zp;
  std::vector<std::pair<std::vector<double>, std::vector<double>>> segs;
  watch.reset(zp[st.output_index()]);
  Seed s;
  std::vector<std::vector<double>> zs;
  std::vector<double> ts;
  Return ret;
  const long long steps = std::llround(opt.seed_duration / L.config.dt);
  for (long long k = 0; k < steps; ++k) {
    st.step();
    st.state_into(zc);
    for (std::size_t i = 0; i < zc.size(); ++i)
      seg_lo[i] = std::min(seg_lo[i], zc[i]), seg_hi[i] = std::max(seg_hi[i], zc[i]);
    const double th = watch.check(zp[st.output_index()], zc[st.output_index()], st.step_index());
    if (th > 0.0) {
      ts.push_back((static_cast<double>(k) + th) * L.config.dt);
      ++s.crossings;
      std::vector<double> z = zc;
      for (std::size_t i = 0; i < zc.size(); ++i)
        if (mask[i]) z[i] = zp[i] + th * (zc[i] - zp[i]);
      if (!sampled) z[st.output_index()] = level;
      zs.push_back(std::move(z));
      segs.push_back({seg_lo, seg_hi});
      seg_lo = seg_hi = zc;
      if (zs.size() > 5) zs.erase(zs.begin()), ts.erase(ts.begin()), segs.erase(segs.begin());
      // The entries' ranges over the intervals between the kept crossings.
      lo = segs.back().first, hi = segs.back().second;
      for (std::size_t j = 1; j < segs.size(); ++j)
        for (std::size_t i = 0; i < lo.size(); ++i)
          lo[i] = std::min(lo[i], segs[j].first[i]), hi[i] = std::max(hi[i], segs[j].second[i]);
      watch.rearm();
      if (zs.size() >= 3) {
        // A sampled loop's crossings differ by the sample period's resolution.
        const double slack =
            std::min(kMaxResidual, 1e-3 + kResolutionFactor * 2.0 * std::numbers::pi * resolution /
                                              (ts.back() - ts[ts.size() - 2]));
        ret = best_return(zs, lo, hi, mask, slack);
        // Settled: the state returns, and the output's excursion over the last period is that of
        // the one before within 1 % (a slowly decaying oscillation returns close too, but shrinks).
        const std::size_t nk = static_cast<std::size_t>(ret.k), o = st.output_index();
        bool same_swing = segs.size() >= 2 * nk;
        if (same_swing) {
          double lo1 = 1e300, hi1 = -1e300, lo2 = 1e300, hi2 = -1e300;
          for (std::size_t j = 0; j < nk; ++j) {
            const auto& a = segs[segs.size() - 1 - j];
            const auto& b = segs[segs.size() - 1 - nk - j];
            lo1 = std::min(lo1, a.first[o]), hi1 = std::max(hi1, a.second[o]);
            lo2 = std::min(lo2, b.first[o]), hi2 = std::max(hi2, b.second[o]);
          }
          same_swing = std::abs((hi1 - lo1) - (hi2 - lo2)) <= 0.01 * (hi1 - lo1);
        }
        if (ret.dist <= kSeedSettled + slack && same_swing && s.crossings >= opt.seed_crossings &&
            ts.back() >= std::min(kSeedMinTime, opt.seed_duration))
          break;
      }
    }
    std::swap(zp, zc);
  }
  if (s.crossings < 2) return s;
  // Crossings that stopped well before the end (a transient that came to rest): no seed.
  const double t_end = static_cast<double>(st.step_index()) * L.config.dt;
  if (t_end - ts.back() > 3.0 * (ts.back() - ts[ts.size() - 2]) + 1.0) {
    s.stopped_at = ts.back();
    return s;
  }
  if (zs.size() < 3) ret = Return{1, 0.0};
  s.returns = ret.k;
  s.z = zs.back();
  s.period = ts.back() - ts[ts.size() - 1 - static_cast<std::size_t>(s.returns)];
  return s;
}

// Mean of the output over the last 20 % of a simulation from rest (the section level of a loop
// without integrator).
double tail_mean(const ClosedLoop& L, double duration) {
  LoopStepper st = make_stepper(L, 1.0, duration + 1.0);
  const long long steps = std::llround(duration / L.config.dt), k0 = steps * 4 / 5;
  double sum = 0.0;
  for (long long k = 0; k < steps; ++k) {
    st.step();
    if (k >= k0) sum += st.output();
  }
  return sum / static_cast<double>(std::max(1LL, steps - k0));
}

bool same_orbit(const PeriodicOrbit& a, const PeriodicOrbit& b) {
  return std::abs(a.amplitude - b.amplitude) <= 0.02 * std::max(a.amplitude, b.amplitude) &&
         std::abs(a.period - b.period) <= 0.02 * std::max(a.period, b.period);
}

void check_loop(const ClosedLoop& L) {
  if (L.config.reference.kind != Signal::Kind::Constant)
    throw InputError(
        "periodic orbits: the reference must be constant (the loop's orbits around a set point)");
}
}  // namespace

const PeriodicOrbit* OrbitReport::stable() const {
  const PeriodicOrbit* best = nullptr;
  for (const PeriodicOrbit& o : orbits)
    if (o.stable && (!best || o.amplitude > best->amplitude)) best = &o;
  return best;
}

OrbitReport find_orbits(const ClosedLoop& L, const OrbitOptions& opt, const HuntingReport* df) {
  check_loop(L);
  OrbitReport rep;
  rep.dt = L.config.dt;
  const double r = L.config.reference(0.0);
  std::ostringstream method;
  method << "shooting on the loop's section map (upward crossings of ";
  double level = r;
  try {
    if (!has_integrator(L.config.C)) level = tail_mean(L, opt.seed_duration);
    method << (has_integrator(L.config.C) ? "the reference " : "the settled mean ") << num(level)
           << " m), seeded by a simulation from rest over up to " << num(opt.seed_duration) << " s";
    std::vector<std::pair<std::string, Seed>> seeds;
    seeds.push_back({"simulation", seed_run(L, level, nullptr, opt)});
    const HuntingCycle* hc = df ? df->hunting() : nullptr;
    if (hc && hc->amplitude > 0.0) {
      LoopStepper st = make_stepper(L, 1.0, 1.0);
      std::vector<double> z0(st.state().size(), 0.0);
      z0[st.output_index()] = level - hc->amplitude;
      method << " and from rest at the describing function's amplitude " << num(hc->amplitude)
             << " m below it";
      seeds.push_back({"describing function", seed_run(L, level, &z0, opt)});
    }
    std::vector<std::string> why;
    for (auto& [name, seed] : seeds) {
      if (seed.stopped_at > 0.0) {
        why.push_back("the " + name + " seed stopped crossing the level after " +
                      num(seed.stopped_at) + " s of " + num(opt.seed_duration) +
                      " s (the loop settles)");
        continue;
      }
      if (seed.crossings < 2) {
        why.push_back("the " + name + " seed crossed the level " + std::to_string(seed.crossings) +
                      " time(s) in " + num(opt.seed_duration) +
                      " s (the loop settles, or moves slower than this span can show: no "
                      "orbit of a period above half of it is searched)");
        continue;
      }
      const double max_period =
          opt.max_period > 0.0 ? opt.max_period : std::max(3.0 * seed.period, 0.05);
      SectionMap map(L, 1.0, level, max_period, seed.returns);
      OrbitSolver solver(map, opt);
      std::optional<PeriodicOrbit> o = solver.solve(seed.z);
      rep.map_evaluations += map.evaluations;
      if (!o && solver.last_drift) {
        why.push_back("the " + name +
                      " seed's solution drifts over further periods (a slowly settling transient, "
                      "not a periodic orbit)");
        continue;
      }
      if (!o) {
        why.push_back("Newton from the " + name + " seed did not converge within " +
                      std::to_string(opt.newton) + " iterations (scaled residual " +
                      num(solver.last_residual) + " above the step's resolution " +
                      num(solver.last_resolution) + "; periods up to " + num(max_period) + " s)");
        continue;
      }
      if (!(o->amplitude < 100.0 * std::max(std::abs(level), 1e-3))) {
        why.push_back("the " + name +
                      " seed's orbit grows beyond 100 x the set point (the loop diverges)");
        continue;
      }
      o->seed = name;
      o->map_evaluations = map.evaluations;
      if (std::none_of(rep.orbits.begin(), rep.orbits.end(),
                       [&](const PeriodicOrbit& p) { return same_orbit(p, *o); }))
        rep.orbits.push_back(std::move(*o));
    }
    if (rep.orbits.empty()) {
      rep.not_found = "no periodic orbit found:";
      for (const auto& w : why) rep.not_found += " " + w + ";";
      rep.not_found.pop_back();
    }
  } catch (const SimulationError& e) {
    rep.not_found = std::string("no periodic orbit: the loop diverges (") + e.what() + ")";
  }
  rep.method = method.str();
  std::sort(
      rep.orbits.begin(), rep.orbits.end(),
      [](const PeriodicOrbit& a, const PeriodicOrbit& b) { return a.amplitude > b.amplitude; });
  return rep;
}

std::optional<PeriodicOrbit> continue_orbit(const ClosedLoop& L, const PeriodicOrbit& from,
                                            double scale, const OrbitOptions& opt) {
  check_loop(L);
  const double max_period = opt.max_period > 0.0 ? opt.max_period : 3.0 * from.period;
  SectionMap map(L, scale, from.level, max_period, from.returns);
  OrbitSolver solver(map, opt);
  std::optional<PeriodicOrbit> o;
  try {
    o = solver.solve(from.section_state, &from);
  } catch (const SimulationError&) {
    return std::nullopt;
  }
  if (o) {
    o->gain_scale = scale;
    o->seed = "continuation";
    o->map_evaluations = map.evaluations;
  }
  return o;
}

namespace {
// Pseudo-arclength continuation of an orbit's branch in x = (u, p): u the unknown entries of the
// section state divided by their ranges over the last orbit (rescaled at each point), p = ln(gain
// scale). F(x) = P(u; p) - u; its Jacobian A = [M - I, b] (M = dP/du, b = dP/dp by finite
// differences, fresh at each point; Broyden's update inside the corrector). Each step: predictor
// x + h t along the unit tangent t (A t = 0), corrector Newton on [F(x); t . (x - x_pred)] = 0. A
// fold is where t's p-component changes sign: the branch turns around in the gain, one real
// multiplier crossing +1 there.
class BranchTracer {
 public:
  struct Node {
    PeriodicOrbit orbit;
    double p = 0.0;
    std::vector<double> z;      // the full section state
    std::vector<double> scale;  // the unknowns' scales at this node
    Eigen::MatrixXd A;          // [M - I, b] in this node's scaling
    Eigen::VectorXd t;          // unit tangent (oriented along the trace)
    double h = 0.0;             // the arclength step that reached it
  };

  BranchTracer(const ClosedLoop& L, const PeriodicOrbit& start, const OrbitOptions& opt)
      : L_(L),
        opt_(opt),
        level_(start.level),
        returns_(start.returns),
        max_period_(opt.max_period > 0.0 ? opt.max_period : 3.0 * start.period),
        unknowns_(start.unknowns) {}

  int evaluations() const { return evaluations_ + (map_ ? map_->evaluations : 0); }

  // The start node (gain scale of `start`), its tangent oriented towards increasing p when up.
  std::optional<Node> start_node(const PeriodicOrbit& start, bool up) {
    Node nd;
    nd.orbit = start;
    nd.p = std::log(start.gain_scale);
    nd.z = start.section_state;
    nd.scale = start.scale;
    const MapRun r = map_at(nd.p).run(nd.z);
    if (!r.crossed) return std::nullopt;
    set_resolution(r.period);
    nd.A = jacobian(nd.z, nd.scale, nd.p, r);
    Eigen::VectorXd dir = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(unknowns_.size()) + 1);
    dir(dir.size() - 1) = up ? 1.0 : -1.0;
    if (!tangent(nd.A, dir, nd.t)) return std::nullopt;
    return nd;
  }

  // The next node from `nd` with arclength step h (clamped to p in [p_lo, p_hi]: there the
  // constraint is p = the bound). nullopt: the corrector did not converge.
  std::optional<Node> step(const Node& nd, double h, double p_lo, double p_hi, bool* at_bound) {
    const auto n = static_cast<Eigen::Index>(unknowns_.size());
    Eigen::VectorXd x0 = pack(nd.z, nd.scale, nd.p);
    Eigen::VectorXd xp = x0 + h * nd.t;
    Eigen::VectorXd c = nd.t;
    *at_bound = false;
    if (xp(n) > p_hi || xp(n) < p_lo) {  // natural-parameter step onto the range's end
      const double pb = xp(n) > p_hi ? p_hi : p_lo;
      xp = x0 + (pb - x0(n)) / nd.t(n) * nd.t;
      xp(n) = pb;
      c = Eigen::VectorXd::Zero(n + 1);
      c(n) = 1.0;
      *at_bound = true;
    }
    Eigen::VectorXd x;
    std::vector<double> z;
    MapRun r;
    double res = 0.0;
    // Newton on [F(x); c . (x - xp)] = 0 from xp; false when it does not converge or lands far
    // from the prediction (a jump to another branch).
    const auto correct = [&](const Eigen::VectorXd& c) {
      Eigen::MatrixXd A = nd.A;
      x = xp;
      z = unpack(x, nd.z, nd.scale);
      r = map_at(x(n)).run(z);
      if (!r.crossed) return false;
      Eigen::VectorXd g = scaled(r.z, nd.scale) - x.head(n);
      res = g.cwiseAbs().maxCoeff();
      bool fresh = false;
      for (int it = 0; it < opt_.newton && res > opt_.tolerance; ++it) {
        Eigen::MatrixXd K(n + 1, n + 1);
        K.topRows(n) = A;
        K.row(n) = c.transpose();
        Eigen::VectorXd rhs(n + 1);
        rhs.head(n) = -g;
        rhs(n) = -c.dot(x - xp);
        const Eigen::VectorXd dx = K.colPivHouseholderQr().solve(rhs);
        bool accepted = false;
        for (double lam = 1.0; dx.allFinite() && lam > 0.2 && !accepted; lam *= 0.5) {
          const Eigen::VectorXd xn = x + lam * dx;
          if (xn(n) > p_hi + 1e-9 || xn(n) < p_lo - 1e-9) continue;  // outside the map's range
          const std::vector<double> zn = unpack(xn, nd.z, nd.scale);
          MapRun rn = map_at(xn(n)).run(zn);
          if (!rn.crossed) continue;
          const Eigen::VectorXd gn = scaled(rn.z, nd.scale) - xn.head(n);
          const double rr = gn.cwiseAbs().maxCoeff();
          if (rr < res) {
            const Eigen::VectorXd s = xn - x;
            A += (gn - g - A * s) * s.transpose() / s.squaredNorm();
            x = xn, z = zn, r = std::move(rn), g = gn, res = rr, accepted = true;
          }
        }
        if (accepted) continue;
        if (fresh) break;
        A = jacobian(z, nd.scale, x(n), r), fresh = true;
      }
      if (res > std::max(opt_.tolerance, std::min(kResolutionFactor * noise_, kMaxResidual)))
        return false;
      return (x - xp).norm() <= 0.5 * std::abs(h) + 0.05;
    };
    // Where the arclength corrector fails away from a fold (the branch steep in the gain), the
    // natural-parameter one (the gain fixed at the prediction's) is tried.
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n + 1);
    e(n) = 1.0;
    if (!correct(c) && (*at_bound || std::abs(nd.t(n)) < 0.2 || !correct(e))) return std::nullopt;
    std::optional<Node> next = node(x(n), z, nd, r, res);
    if (next) next->h = nd.t.dot(x - x0);
    return next;
  }

  // The branch point's orbit from a converged state: fresh Jacobian in the orbit's own scaling,
  // multipliers, stability (the second method where the finite differences say unstable).
  std::optional<Node> node(double p, const std::vector<double>& z, const Node& prev,
                           const MapRun& r, double res) {
    Node nd;
    nd.p = p;
    nd.z = z;
    nd.scale = prev.scale;
    for (std::size_t k : unknowns_)
      if (r.range[k] > 0.0) nd.scale[k] = r.range[k];
    set_resolution(r.period);
    nd.A = jacobian(z, nd.scale, p, r);
    // The previous tangent in this node's scaling orients the new one.
    const auto n = static_cast<Eigen::Index>(unknowns_.size());
    Eigen::VectorXd dir = prev.t;
    for (Eigen::Index i = 0; i < n; ++i) {
      const std::size_t k = unknowns_[static_cast<std::size_t>(i)];
      dir(i) *= prev.scale[k] / nd.scale[k];
    }
    if (!tangent(nd.A, dir, nd.t)) return std::nullopt;
    SectionMap& map = map_at(p);
    OrbitSolver solver(map, opt_);
    solver.unknowns_ = unknowns_, solver.scale_ = nd.scale, solver.fd_ = fd_,
    solver.central_ = central_;
    const Eigen::MatrixXd M = nd.A.leftCols(n) + Eigen::MatrixXd::Identity(n, n);
    nd.orbit = solver.orbit(z, r, M, res, true);
    if (!nd.orbit.stable) solver.check_by_iteration(nd.orbit, M, std::max(0.02, 4.0 * noise_));
    nd.orbit.gain_scale = std::exp(p);
    nd.orbit.seed = "continuation";
    return nd;
  }

 private:
  SectionMap& map_at(double p) {
    if (!map_ || map_p_ != p) {
      if (map_) evaluations_ += map_->evaluations;
      map_ = std::make_unique<SectionMap>(L_, std::exp(p), level_, max_period_, returns_);
      map_p_ = p;
    }
    return *map_;
  }
  void set_resolution(double period) {
    const double resolution = L_.config.sample_time > 0.0 ? L_.config.sample_time : L_.config.dt;
    noise_ = 2.0 * std::numbers::pi * resolution / period;
    central_ = L_.config.sample_time > 0.0;
    fd_ = std::max(opt_.fd_step, (central_ ? 16.0 : 4.0) * noise_);
  }
  Eigen::VectorXd scaled(const std::vector<double>& z, const std::vector<double>& scale) const {
    Eigen::VectorXd u(static_cast<Eigen::Index>(unknowns_.size()));
    for (std::size_t i = 0; i < unknowns_.size(); ++i)
      u(static_cast<Eigen::Index>(i)) = z[unknowns_[i]] / scale[unknowns_[i]];
    return u;
  }
  Eigen::VectorXd pack(const std::vector<double>& z, const std::vector<double>& scale,
                       double p) const {
    Eigen::VectorXd x(static_cast<Eigen::Index>(unknowns_.size()) + 1);
    x.head(x.size() - 1) = scaled(z, scale);
    x(x.size() - 1) = p;
    return x;
  }
  std::vector<double> unpack(const Eigen::VectorXd& x, std::vector<double> z,
                             const std::vector<double>& scale) const {
    for (std::size_t i = 0; i < unknowns_.size(); ++i)
      z[unknowns_[i]] = x(static_cast<Eigen::Index>(i)) * scale[unknowns_[i]];
    return z;
  }
  // [dP/du - I, dP/dp] at (z, p) (forward differences; central for a sampled loop).
  Eigen::MatrixXd jacobian(const std::vector<double>& z, const std::vector<double>& scale, double p,
                           const MapRun& r) {
    const auto n = static_cast<Eigen::Index>(unknowns_.size());
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n + 1);
    const Eigen::VectorXd base = scaled(r.z, scale);
    for (Eigen::Index j = 0; j <= n; ++j) {
      const auto at = [&](double sign) -> std::optional<Eigen::VectorXd> {
        std::vector<double> zj = z;
        double pj = p;
        if (j < n)
          zj[unknowns_[static_cast<std::size_t>(j)]] +=
              sign * fd_ * scale[unknowns_[static_cast<std::size_t>(j)]];
        else
          pj += sign * fd_;
        const MapRun rj = map_at(pj).run(zj);
        if (!rj.crossed) return std::nullopt;
        return scaled(rj.z, scale);
      };
      const std::optional<Eigen::VectorXd> plus = at(1.0);
      const std::optional<Eigen::VectorXd> minus = central_ ? at(-1.0) : std::optional(base);
      if (plus && minus) A.col(j) = (*plus - *minus) / (central_ ? 2.0 * fd_ : fd_);
    }
    map_at(p);
    A.leftCols(n) -= Eigen::MatrixXd::Identity(n, n);
    return A;
  }
  // The unit null vector of A (n x (n+1)) with a positive component along dir.
  static bool tangent(const Eigen::MatrixXd& A, const Eigen::VectorXd& dir, Eigen::VectorXd& t) {
    const auto n = A.rows();
    Eigen::MatrixXd K(n + 1, n + 1);
    K.topRows(n) = A;
    K.row(n) = dir.transpose();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
    rhs(n) = 1.0;
    t = K.colPivHouseholderQr().solve(rhs);
    if (!t.allFinite() || t.norm() == 0.0) return false;
    t.normalize();
    if (t.dot(dir) < 0.0) t = -t;
    return true;
  }

  const ClosedLoop& L_;
  const OrbitOptions& opt_;
  double level_;
  int returns_;
  double max_period_;
  std::vector<std::size_t> unknowns_;
  std::unique_ptr<SectionMap> map_;
  double map_p_ = 0.0;
  int evaluations_ = 0;
  double noise_ = 0.0, fd_ = 1e-4;
  bool central_ = false;
};

// The fold between two nodes a, b an arclength H apart whose tangents' p-components ta, tb (along
// the branch) have opposite signs: p with that component linear in the arclength, at its zero.
double fold_between(double pa, double ta, double tb, double H) {
  const double s = H * ta / (ta - tb);
  return pa + ta * s + (tb - ta) * s * s / (2.0 * H);
}
}  // namespace

HuntingMap hunting_map(const ClosedLoop& L, const PeriodicOrbit& start, double lo, double hi, int n,
                       const OrbitOptions& opt) {
  if (!(lo > 0.0) || !(hi > lo) || n < 2)
    throw InputError("hunting map: need 0 < LO < HI and N >= 2 gain scales (got " + num(lo) + ":" +
                     num(hi) + ":" + std::to_string(n) + ")");
  check_loop(L);
  HuntingMap m;
  const double p_lo = std::log(lo), p_hi = std::log(hi);
  const double dp_max = (p_hi - p_lo) / (n - 1);  // the longest step in ln(gain scale)
  const int max_nodes = 4 * n + 24;
  constexpr double kRefine = 0.04;  // the step that brackets a fold or a change of stability
  BranchTracer tracer(L, start, opt);
  std::vector<std::string> ends;
  // One direction from the start: nodes until the range's end, a lost branch or max_nodes. The
  // stability of a node: its own (multipliers, iteration) on the start's side of an even number of
  // folds, unstable past an odd number (at a fold exactly one real multiplier crosses +1; next to
  // it the iteration cannot tell a multiplier of 1.005 from 1).
  const auto trace = [&](bool up) {
    std::vector<BranchTracer::Node> nodes;
    std::optional<BranchTracer::Node> nd;
    std::string error;
    try {
      nd = tracer.start_node(start, up);
    } catch (const Error& e) {  // a diverging loop, a step too coarse for the gain
      error = e.what();
    }
    if (!nd) {
      ends.push_back("the branch's tangent at the start could not be computed" +
                     (error.empty() ? std::string() : " (" + error + ")"));
      return nodes;
    }
    nodes.push_back(*nd);
    bool stable_side = start.stable;
    std::size_t pending = 0;  // index of the point just past an unconfirmed fold (0: none)
    double cap = 1.0;
    bool done = false;
    while (!done && static_cast<int>(nodes.size()) < max_nodes) {
      const BranchTracer::Node& cur = nodes.back();
      const auto k = cur.t.size() - 1;
      const double h = std::min(cap, dp_max / std::max(std::abs(cur.t(k)), 1e-3));
      bool at_bound = false;
      std::optional<BranchTracer::Node> next;
      try {
        next = tracer.step(cur, h, p_lo, p_hi, &at_bound);
      } catch (const Error& e) {  // a diverging loop, a step too coarse for the gain
        error = e.what();
      }
      if (!next) {
        cap = 0.5 * std::min(cap, h);
        if (cap < 0.01) {
          ends.push_back("continuation lost the branch at gain scale " + num(std::exp(cur.p)) +
                         (up ? " going up" : " going down") +
                         (error.empty() ? std::string() : " (" + error + ")"));
          break;
        }
        continue;
      }
      // A turn in the gain or a change of stability: bracketed by a step of at most kRefine (the
      // fold is interpolated between two close points).
      const bool turn = next->t(k) * cur.t(k) < 0.0;
      const bool raw_stable = next->orbit.stable;
      if ((turn || (stable_side && raw_stable != cur.orbit.stable)) && h > kRefine) {
        cap = 0.5 * h;
        continue;
      }
      if (turn) {
        // A fold: the largest finite-difference multiplier crosses 1 between the two points.
        // A turn without is the corrector doubling back over the branch: the trace stops there.
        const double mu0 = cur.orbit.multipliers.empty() ? 0.0 : std::abs(cur.orbit.multipliers[0]);
        const double mu1 =
            next->orbit.multipliers.empty() ? 0.0 : std::abs(next->orbit.multipliers[0]);
        if ((mu0 < 1.0) == (mu1 < 1.0)) {
          ends.push_back("the continuation turned back at gain scale " + num(std::exp(next->p)) +
                         " without a multiplier crossing +1 (not a fold; the trace stops there)");
          break;
        }
        stable_side = !stable_side;
        m.folds.push_back(std::exp(fold_between(cur.p, cur.t(k), next->t(k), next->h)));
        pending = nodes.size();  // confirmed by the next point's multipliers
      } else if (pending > 0 && nodes.size() == pending + 1) {
        // Past a fold the multiplier grows away from 1: one point later the orbit is unstable by
        // itself (multipliers and the displaced orbit's growth). Stable there, the turn was the
        // corrector retracing the branch (finite differences across an event): the points from
        // the turn on are dropped and the trace stops.
        if (raw_stable) {
          nodes.resize(pending);
          m.folds.pop_back();
          ends.push_back("the continuation turned back at gain scale " +
                         num(std::exp(nodes.back().p)) +
                         " and retraced the branch (not a fold; the trace stops there)");
          break;
        }
        pending = 0;
      }
      next->orbit.stable = stable_side && raw_stable;
      if (next->orbit.amplitude < 1e-9 * std::max(1.0, std::abs(start.level))) {
        ends.push_back("the orbit shrinks to the set point at gain scale " +
                       num(std::exp(next->p)));
        break;
      }
      cap = std::min(1.0, 1.5 * cap);
      done = at_bound;
      nodes.push_back(std::move(*next));
    }
    return nodes;
  };
  std::vector<BranchTracer::Node> down = trace(false), up = trace(true);
  // The branch in order: the far end of the downward trace first.
  std::vector<const BranchTracer::Node*> branch;
  for (auto it = down.rbegin(); it != down.rend(); ++it) branch.push_back(&*it);
  for (std::size_t i = 1; i < up.size(); ++i) branch.push_back(&up[i]);
  if (down.empty() && !up.empty()) branch.insert(branch.begin(), &up.front());
  for (const BranchTracer::Node* a : branch) m.points.push_back({a->orbit.gain_scale, a->orbit});
  std::sort(m.folds.begin(), m.folds.end());
  if (!m.folds.empty()) {
    // The fold nearest the start's gain.
    m.fold = *std::min_element(m.folds.begin(), m.folds.end(), [&](double a, double b) {
      return std::abs(std::log(a / start.gain_scale)) < std::abs(std::log(b / start.gain_scale));
    });
  }
  m.map_evaluations = tracer.evaluations();
  std::ostringstream note;
  note << "pseudo-arclength continuation in (section state, ln gain scale) from the orbit at "
       << num(start.gain_scale) << " over [" << num(lo) << ", " << num(hi) << "] (steps of at most "
       << num(dp_max) << " in ln gain scale; fresh finite-difference "
       << "Jacobian and multipliers at each point)";
  if (m.folds.empty()) note << "; no fold in the traced branch";
  for (double f : m.folds)
    note << "; fold at gain scale " << num(f) << " (a stable and an unstable cycle meet)";
  for (const std::string& e : ends) note << "; " << e;
  m.note = note.str();
  return m;
}

}  // namespace gmslab::control
