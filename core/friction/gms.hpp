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

 private:
  ModelParams params_;
  GmsParams p_;
  std::size_t n_;
  std::vector<double> sigma_over_k_;  // sigma_i / k_i [s]
  double inv_vs_ = 0.0;              // 1 / Vs [s/m]
  double r_sat_ = 0.0;               // |v|/Vs beyond which S(v) == Fc exactly in doubles [-]
};

ModelInfo gms_model_info();

}  // namespace gmslab
