#include "core/friction/gms_path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gmslab {

void GmsPath::add_step(double vj, double hj) {
  v.push_back(vj);
  h.push_back(hj);
}

void GmsPath::end_sample() {
  if (samples == 0) samples = 1;  // sample 0: the initial state
  last.push_back(static_cast<std::uint32_t>(v.size()));
  ++samples;
}

void GmsPathRunner::prepare(const Stribeck& S, double C, const GmsPath& path) {
  const std::size_t m = path.v.size();
  // The same shape along the same path (a search moving only the elements): nothing to redo.
  const bool same_path = &path == path_ && m == steps_;
  const bool same_S = same_path && S.Fs == shape_.Fs && S.Fc == shape_.Fc && S.Vs == shape_.Vs &&
                      S.delta == shape_.delta;
  if (same_S && C == C_) return;
  path_ = &path, steps_ = m, shape_ = S, C_ = C;
  S_.resize(m);
  E_.resize(m);
  if (!same_S) {
    // As GmsModel::step: beyond r_sat S is Fc exactly in doubles (no pow, no exp there).
    const double inv_vs = 1.0 / S.Vs;
    const double gap = S.Fs - S.Fc;
    double r_sat = gap > 0.0 ? std::pow(std::log(gap / S.Fc) + 54.0 * std::log(2.0), 1.0 / S.delta) : 0.0;
    if (!(r_sat > 0.0)) r_sat = gap > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const double r = std::abs(path.v[j]) * inv_vs;
      S_[j] = r > r_sat ? S.Fc : S.at_scaled(r);
    }
  }
  // Relaxation exp(-C h / S): consecutive steps of the same h and S (sliding beyond the Stribeck
  // region at a fixed sample step) share it.
  double last_x = -1.0, last_e = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    const double x = C * path.h[j] / S_[j];
    if (x != last_x) last_x = x, last_e = exp_neg(x);
    E_[j] = last_e;
  }
}

namespace {

struct Sums {
  double force, damping;
};

// The element updates of GmsModel::step (gms.cpp) with S and E given.
inline Sums elements_scalar(std::size_t n, double* __restrict F, double* __restrict d,
                            const double* __restrict alpha, const double* __restrict k,
                            const double* __restrict sk, double s, double S, double E, double vh) {
  double sum_f = 0.0, sum_damp = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f0 = F[i];
    const double lim = alpha[i] * S;
    double f1;
    if (d[i] * s > 0.0 || s * f0 >= lim) {
      const double target = s * lim;
      f1 = target + (f0 - target) * E;
      d[i] = s;
    } else {
      const double f_stick = f0 + k[i] * vh;
      if (s * f_stick >= lim) {
        f1 = s * lim;
        d[i] = s;
      } else {
        f1 = f_stick;
        d[i] = 0.0;
      }
    }
    sum_damp += sk[i] * (f1 - f0);
    F[i] = f1;
    sum_f += f1;
  }
  return {sum_f, sum_damp};
}

__attribute__((target_clones("avx2", "default"))) Sums elements_vector(
    std::size_t n, double* __restrict F, double* __restrict d, const double* __restrict alpha,
    const double* __restrict k, const double* __restrict sk, double s, double S, double E,
    double vh) {
  double sum_f = 0.0, sum_damp = 0.0;
#pragma omp simd reduction(+ : sum_f, sum_damp)
  for (std::size_t i = 0; i < n; ++i) {
    const double f0 = F[i];
    const double lim = alpha[i] * S;
    const double target = s * lim;
    const double f_slip = target + (f0 - target) * E;
    const double f_stick = f0 + k[i] * vh;
    const bool breaks = s * f_stick >= lim;
    const bool slips = (d[i] * s > 0.0) | (s * f0 >= lim);
    const double f_clamped = breaks ? target : f_stick;
    const double f1 = slips ? f_slip : f_clamped;
    d[i] = (slips | breaks) ? s : 0.0;
    sum_damp += sk[i] * (f1 - f0);
    F[i] = f1;
    sum_f += f1;
  }
  return {sum_f, sum_damp};
}

}  // namespace

void GmsPathRunner::run(const GmsPath& path, std::span<const double> alpha,
                        std::span<const double> k, std::span<const double> sigma_over_k,
                        double sigma2, std::span<const long> rows, double scale,
                        double* element_rows, std::span<double> total) const {
  const std::size_t n = alpha.size();
  std::vector<double> F(n, 0.0), d(n, 0.0);
  const bool vec = n > GmsModel::kScalarElements;
  if (!total.empty()) total[0] = 0.0;
  std::size_t j = 0;
  for (std::size_t kk = 1; kk < path.samples; ++kk) {
    const std::size_t end = path.last[kk - 1];
    Sums sums{0.0, 0.0};
    double v = 0.0, h = 1.0;
    for (; j < end; ++j) {
      v = path.v[j];
      h = path.h[j];
      const double s = sgn(v);
      sums = vec ? elements_vector(n, F.data(), d.data(), alpha.data(), k.data(),
                                   sigma_over_k.data(), s, S_[j], E_[j], v * h)
                 : elements_scalar(n, F.data(), d.data(), alpha.data(), k.data(),
                                   sigma_over_k.data(), s, S_[j], E_[j], v * h);
    }
    if (!total.empty()) total[kk] = sums.force + sums.damping * (1.0 / h) + sigma2 * v;
    if (element_rows && kk < rows.size() && rows[kk] >= 0) {
      double* out = element_rows + static_cast<std::size_t>(rows[kk]) * n;
      for (std::size_t i = 0; i < n; ++i) out[i] = scale * F[i];
    }
  }
}

}  // namespace gmslab
