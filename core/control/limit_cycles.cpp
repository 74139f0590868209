#include "core/control/limit_cycles.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
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
                      " time(s) in " + num(opt.seed_duration) + " s (the loop settles)");
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

HuntingMap hunting_map(const ClosedLoop& L, const PeriodicOrbit& start, double lo, double hi, int n,
                       const OrbitOptions& opt) {
  if (!(lo > 0.0) || !(hi > lo) || n < 2)
    throw InputError("hunting map: need 0 < LO < HI and N >= 2 gain scales (got " + num(lo) + ":" +
                     num(hi) + ":" + std::to_string(n) + ")");
  HuntingMap m;
  for (int i = 0; i < n; ++i)
    m.points.push_back({lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1)), std::nullopt});
  // From the start (gain scale 1) outwards in both directions, each point from its neighbour.
  const auto it =
      std::lower_bound(m.points.begin(), m.points.end(), 1.0,
                       [](const HuntingMapPoint& p, double s) { return p.gain_scale < s; });
  const auto up0 = static_cast<std::ptrdiff_t>(it - m.points.begin());
  const auto walk = [&](std::ptrdiff_t i0, std::ptrdiff_t step) {
    PeriodicOrbit prev = start;
    for (std::ptrdiff_t i = i0; i >= 0 && i < static_cast<std::ptrdiff_t>(m.points.size());
         i += step) {
      const double target = m.points[static_cast<std::size_t>(i)].gain_scale;
      double s = prev.gain_scale;
      std::optional<PeriodicOrbit> o;
      // Halve the step on a failure (4 times); a branch that ends: the fold lies beyond s.
      double ds = target - s;
      for (int halving = 0; halving <= 4 && std::abs(target - s) > 0.0;) {
        o = continue_orbit(L, prev, s + ds, opt);
        if (o) m.map_evaluations += o->map_evaluations;
        if (o && o->stable == prev.stable) {
          prev = *o, s += ds;
          ds = target - s;
        } else {
          ds *= 0.5, ++halving;
        }
      }
      if (std::abs(target - s) > 1e-12 * target) {
        if (step < 0)
          m.fold = s;  // the last orbit of the branch, within ds of its end
        else
          m.lost_above = s;
        return;
      }
      m.points[static_cast<std::size_t>(i)].orbit = prev;
    }
  };
  walk(up0 - 1, -1);
  walk(up0, +1);
  std::ostringstream note;
  note << "natural-parameter continuation in the gain scale from the orbit at 1 (Newton "
          "warm-started from the "
          "neighbouring orbit, step halved up to 4 times); ";
  if (m.fold)
    note << "the branch ends near gain scale " << num(*m.fold)
         << " (fold: no orbit of this branch below)";
  else
    note << "no fold in [" << num(lo) << ", " << num(hi) << "]";
  if (m.lost_above) note << "; the branch was lost above gain scale " << num(*m.lost_above);
  note << "; unstable branches are not traced";
  m.note = note.str();
  return m;
}

}  // namespace gmslab::control
