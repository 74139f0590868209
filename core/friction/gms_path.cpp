#include "core/friction/gms_path.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace gmslab {

namespace {

// exp(y[i]) (or exp(-y[i]) with negate): Cody-Waite reduction y = n ln2 + r, |r| <= ln2 / 2, a
// degree-13 Taylor polynomial of exp(r) (truncation below 5e-18 relative), 2^n put into the
// exponent bits; |y| beyond the double range: 0 or +inf. Branch-free, so the loop vectorises.
__attribute__((target_clones("avx2", "default"))) void exp_kernel(const double* __restrict y,
                                                                   double* __restrict out,
                                                                   std::size_t n, double sign) {
  constexpr double log2e = 1.4426950408889634074;
  constexpr double ln2_hi = 6.93147180369123816490e-01;  // fdlibm: n ln2_hi exact for |n| < 2^20
  constexpr double ln2_lo = 1.90821492927058770002e-10;
  constexpr double shifter = 0x1.8p52;  // adding it rounds to an integer in the low mantissa bits
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    const double yi = sign * y[i];
    const double yc = std::clamp(yi, -708.0, 709.0);
    const double t = yc * log2e + shifter;
    const double nd = t - shifter;
    const double r = (yc - nd * ln2_hi) - nd * ln2_lo;
    double p = 1.0 / 6227020800.0;  // 1/13!
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    const std::uint64_t bits = (std::bit_cast<std::uint64_t>(t) + 1023u) << 52;
    double e = p * std::bit_cast<double>(bits);
    e = yi < -708.0 ? 0.0 : e;
    e = yi > 709.0 ? std::numeric_limits<double>::infinity() : e;
    out[i] = yi != yi ? yi : e;  // NaN stays NaN
  }
}

}  // namespace

void exp_neg_n(std::span<const double> x, std::span<double> out) {
  exp_kernel(x.data(), out.data(), std::min(x.size(), out.size()), -1.0);
}

void GmsPath::add_step(double vj, double hj) {
  v.push_back(vj);
  h.push_back(hj);
  log_abs_v.push_back(std::log(std::abs(vj)));
}

void GmsPath::end_sample() {
  if (samples == 0) samples = 1;  // sample 0: the initial state
  last.push_back(static_cast<std::uint32_t>(v.size()));
  ++samples;
}

void GmsPathRunner::prepare(const Stribeck& S, double C, const GmsPath& path) {
  const std::size_t m = path.v.size();
  S_.resize(m);
  E_.resize(m);
  tmp_.resize(m);
  // (|v| / Vs)^delta: squares and plain ratios without exp/log (the common delta = 2 and 1).
  const double inv_vs = 1.0 / S.Vs;
  if (S.delta == 2.0) {
    for (std::size_t j = 0; j < m; ++j) {
      const double r = std::abs(path.v[j]) * inv_vs;
      tmp_[j] = r * r;
    }
  } else if (S.delta == 1.0) {
    for (std::size_t j = 0; j < m; ++j) tmp_[j] = std::abs(path.v[j]) * inv_vs;
  } else {
    const double lvs = std::log(S.Vs);
    for (std::size_t j = 0; j < m; ++j) S_[j] = S.delta * (path.log_abs_v[j] - lvs);
    exp_kernel(S_.data(), tmp_.data(), m, 1.0);  // exp(-inf) = 0 at v = 0
  }
  exp_kernel(tmp_.data(), S_.data(), m, -1.0);
  const double gap = S.Fs - S.Fc;
  for (std::size_t j = 0; j < m; ++j) {
    S_[j] = S.Fc + gap * S_[j];
    tmp_[j] = C * path.h[j] / S_[j];
  }
  exp_kernel(tmp_.data(), E_.data(), m, -1.0);
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
