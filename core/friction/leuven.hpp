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
// as n grows; both are the model's, the same at a tenth of the time step). The default n = 8 keeps
// presliding Maxwell-slip-like: the Fig. 2A inner loop misses closing by 0.139 / 0.016 / 0.001 N
// and the 2D protocol creeps 14 / 0.23 / 0.002 um in 6 s for n = 2 / 8 / 16, but a larger n also
// narrows the frictional-lag loop (Fig. 2B x100 at 1 mm/s: 0.112 / 0.051 / 0.026 N). sigma1
// defaults to 0: in sliding dz/dt follows (dS/dt) / (stiffness of the sticking elements), so a
// large sigma1 inverts the frictional lag (with sigma1 = 183 N s/m, the GMS reference's total
// micro-damping, the Fig. 2B loop runs the wrong way round).
//
// Step with v frozen: z moves monotonically towards the fixed point F_h = sgn(v) S(v) and never
// crosses it, so the element forces after a state increment dz are exactly
// F_i(dz) = clamp(F_i + k_i dz, -W_i, W_i) (one monotone move from the step start). dz over the
// step is integrated by classical RK4 on adaptive sub-steps. Each is at most 1/4 of the inverse
// relaxation rate of the state equation, K |v| phi'(u) / S(v) with u = F_h / s, phi = sgn(u)|u|^n
// and K the stiffness of the elements not yet at their limit in the direction of motion, taken as
// its largest value on the rest of the path (n >= 1: n max(1, |u|^(n-1)); K only falls), and short
// enough that no RK4 stage reaches the fixed point (|dz* - dz| >= |F_h - s| / K). The update then
// stays between dz and dz*: the path of z is monotone and the one-move element update exact.
// After a velocity jump |u| can be well above 1 (F_h near Fs after slow sliding, S near Fc at
// speed) and the state equation is then n |u|^(n-1) times stiffer than at the fixed point; a step
// size from u = 1 alone (the former scheme, at most 4096 equal sub-steps) made RK4 unstable there:
// dz of the wrong sign, every element stuck at its limit against the motion, energy given out over
// closed cycles. The sub-steps stop once F_h is on the fixed point to rounding, so a step in steady
// sliding costs one pass. When more than one sub-step is left and |F_h - s|, which decays at least
// at the rate K* |v| min phi' / S (K* the free stiffness at the fixed point, min phi' over [u, 1]),
// certainly falls below that rounding tolerance within the rest of the step, the step goes
// straight to the fixed point (solved exactly on the piecewise-linear F_h) instead of taking the
// ~4 ln(1/eps) sub-steps of settling. dz/dt in F is the step average. At v = 0 the state is held.
// Throws SimulationError if a step needs more than 1e6 sub-steps.
//
// Passivity (sigma1 = 0): F_h (v - dz/dt) = |F_h| |v| |u|^n >= 0 and the Maxwell-slip elements
// dissipate in z, so a closed displacement cycle takes energy; the step keeps this because the
// path of z is monotone and F_h is taken at the end of the step. sigma1 dz/dt v = sigma1 v^2 (1 -
// sgn(u)|u|^n) is negative while |u| > 1, so with sigma1 > 0 the model itself can give out energy
// after a velocity jump (sufficient for passivity: sigma1 |v| <= Fc).
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
  struct HysteresisAt {
    double fh;         // F_h [N]
    double magnitude;  // sum |F_i| [N] (the rounding scale of F_h)
  };
  double hysteresis(const double* F, double dz) const;  // F_h after a state increment dz [N]
  HysteresisAt hysteresis_at(const double* F, double dz) const;
  // sum of k_i of the elements not at their limit in direction dir after the increment dz [N/m]
  double free_stiffness(const double* F, double dz, double dir) const;
  // The fixed point dz* >= dz (dir > 0) or <= dz (dir < 0) where the hysteresis force reaches s;
  // false when the elements saturate before it does.
  bool fixed_point(const double* F, double dz, double dir, double s, double& out) const;
  double power(double a) const;                                       // a^n, a >= 0
  double rate(const double* F, double dz, double v, double S) const;  // dz/dt [m/s]
  double state_increment(const double* F, double v, double s, double h) const;  // dz [m]

  ModelParams params_;
  Stribeck S_;
  double n_exp_, n_eff_ = 1.0, sigma1_, sigma2_, k_total_ = 0.0;
  int n_int_ = 0;  // n when it is a whole number (fast power), else 0
  std::vector<double> k_, W_;
};

ModelInfo leuven_model_info();

}  // namespace gmslab
