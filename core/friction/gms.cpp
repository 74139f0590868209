#include "core/friction/gms.hpp"

#include <cmath>
#include <limits>
#include <numeric>

#include "core/friction/gms_elements.hpp"
#include "core/friction/param_specs.hpp"
#include "core/simd_path.hpp"

namespace gmslab {

GmsParams GmsParams::from(const ModelParams& p) {
  GmsParams g;
  g.S = {p.scalar("Fs"), p.scalar("Fc"), p.scalar("Vs"), p.scalar("delta")};
  g.C = p.scalar("C");
  g.sigma2 = p.scalar("sigma2");
  g.alpha = p.column("alpha");
  g.k = p.column("k");
  g.sigma = p.column("sigma");
  return g;
}

ModelParams GmsParams::to_params() const {
  ModelParams p;
  p.model = "gms";
  p.scalars = {S.Fs, S.Fc, S.Vs, S.delta, C, sigma2};
  for (std::size_t i = 0; i < alpha.size(); ++i) p.elements.push_back({alpha[i], k[i], sigma[i]});
  return p;
}

GmsParams GmsParams::reference(bool micro_damping) {
  GmsParams g;
  g.alpha = {0.1, 0.2, 0.3, 0.4};
  g.k = {75000.0, 60000.0, 45000.0, 30000.0};
  for (double ki : g.k) g.sigma.push_back(micro_damping ? 8.7e-4 * ki : 0.0);
  return g;
}

ModelInfo gms_model_info() {
  ModelInfo m;
  m.tag = "gms";
  m.name = "Generalized Maxwell-slip (GMS)";
  m.citation = "Al-Bender, Lampaert, Swevers, IEEE TAC 50(11), 2005";
  m.equation =
      "stick: dF_i/dt = k_i v until F_i reaches alpha_i S(v); slip: dF_i/dt = C (alpha_i sgn(v) - "
      "F_i/S(v)) until v reverses; F = sum(F_i + sigma_i dz_i/dt) + sigma2 v; "
      "S(v) = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta)";
  m.scalars = {
      {"Fs", "F_s", "N", "static (break-away) force level of the Stribeck curve", 0, 1e7, true},
      {"Fc", "F_c", "N", "Coulomb (sliding) force level, Fc <= Fs", 0, 1e7, true},
      {"Vs", "V_s", "m/s", "Stribeck velocity", 0, 1e3, true, true},
      {"delta", "delta", "-", "Stribeck shape exponent", 0.1, 10},
      {"C", "C", "N/s", "attraction: how fast a slipping element reaches its Stribeck level", 0,
       1e9, true, true},
      {"sigma2", "sigma_2", "N s/m", "viscous friction coefficient", 0, 1e7},
  };
  m.columns = {
      {"alpha", "alpha_i", "-", "element weight (share of the Stribeck level); weights sum to 1", 0,
       1, true},
      {"k", "k_i", "N/m", "element stiffness (presliding)", 0, 1e12, true, true},
      {"sigma", "sigma_i", "N s/m", "element micro-damping (viscoelastic)", 0, 1e9},
  };
  m.min_elements = 1;
  m.max_elements = 100000;
  m.defaults = [] { return GmsParams::reference(true).to_params(); };
  m.check = [](const ModelParams& p, std::vector<std::string>& out) {
    specs::check_fc_le_fs(p, out);
    const auto a = p.column("alpha");
    const double sum = std::accumulate(a.begin(), a.end(), 0.0);
    if (std::abs(sum - 1.0) > 1e-6)
      out.push_back("element weights alpha must sum to 1 (they sum to " + specs::num(sum) + ")");
  };
  m.build = [](const ModelParams& p) { return std::make_unique<GmsModel>(p); };
  return m;
}

GmsModel::GmsModel(const ModelParams& p)
    : params_(p), p_(GmsParams::from(p)), n_(p_.alpha.size()) {
  inv_vs_ = 1.0 / p_.S.Vs;
  r_sat_ = gms_elements::saturation_ratio(p_.S);
  sigma_over_k_.resize(n_);
  for (std::size_t i = 0; i < n_; ++i) sigma_over_k_[i] = p_.sigma[i] / p_.k[i];
}

const ModelInfo& GmsModel::info() const { return model_info("gms"); }

void GmsModel::reset(std::span<double> state) const {
  std::fill(state.begin(), state.end(), 0.0);
}

namespace {

// One element's branch-free update (selects only, so that the loops over the elements
// vectorise): its new force and slip direction.
struct ElementUpdate {
  double f, d;
};
[[gnu::always_inline]] inline ElementUpdate element_update(double f0, double d0, double alpha,
                                                           double k, double s, double S, double E,
                                                           double vh) {
  const double lim = alpha * S;
  const double target = s * lim;
  const double f_slip = target + (f0 - target) * E;
  const double f_stick = f0 + k * vh;
  const bool breaks = s * f_stick >= lim;  // false when v = 0 (lim > 0)
  const bool slips = (d0 * s > 0.0) | (s * f0 >= lim);
  const double f_clamped = breaks ? target : f_stick;
  return {slips ? f_slip : f_clamped, (slips | breaks) ? s : 0.0};
}

// The loop is compiled twice, for AVX2 and for the baseline, and the CPU (or a test,
// core/simd_path.hpp) chooses per call.
[[gnu::always_inline]] inline gms_elements::Sums vector_body(
    std::size_t n, double* __restrict F, double* __restrict d, const double* __restrict alpha,
    const double* __restrict k, const double* __restrict sk, double s, double S, double E,
    double vh) {
  double sum_f = 0.0;
  double sum_damp = 0.0;
#pragma omp simd reduction(+ : sum_f, sum_damp)
  for (std::size_t i = 0; i < n; ++i) {
    const double f0 = F[i];
    const auto [f1, d1] = element_update(f0, d[i], alpha[i], k[i], s, S, E, vh);
    d[i] = d1;
    sum_damp += sk[i] * (f1 - f0);
    F[i] = f1;
    sum_f += f1;
  }
  return {sum_f, sum_damp};
}

// vector_body's element updates without its sums, along a whole path.
[[gnu::always_inline]] inline void rows_body(std::size_t n, double* __restrict F,
                                             double* __restrict d, const double* __restrict alpha,
                                             const double* __restrict k,
                                             const gms_elements::PathSteps& p, const long* rows,
                                             std::size_t n_rows, double scale,
                                             double* element_rows) {
  std::size_t j = 0;
  for (std::size_t kk = 1; kk < p.samples; ++kk) {
    for (const std::size_t end = p.last[kk - 1]; j < end; ++j) {
      const double v = p.v[j];
      const double s = sgn(v), S = p.S[j], E = p.E[j], vh = v * p.h[j];
#pragma omp simd
      for (std::size_t i = 0; i < n; ++i) {
        const auto [f1, d1] = element_update(F[i], d[i], alpha[i], k[i], s, S, E, vh);
        F[i] = f1, d[i] = d1;
      }
    }
    if (kk < n_rows && rows[kk] >= 0) {
      double* out = element_rows + static_cast<std::size_t>(rows[kk]) * n;
      for (std::size_t i = 0; i < n; ++i) out[i] = scale * F[i];
    }
  }
}

__attribute__((target("avx2"))) void rows_avx2(std::size_t n, double* __restrict F,
                                               double* __restrict d, const double* __restrict alpha,
                                               const double* __restrict k,
                                               const gms_elements::PathSteps& p, const long* rows,
                                               std::size_t n_rows, double scale,
                                               double* element_rows) {
  rows_body(n, F, d, alpha, k, p, rows, n_rows, scale, element_rows);
}

void rows_baseline(std::size_t n, double* __restrict F, double* __restrict d,
                   const double* __restrict alpha, const double* __restrict k,
                   const gms_elements::PathSteps& p, const long* rows, std::size_t n_rows,
                   double scale, double* element_rows) {
  rows_body(n, F, d, alpha, k, p, rows, n_rows, scale, element_rows);
}

__attribute__((target("avx2"))) gms_elements::Sums vector_avx2(
    std::size_t n, double* __restrict F, double* __restrict d, const double* __restrict alpha,
    const double* __restrict k, const double* __restrict sk, double s, double S, double E,
    double vh) {
  return vector_body(n, F, d, alpha, k, sk, s, S, E, vh);
}

gms_elements::Sums vector_baseline(std::size_t n, double* __restrict F, double* __restrict d,
                                   const double* __restrict alpha, const double* __restrict k,
                                   const double* __restrict sk, double s, double S, double E, double vh) {
  return vector_body(n, F, d, alpha, k, sk, s, S, E, vh);
}

}  // namespace

gms_elements::Sums gms_elements::vector(std::size_t n, double* __restrict F, double* __restrict d,
                                        const double* __restrict alpha, const double* __restrict k,
                                        const double* __restrict sk, double s, double S, double E, double vh) {
  return use_avx2() ? vector_avx2(n, F, d, alpha, k, sk, s, S, E, vh)
                    : vector_baseline(n, F, d, alpha, k, sk, s, S, E, vh);
}

void gms_elements::vector_rows(std::size_t n, double* __restrict F, double* __restrict d,
                               const double* __restrict alpha, const double* __restrict k,
                               const PathSteps& p, const long* rows, std::size_t n_rows,
                               double scale, double* element_rows) {
  if (use_avx2()) return rows_avx2(n, F, d, alpha, k, p, rows, n_rows, scale, element_rows);
  rows_baseline(n, F, d, alpha, k, p, rows, n_rows, scale, element_rows);
}

double GmsModel::step(std::span<double> state, const FrictionInput& in) const {
  if (n_ <= kScalarElements) return step_scalar(state.data(), in.v, constants(in.h, false));
  const double v = in.v;
  const double h = in.h;
  const double inv_h = 1.0 / h;  // independent of v: off the step's critical path
  const double s = sgn(v);
  const double r = std::abs(v) * inv_vs_;
  const double S = r > r_sat_ ? p_.S.Fc : p_.S.at_scaled(r);
  double* F = state.data();
  double* d = state.data() + n_;
  const auto [sum_f, sum_damp] =
      gms_elements::vector(n_, F, d, p_.alpha.data(), p_.k.data(), sigma_over_k_.data(), s, S,
                           exp_neg(p_.C * h / S), v * h);
  return sum_f + sum_damp * inv_h + p_.sigma2 * v;
}

double GmsModel::steady_state(double v) const { return sgn(v) * p_.S(v) + p_.sigma2 * v; }

ElementState GmsModel::element(std::span<const double> state, std::size_t i) const {
  return {state[i], state[n_ + i] != 0.0};
}

}  // namespace gmslab
