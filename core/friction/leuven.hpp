// gmslab core: the Leuven model (Swevers, Al-Bender, Ganseman, Prajogo, IEEE TAC 45(4), 2000) in
// the modified form of Lampaert, Swevers, Al-Bender (IEEE TAC 47(4), 2002): the hysteresis force
// F_h(z) is a Maxwell-slip model driven by the state z.
//
//   dz/dt = v (1 - sgn(F_h(z)/s(v)) |F_h(z)/s(v)|^n),   s(v) = sgn(v) S(v)
//   F     = F_h(z) + sigma1 dz/dt + sigma2 v
//   F_h(z) = sum_i F_i,  Jenkin element i: dF_i/dz = k_i while |F_i| < W_i, F_i = +-W_i in slip
//   S(v)  = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta)
//
// z [m] state (only its increments matter), n [-] transition exponent, sigma1, sigma2 [N s/m],
// k_i [N/m], W_i [N] with sum W_i >= Fs (F_h must be able to reach S(v), else z runs away).
// Steady sliding: F_h = sgn(v) S(v), dz/dt = 0, F = sgn(v) S(v) + sigma2 v. The level s(v) must
// carry the sign of v (as in Swevers et al.): with the magnitude S(v) the v < 0 fixed point is
// unstable and z runs away.
//
// Memory: F_h has exact nonlocal memory in z, but z follows x only as far as
// dz/dx = 1 - sgn(F_h/s)|F_h/s|^n is close to 1. Presliding loops in x therefore close only
// approximately, and a sub-break-away oscillating force makes the body creep slowly (both vanish
// as n grows). The default n = 8 keeps presliding Maxwell-slip-like (with n = 2 the Fig. 2A inner
// loop misses closing by 0.14 N and the 2D protocol drifts 14 um in 6 s; with n = 8: 0.016 N and
// 0.2 um). sigma1 defaults to 0: in sliding dz/dt follows (dS/dt) / (stiffness of the sticking
// elements), so a large sigma1 inverts the frictional lag (with sigma1 = 183 N s/m, the GMS
// reference's total micro-damping, the Fig. 2B loop runs the wrong way round).
//
// Step with v frozen: z moves monotonically towards the fixed point F_h = sgn(v) S(v), so the
// element forces after a state increment dz are exactly F_i(dz) = clamp(F_i + k_i dz, -W_i, W_i)
// (one monotone move from the step start). dz over the step is integrated by classical RK4 on
// sub-steps chosen so that the linearised relaxation rate  (sum k_i) |v| n / S  times the sub-step
// is <= 1/4 (at most 4096 sub-steps). dz/dt in F is the step average. At v = 0 the state is held.
//
// State layout: [F_0 .. F_{N-1} | d_0 .. d_{N-1}], d_i = +-1 while element i is pushed against its
// slip limit (slipping), 0 while it sticks.
#pragma once

#include <vector>

#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

class LeuvenModel final : public FrictionModel {
 public:
  explicit LeuvenModel(const ModelParams& p);
  const ModelInfo& info() const override;
  const ModelParams& params() const override { return params_; }
  std::size_t state_size() const override { return 2 * k_.size(); }
  void reset(std::span<double> state) const override;
  double step(std::span<double> state, const FrictionInput& in) const override;
  double steady_state(double v) const override;
  double break_away() const override { return S_.Fs; }
  std::size_t element_count() const override { return k_.size(); }
  ElementState element(std::span<const double> state, std::size_t i) const override;

 private:
  double hysteresis(const double* F, double dz) const;       // F_h after a state increment dz
  double rate(const double* F, double dz, double v, double S) const;  // dz/dt

  ModelParams params_;
  Stribeck S_;
  double n_exp_, sigma1_, sigma2_, k_total_;
  int n_int_ = 0;  // n when it is a whole number (fast power), else 0
  std::vector<double> k_, W_;
};

ModelInfo leuven_model_info();

}  // namespace gmslab
