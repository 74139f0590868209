// gmslab core: the Maxwell-slip model (Iwan 1966; Lampaert, Al-Bender, Swevers 2003): N Jenkin
// elements (a spring k_i [N/m] in series with a Coulomb slider of slip force W_i [N]) in parallel,
// all driven by the common displacement x.
//
//   stick : dF_i/dt = k_i v       while |F_i| < W_i
//   slip  : F_i = W_i sgn(v)      until v reverses (then the element sticks again)
//   F     = sum_i F_i + sigma2 v  [N]
//
// Rate-independent hysteresis with nonlocal memory (Masing rules, wiping-out); no Stribeck
// effect, no frictional lag. GMS with a constant Stribeck level S = W reduces to it
// (alpha_i = W_i / W). Step with v frozen is exact: F_i <- clamp(F_i + k_i v h, -W_i, W_i).
//
// State layout: [F_0 .. F_{N-1} | d_0 .. d_{N-1}], d_i in {-1, 0, +1} (0 = stick, +-1 = slipping
// in that direction), as GMS.
#pragma once

#include <vector>

#include "core/friction/model.hpp"

namespace gmslab {

class MaxwellSlipModel final : public FrictionModel {
 public:
  explicit MaxwellSlipModel(const ModelParams& p);
  const ModelInfo& info() const override;
  const ModelParams& params() const override { return params_; }
  std::size_t state_size() const override { return 2 * k_.size(); }
  void reset(std::span<double> state) const override;
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return W_total_; }
  std::size_t element_count() const override { return k_.size(); }
  ElementState element(std::span<const double> state, std::size_t i) const override;

 private:
  ModelParams params_;
  std::vector<double> k_, W_;
  double sigma2_, W_total_;
};

ModelInfo maxwell_slip_model_info();

}  // namespace gmslab
