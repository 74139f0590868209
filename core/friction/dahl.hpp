// gmslab core: the Dahl model (Dahl 1968/1976), with an optional viscous term.
//
//   dF_d/dt = sigma0 v (1 - (F_d/Fc) sgn v)^a        F = F_d + sigma2 v
//
// F_d [N] is the state, sigma0 [N/m] the rest stiffness, Fc [N] the Coulomb level, a [-] the shape
// exponent (a = 1: F_d = sigma0 z with dz/dt = v - sigma0 |v| z / Fc), sigma2 [N s/m] viscous
// (0 gives Dahl's original). Local memory only; no Stribeck effect, no stiction, no lag.
//
// Exact step with v frozen: with u = 1 - F_d sgn(v) / Fc and c = sigma0 |v| / Fc,
//   du/dt = -c |u|^a sgn(u):   a = 1: u(h) = u e^{-c h};
//   a != 1: |u(h)|^(1-a) = |u|^(1-a) + (a - 1) c h  (a < 1: u reaches 0 in finite time, then stays).
// No sgn(0) is evaluated: at v = 0 the state is held.
#pragma once

#include "core/friction/model.hpp"

namespace gmslab {

class DahlModel final : public SingleStateModel {
 public:
  explicit DahlModel(const ModelParams& p);
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return Fc_; }

 private:
  double sigma0_, Fc_, a_, sigma2_;
};

ModelInfo dahl_model_info();

}  // namespace gmslab
