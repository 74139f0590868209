// gmslab core/control: limit cycles of the friction loop predicted by the describing function.
//
// Describing function of a (stateful) nonlinearity F(v), computed numerically from its own step:
//   drive v(t) = a sin(w t) for `periods` periods of `steps` steps each (step h = 2 pi / (w steps),
//   v held at its mid-step value), and take the first harmonic of F over the last period:
//   N(a, w) = (B + j A) / a,  B = (2/T) int F sin(w t) dt,  A = (2/T) int F cos(w t) dt.
//   (Coulomb Fc sgn(v): N = 4 Fc / (pi a); rate-state and presliding models depend on w too.)
// The friction loop with the compensator Gc = Kc (s + z) / (s + p) around the friction-free plant
// G = 1 / (m s^2 + c s + k) (constant reference):
//   v = -H(s) F,  H(s) = s G / (1 + Gc G) = s (s + p) / ((m s^2 + c s + k)(s + p) + Kc (s + z))
//   harmonic balance: 1 + H(jw) N(a, w) = 0, i.e. H(jw) = -1/N(a, w).
// Prediction: start at each w0 > 0 where H(jw0) is real negative (polynomial roots, as the phase
// crossovers of core/control/frequency.hpp), the velocity amplitude a0 where Re N(a0, w0) = 1/|H(jw0)|
// (bisection in log a over [a_min, a_max]), then Newton on (ln a, w) with the complex N.
// Stability (Loeb, by the quasi-linear system): with N frozen at a (1 +- 5 %), the closed-loop root
// of den_H + N num_H nearest j w moves into the left half plane for the larger amplitude and into
// the right for the smaller one: the cycle is stable (it attracts).
// Amplitudes: a is the velocity amplitude [m/s]; the position amplitude is a / w [m]; the period
// 2 pi / w [s].
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/control/linear_response.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/friction/model.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab::control {

// A nonlinearity stepped over time: force [N] for velocity v [m/s] held over a step h [s].
// reset() puts it back to its initial state.
struct SteppedNonlinearity {
  std::function<void()> reset;
  std::function<double(double v, double h)> step;
};
SteppedNonlinearity stepped(const FrictionModel& model);  // prescribed motion (mass 0)

// Model-based friction compensation driven by the measured velocity: the loop then sees the
// compensated nonlinearity F(v) - F_hat(v) (both stepped with the same v), whose describing
// function is N_F - N_Fhat (e.g. Coulomb Fc with a Coulomb compensator Fc_hat:
// 4 (Fc - Fc_hat) / (pi a); perfect compensation leaves only what the compensator does not model).
SteppedNonlinearity compensated(SteppedNonlinearity f, SteppedNonlinearity f_hat);
// Fc_hat sgn(v) [N], stateless (0 at v = 0).
SteppedNonlinearity coulomb_law(double Fc_hat);
// The nonlinearity of a friction loop with its compensator driven by the measured velocity:
// none: the friction; coulomb: F - Fc_hat sgn(v), Fc_hat = mismatch.force x the plant's Fc (its
// break-away force when the model has no Fc); gms: F - F_hat(v), F_hat the compensator's GMS model
// (feedforward_model(friction, mismatch)). Owns its models. Throws InputError for a bad model.
// (The loop simulation gives exactly this loop with LoopConfig::feedforward_source = Measured; with
// the default, Reference, the feedforward is 0 around a constant set point and the loop's
// nonlinearity is the friction alone.)
SteppedNonlinearity compensated_friction(const ModelParams& friction, Compensation comp, const Mismatch& m);

struct DfOptions {
  int steps = 2000;  // per period
  int periods = 3;   // the first harmonic is taken over the last one
};
// Throws InputError for a <= 0, w <= 0.
cplx describing_function(const SteppedNonlinearity& f, double a, double w, const DfOptions& opt = {});

struct LimitCycle {
  double velocity_amplitude = 0.0;  // a [m/s]
  double amplitude = 0.0;           // position amplitude a / w [m]
  double frequency = 0.0;           // w [rad/s]
  double period = 0.0;              // 2 pi / w [s]
  cplx point;                       // -1/N(a, w) = H(jw) [m/(N s)]
  bool stable = false;
  bool converged = false;  // Newton on the complex balance converged (else the real estimate)
};

struct LimitCycleReport {
  TransferFunction H;                 // s G / (1 + Gc G) [m/(N s)]
  std::vector<cplx> h_curve;          // H(jw) on a log grid of w
  std::vector<double> h_w;            // that grid [rad/s]
  std::vector<cplx> locus;            // -1/N(a, w0) over a log grid of a (w0: first cycle's w)
  std::vector<double> locus_a;        // that grid [m/s]
  std::vector<LimitCycle> cycles;
  std::string note;                   // why none is predicted, when none is
};

TransferFunction friction_loop(const Plant& plant, const LeadCompensator& c);
// a range: [a_min, a_max] m/s (velocity amplitudes searched).
LimitCycleReport predict_limit_cycles(const SteppedNonlinearity& f, const Plant& plant,
                                      const LeadCompensator& c, double a_min = 1e-6, double a_max = 10.0,
                                      const DfOptions& opt = {});

}  // namespace gmslab::control
