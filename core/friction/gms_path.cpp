#include "core/friction/gms_path.hpp"
#include "core/simd_path.hpp"

#include "core/friction/gms_elements.hpp"

#include <algorithm>
#include <cmath>

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
    const double r_sat = gms_elements::saturation_ratio(S);
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


void GmsPathRunner::run(const GmsPath& path, std::span<const double> alpha,
                        std::span<const double> k, std::span<const double> sigma_over_k,
                        double sigma2, std::span<const long> rows, double scale,
                        double* element_rows, std::span<double> total) const {
  const std::size_t n = alpha.size();
  std::vector<double> F(n, 0.0), d(n, 0.0);
  const bool vec = n > GmsModel::kScalarElements || simd_path().vector_elements;
  if (!total.empty()) total[0] = 0.0;
  std::size_t j = 0;
  for (std::size_t kk = 1; kk < path.samples; ++kk) {
    const std::size_t end = path.last[kk - 1];
    gms_elements::Sums sums{0.0, 0.0};
    double v = 0.0, h = 1.0;
    for (; j < end; ++j) {
      v = path.v[j];
      h = path.h[j];
      const double s = sgn(v);
      const double E = E_[j];
      sums = vec ? gms_elements::vector(n, F.data(), d.data(), alpha.data(), k.data(), sigma_over_k.data(), s,
                                        S_[j], E, v * h)
                 : gms_elements::scalar(n, F.data(), d.data(), alpha.data(), k.data(), sigma_over_k.data(), s,
                                        S_[j], [E] { return E; }, v * h);
    }
    if (!total.empty()) total[kk] = sums.force + sums.damping * (1.0 / h) + sigma2 * v;
    if (element_rows && kk < rows.size() && rows[kk] >= 0) {
      double* out = element_rows + static_cast<std::size_t>(rows[kk]) * n;
      for (std::size_t i = 0; i < n; ++i) out[i] = scale * F[i];
    }
  }
}

}  // namespace gmslab
