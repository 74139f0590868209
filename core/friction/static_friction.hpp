// gmslab core: static (memoryless) friction laws with a Karnopp-type stick band.
//
// Two registry entries share this class:
//   "coulomb"   F = Fc sgn(v) + sigma2 v                      (v != 0), |F| <= Fs at rest
//   "stribeck"  F = sgn(v) S(v) + sigma2 v,  S(v) = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta)
// All forces in N, velocities in m/s, sigma2 in N s/m.
//
// Sticking (Karnopp 1985, with a zero-crossing test). A body of mass m > 0 sticks when
//   |v| < v_stick, or the sliding force would reverse v within this step
//   (v + h (f_other - F_slide) / m has the opposite sign of v).
// While it sticks, the friction is the force that brings it to rest in this step,
//   F = f_other + m v / h,   clipped to +-max(Fs, |F_slide|)   (the stick band),
// so a mass comes exactly to rest (v = 0 after the step) and stays there while |f_other| <= Fs;
// the clip is the break-away. f_other is the sum of all non-friction forces on the body [N].
//
// Prescribed motion (mass 0: there is no body to stop): inside |v| < v_stick the set-valued law
// is replaced by the straight line through the origin to the sliding curve at v_stick,
//   F = (v / v_stick) (S(v_stick) + sigma2 v_stick),
// a regularised curve (zero force at rest, odd, dissipative). Outside the band it is the sliding
// curve. The models have no state (state_size 0): no presliding hysteresis, no lag.
#pragma once

#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

class StaticFrictionModel final : public FrictionModel {
 public:
  // coulomb: true for the Coulomb law (sliding force Fc at any v != 0), false for Stribeck.
  StaticFrictionModel(const ModelParams& p, bool coulomb);
  const ModelInfo& info() const override;
  const ModelParams& params() const override { return params_; }
  std::size_t state_size() const override { return 0; }
  void reset(std::span<double> state) const override {}
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return S_.Fs; }

 private:
  double sliding_magnitude(double v) const;  // S(v), or Fc for Coulomb [N]

  ModelParams params_;
  bool coulomb_;
  Stribeck S_;
  double sigma2_;
  double v_stick_;
};

ModelInfo coulomb_model_info();
ModelInfo stribeck_model_info();

}  // namespace gmslab
