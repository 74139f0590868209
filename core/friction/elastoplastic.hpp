// gmslab core: the elasto-plastic model (Dupont, Hayward, Armstrong, Altpeter, IEEE TAC 47(5),
// 2002), a LuGre variant with a purely elastic presliding range (no drift below break-away).
//
//   dz/dt = v (1 - alpha(z, v) z / z_ss(v)),   z_ss(v) = sgn(v) S(v) / sigma0
//   F     = sigma0 z + sigma1 dz/dt + sigma2 v
//   alpha = 0                                               |z| <= z_ba or sgn(z) != sgn(v)
//         = 1/2 + 1/2 sin(pi (|z| - (z_max + z_ba)/2) / (z_max - z_ba))   z_ba < |z| < z_max
//         = 1                                               |z| >= z_max = S(v) / sigma0
//
// z [m] bristle deflection, z_ba [m] elastic limit (break-away displacement, 0 < z_ba < Fc/sigma0
// so the ramp exists at every velocity), other parameters as LuGre.
//
// Step with v frozen, in w = z sgn(v) (deflection along the motion), u = |v|, w_max = S(v)/sigma0:
//   w < z_ba       dw/dt = u            exact, up to the crossing of z_ba inside the step
//   ramp           dw/dt = u (1 - alpha(w) w / w_max)    classical RK4 on adaptive sub-steps
//                  (local Lipschitz constant x sub-step <= 1/5, travel <= (w_max - z_ba)/16),
//                  clipped to w_max (the fixed point); once alpha = 1 to 1e-10, exact exponential
//   w >= w_max     dw/dt = u (1 - w / w_max)             exact exponential (LuGre)
// dz/dt in F is the step average. At v = 0 the state is held.
#pragma once

#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

class ElastoPlasticModel final : public SingleStateModel {
 public:
  explicit ElastoPlasticModel(const ModelParams& p);
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return S_.Fs; }

  // Advance w = z sgn(v) over time h at speed u > 0 with ramp end w_max (exposed for tests).
  double advance_w(double w, double u, double w_max, double h) const;

 private:
  double ramp_rate(double w, double u, double w_max) const;  // dw/dt inside the ramp

  Stribeck S_;
  double sigma0_, sigma1_, sigma2_, z_ba_;
};

ModelInfo elastoplastic_model_info();

}  // namespace gmslab
