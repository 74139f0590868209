#include "core/friction/leuven.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/error.hpp"
#include "core/friction/param_specs.hpp"

namespace gmslab {

ModelInfo leuven_model_info() {
  ModelInfo m;
  m.tag = "leuven";
  m.name = "Leuven (2002, Maxwell-slip hysteresis)";
  m.citation = "Swevers et al., IEEE TAC 45(4), 2000; Lampaert, Swevers, Al-Bender, IEEE TAC "
               "47(4), 2002";
  m.equation =
      "dz/dt = v (1 - sgn(F_h(z)/S(v)) |F_h(z)/S(v)|^n); F = F_h(z) + sigma1 dz/dt + sigma2 v; "
      "F_h(z) = sum of Maxwell-slip elements (k_i, W_i) driven by z";
  m.scalars = {specs::Fs(), specs::Fc(), specs::Vs(), specs::delta(),
               {"n", "n", "-", "shape exponent of the transition to sliding", 0.2, 20},
               specs::sigma1(), specs::sigma2()};
  m.columns = {
      {"k", "k_i", "N/m", "hysteresis element stiffness", 0, 1e12, true, true},
      {"W", "W_i", "N", "hysteresis element slip force; sum W_i >= Fs", 0, 1e7, true, true},
  };
  m.min_elements = 1;
  m.max_elements = 100000;
  m.defaults = [] {
    return ModelParams{"leuven",
                       {1.5, 1.0, 1e-3, 2.0, 8.0, 0.0, 0.4},
                       {{75000, 0.15}, {60000, 0.3}, {45000, 0.45}, {30000, 0.6}}};
  };
  m.check = [](const ModelParams& p, std::vector<std::string>& out) {
    specs::check_fc_le_fs(p, out);
    const auto W = p.column("W");
    const double sum = std::accumulate(W.begin(), W.end(), 0.0);
    if (sum < p.scalar("Fs") * (1.0 - 1e-9))
      out.push_back("the element slip forces W must sum to at least Fs (sum W = " +
                    specs::num(sum) + " N, Fs = " + specs::num(p.scalar("Fs")) +
                    " N): F_h must be able to reach S(v)");
  };
  m.build = [](const ModelParams& p) { return std::make_unique<LeuvenModel>(p); };
  return m;
}

LeuvenModel::LeuvenModel(const ModelParams& p)
    : params_(p),
      S_(specs::stribeck_from(p)),
      n_exp_(p.scalar("n")),
      sigma1_(p.scalar("sigma1")),
      sigma2_(p.scalar("sigma2")),
      k_(p.column("k")),
      W_(p.column("W")) {
  n_int_ = (n_exp_ == std::floor(n_exp_) && n_exp_ >= 1.0) ? static_cast<int>(n_exp_) : 0;
  n_eff_ = std::max(n_exp_, 1.0);
  k_total_ = std::accumulate(k_.begin(), k_.end(), 0.0);
}

const ModelInfo& LeuvenModel::info() const { return model_info("leuven"); }

void LeuvenModel::reset(std::span<double> state) const {
  std::fill(state.begin(), state.end(), 0.0);
}

double LeuvenModel::steady_state(double v) const { return sgn(v) * S_(v) + sigma2_ * v; }

double LeuvenModel::hysteresis(const double* F, double dz) const {
  double sum = 0.0;
  for (std::size_t i = 0; i < k_.size(); ++i) sum += std::clamp(F[i] + k_[i] * dz, -W_[i], W_[i]);
  return sum;
}

LeuvenModel::HysteresisAt LeuvenModel::hysteresis_at(const double* F, double dz) const {
  HysteresisAt a{0.0, 0.0};
  for (std::size_t i = 0; i < k_.size(); ++i) {
    const double f = std::clamp(F[i] + k_[i] * dz, -W_[i], W_[i]);
    a.fh += f;
    a.magnitude += std::abs(f);
  }
  return a;
}

double LeuvenModel::free_stiffness(const double* F, double dz, double dir) const {
  double k = 0.0;
  for (std::size_t i = 0; i < k_.size(); ++i)
    k += dir * std::clamp(F[i] + k_[i] * dz, -W_[i], W_[i]) < W_[i] ? k_[i] : 0.0;
  return k;
}

bool LeuvenModel::fixed_point(const double* F, double dz, double dir, double s, double& out) const {
  // F_h is piecewise linear and non-decreasing in dz: walk its segments in the direction dir.
  double z = dz;
  for (std::size_t seg = 0; seg <= k_.size(); ++seg) {
    double fh = 0.0, K = 0.0, next = std::numeric_limits<double>::infinity();  // next: distance
    for (std::size_t i = 0; i < k_.size(); ++i) {
      const double f = F[i] + k_[i] * z;
      fh += std::clamp(f, -W_[i], W_[i]);
      if (dir * f < W_[i]) {  // still loading in this direction
        K += k_[i];
        next = std::min(next, (W_[i] - dir * f) / k_[i]);
      }
    }
    if (K <= 0.0) return false;
    const double to_go = dir * (s - fh) / K;  // distance to s on this segment
    if (to_go <= next) {
      out = z + dir * std::max(0.0, to_go);
      return true;
    }
    z += dir * next;
  }
  return false;
}

double LeuvenModel::power(double a) const {  // a^n for a >= 0
  if (n_int_ == 0) return std::pow(a, n_exp_);
  double p = 1.0, b = a;  // integer exponent by squaring (pow costs as much as a whole step)
  for (int e = n_int_; e > 0; e >>= 1, b *= b)
    if (e & 1) p *= b;
  return p;
}

double LeuvenModel::rate(const double* F, double dz, double v, double S) const {
  const double r = hysteresis(F, dz) / S;  // S carries the sign of v
  return v * (1.0 - std::copysign(power(std::abs(r)), r));
}

double LeuvenModel::state_increment(const double* F, double v, double s, double h) const {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  constexpr int max_substeps = 1000000;
  const double av = std::abs(v), as = std::abs(s);
  double dz = 0.0, left = h, dir = 0.0;  // dir: sign of dz/dt at the step start
  for (int it = 0; left > 0.0; ++it) {
    if (it == max_substeps)
      throw SimulationError("Leuven step: the state equation did not settle within " +
                            std::to_string(max_substeps) + " sub-steps (v = " + specs::num(v) +
                            " m/s, h = " + specs::num(h) + " s)");
    const HysteresisAt a = hysteresis_at(F, dz);
    if (std::abs(a.fh - s) <= 4.0 * eps * (a.magnitude + as)) break;  // on the fixed point
    const double u = a.fh / s, p = power(std::abs(u));
    const double k1 = v * (1.0 - std::copysign(p, u));
    if (it == 0) dir = sgn(k1);
    if (k1 * dir <= 0.0) break;  // on the fixed point to rounding (RK4 cannot step past it)
    // Sub-step: 1/4 of the inverse relaxation rate K |v| phi'(u) / S (phi = sgn(u)|u|^n), taken
    // as its largest value on the rest of the path when n >= 1, and short enough that no RK4 stage
    // reaches the fixed point dz* (|dz* - dz| >= |F_h - s| / K, |dz/dt| <= |k1| on the way).
    const double slope = std::abs(u) > 1.0 ? n_exp_ * p / std::abs(u) : n_eff_;
    const auto substep = [&](double K) {  // K = 0 (nothing can load further): the whole rest
      return std::min({left, 0.25 * as / (K * av * slope),
                       0.5 * std::abs(a.fh - s) / (K * std::abs(k1))});
    };
    double hs = substep(k_total_);  // all elements free: the bound is then only shorter
    if (hs < left) {  // more than one sub-step to go
      // Relaxation long enough to settle: |F_h - s| decays at least at the rate
      // lambda = K* |v| min phi' / S on the way to the fixed point (K* the free stiffness there,
      // min phi' over [u, 1]); when lambda * left exceeds what is needed to bring |F_h - s|
      // below the settling tolerance, the exact solution ends on the fixed point: go there.
      const double e0 = std::abs(a.fh - s), tol = 4.0 * eps * (a.magnitude + as);
      // An upper bound of ln(e0 / tol) + 1 from the binary exponents (no log on the hot path).
      const double need = 0.6931471805599453 * (std::ilogb(e0) - std::ilogb(tol) + 2) + 1.0;
      if (k_total_ * av * n_exp_ * std::max(1.0, std::abs(u)) * left > need * as) {
        const double au = std::abs(u);
        const double phi_min =
            (u <= 0.0 && n_exp_ > 1.0) ? 0.0 : n_exp_ * std::min(1.0, std::pow(au, n_exp_ - 1.0));
        double zs = 0.0;
        if (phi_min > 0.0 && fixed_point(F, dz, dir, s, zs)) {
          const double K_star = free_stiffness(F, zs, dir);
          if (K_star * av * phi_min * left > need * as) {
            dz = zs;
            break;
          }
        }
      }
      hs = substep(free_stiffness(F, dz, dir));
    }
    const double k2 = rate(F, dz + 0.5 * hs * k1, v, s);
    const double k3 = rate(F, dz + 0.5 * hs * k2, v, s);
    const double k4 = rate(F, dz + hs * k3, v, s);
    const double next = dz + hs * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
    if (next == dz) break;  // the increment is below rounding: z is on its fixed point
    dz = next;
    left = hs == left ? 0.0 : left - hs;
  }
  return dz;
}

double LeuvenModel::step(std::span<double> state, const FrictionInput& in) const {
  const std::size_t nel = k_.size();
  double* F = state.data();
  double* d = state.data() + nel;
  const double v = in.v;
  if (v == 0.0) {
    std::fill(d, d + nel, 0.0);
    return hysteresis(F, 0.0);
  }
  const double s = sgn(v) * S_(v);  // signed level: the fixed point F_h = sgn(v) S(v) is stable
  const double dz = state_increment(F, v, s, in.h);
  double fh = 0.0;
  const double sz = sgn(dz);
  for (std::size_t i = 0; i < nel; ++i) {
    const double f = F[i] + k_[i] * dz;
    const bool slips = sz != 0.0 && sz * f >= W_[i];
    F[i] = std::clamp(f, -W_[i], W_[i]);
    d[i] = slips ? sz : 0.0;
    fh += F[i];
  }
  return fh + sigma1_ * dz / in.h + sigma2_ * v;
}

ElementState LeuvenModel::element(std::span<const double> state, std::size_t i) const {
  return {state[i], state[k_.size() + i] != 0.0};
}

}  // namespace gmslab
