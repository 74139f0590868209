// gmslab core: the LuGre model (Canudas de Wit, Olsson, Astrom, Lischinsky, IEEE TAC 40(3), 1995).
//
//   dz/dt = v - sigma0 |v| z / g(v),   g(v) = S(v) = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta)
//   F     = sigma0 z + sigma1 dz/dt + sigma2 v
//
// z [m] bristle deflection (the state), sigma0 [N/m] stiffness, sigma1 [N s/m] micro-damping,
// sigma2 [N s/m] viscous, Fs, Fc [N], Vs [m/s], delta [-]. Defaults: Table I of the paper
// (sigma0 = 1e5, sigma1 = sqrt(1e5), sigma2 = 0.4, Fc = 1, Fs = 1.5, Vs = 1e-3, delta = 2).
//
// Exact step with v frozen: z(h) = z_ss + (z - z_ss) exp(-sigma0 |v| h / g(v)),
// z_ss = sgn(v) g(v) / sigma0; dz/dt in F is the step average (z(h) - z) / h (so the damper's work
// over the step is exact). At v = 0 the state is held (no sgn(0)).
#pragma once

#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

class LuGreModel final : public SingleStateModel {
 public:
  explicit LuGreModel(const ModelParams& p);
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return S_.Fs; }

 private:
  Stribeck S_;
  double sigma0_, sigma1_, sigma2_;
};

ModelInfo lugre_model_info();

}  // namespace gmslab
