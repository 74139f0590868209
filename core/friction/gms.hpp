// gmslab core: the Generalized Maxwell-Slip (GMS) friction model, force-state form.
//
// Al-Bender, Lampaert, Swevers, "The generalized Maxwell-slip model: a novel model for friction
// simulation and compensation", IEEE TAC 50(11), 2005. N elements in parallel share the velocity v;
// element i has force F_i = k_i z_i, weight alpha_i (sum 1), stiffness k_i, micro-damping sigma_i.
//
//   S(v)  = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta)
//   stick : dF_i/dt = k_i v              until d F_i reaches alpha_i S(v), d = sgn v
//   slip  : dF_i/dt = C (alpha_i d - F_i / S(v))       d fixed at slip onset
//   F_f   = sum_i (F_i + sigma_i dz_i/dt) + sigma2 v,  dz_i/dt = (dF_i/dt) / k_i
//
// Switching has memory: stick -> slip when |F_i| reaches alpha_i S(v) while loaded in the direction
// of v; slip -> stick only when v reverses (or stops). Over a step with v frozen both laws are
// integrated exactly (stick: F += k v h; slip: F = T + (F - T) exp(-C h / S), T = alpha_i d S), and
// a stick -> slip crossing inside the step is located exactly (F then ends the step at T).
//
// State layout (SoA, for the vector units): [F_0 .. F_{N-1} | d_0 .. d_{N-1}], d_i in {-1, 0, +1}
// (0 = stick, +-1 = slipping in that direction).
#pragma once

#include <vector>

#include "core/friction/gms_elements.hpp"
#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

struct GmsParams {
  Stribeck S;                 // common Stribeck curve
  double C = 200.0;           // attraction parameter [N/s]
  double sigma2 = 0.4;        // viscous coefficient [N s/m]
  std::vector<double> alpha;  // element weights [-], sum 1
  std::vector<double> k;      // element stiffnesses [N/m]
  std::vector<double> sigma;  // element micro-damping [N s/m]

  static GmsParams from(const ModelParams& p);
  ModelParams to_params() const;
  // The reference set of docs/references.md (N = 4), with or without micro-damping.
  static GmsParams reference(bool micro_damping);
};

class GmsModel final : public FrictionModel {
 public:
  explicit GmsModel(const ModelParams& p);
  const ModelInfo& info() const override;
  const ModelParams& params() const override { return params_; }
  std::size_t state_size() const override { return 2 * n_; }
  void reset(std::span<double> state) const override;
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return p_.S.Fs; }
  std::size_t element_count() const override { return n_; }
  ElementState element(std::span<const double> state, std::size_t i) const override;

  // Up to this many elements a step uses a scalar loop with branches (latency-bound: a short
  // v -> force chain); beyond, a branch-free vectorised loop (throughput-bound).
  static constexpr std::size_t kScalarElements = 8;

  // What a step of length h computes once: 1 / h, C h and the slip relaxation exp(-C h / Fc) of
  // fast sliding (S(v) = Fc there; < 0: computed when needed).
  struct StepConstants {
    double h, inv_h, Ch, relax_sliding;
  };
  StepConstants constants(double h, bool with_relaxation = true) const {
    return {h, 1.0 / h, p_.C * h, with_relaxation ? exp_neg(p_.C * h / p_.S.Fc) : -1.0};
  }
  // step() with at most kScalarElements elements, inline for a caller's own loop (the engine's
  // one-body path): the same operations in the same order, so the same force and state bit for bit.
  // N > 0: the model has N elements (element_count(); a loop of known length, unrolled).
  template <std::size_t N = 0>
  [[gnu::always_inline]] double step_scalar(double* __restrict state, double v,
                                            const StepConstants& c) const {
    const std::size_t n = N > 0 ? N : n_;
    const double s = sgn(v);
    const double r = std::abs(v) * inv_vs_;
    double* F = state;
    double* d = state + n;
    gms_elements::Sums sums;
    if (r > r_sat_)  // a branch, not a select: S is then a constant, off the critical path
      sums = gms_elements::scalar(
          n, F, d, p_.alpha.data(), p_.k.data(), sigma_over_k_.data(), s, p_.S.Fc,
          [&] { return c.relax_sliding >= 0.0 ? c.relax_sliding : exp_neg(c.Ch / p_.S.Fc); },
          v * c.h);
    else
      sums = scalar_at(n, F, d, s, p_.S.at_scaled(r), c, v * c.h);
    return sums.force + sums.damping * c.inv_h + p_.sigma2 * v;
  }

 private:
  ModelParams params_;
  GmsParams p_;
  std::size_t n_;
  std::vector<double> sigma_over_k_;  // sigma_i / k_i [s]
  double inv_vs_ = 0.0;              // 1 / Vs [s/m]
  double r_sat_ = 0.0;               // |v|/Vs beyond which S(v) == Fc exactly in doubles [-]
  gms_elements::Sums scalar_at(std::size_t n, double* F, double* d, double s, double S,
                               const StepConstants& c, double vh) const {
    return gms_elements::scalar(
        n, F, d, p_.alpha.data(), p_.k.data(), sigma_over_k_.data(), s, S,
        [&] { return exp_neg(c.Ch / S); }, vh);
  }
};

ModelInfo gms_model_info();

}  // namespace gmslab
