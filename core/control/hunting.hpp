// gmslab core/control: the hunting (stick-slip limit cycle) that integral action causes with
// friction, predicted by a describing function of the *mass with its friction and the fast part of
// the controller*.
//
// The velocity-input describing function (describing_function.hpp) never sticks, so it cannot see
// stick-slip hunting. Here the compensator with one integrator is split as
//   C(s) = R / s + C_f(s),  R = lim s C(s) [N/(m s)],  C_f proper without the integrator
// (PI Kc (s + z)/s: R = Kc z, C_f = Kc; PID Kc (s + z)(s + zi)/((s + p) s): C_f = Kc (s + z')/(s + p),
// z' = z + zi - z zi / p). The nonlinear block is the one-body plant with its friction *and* C_f
// (the fast proportional / lead feedback that ends each slip), driven by the integral force u_I:
//   m x'' = u_I + C_f(-x) - k x - c v - F_f,
// stepped as the loop simulation steps it (loop_simulation.cpp: u from the state at the step's start,
// friction step with v frozen, v += h (f - F_f)/m, x += h v; C_f's state advanced exactly, e held).
// Its describing function P(A, w) = X1 / U1: u_I a periodic wave of frequency w and peak A
// (a sine, or a triangle: the integral of the piecewise-constant error of stick-slip), U1 its first
// harmonic phasor, X1 that of x over the block's periodic response (below). The loop with a
// constant reference closes through the
// integrator: u_I = -(R/s) x, so
//   1 + (R / (jw)) P(A, w) = 0:  arg P = -90 deg (phase) and R |P| / w = 1 (gain).
// The block's periodic response is found by shooting: the symmetric stick-slip cycle (stuck at -X0
// as the drive rises through 0, at +X0 half a period later), X0 by bisection of the half-period map;
// when there is none (the mass keeps sliding) the last of `periods` periods from X0 = Xmax / 2
// (linear drift removed); stuck at every X0: P = 0.
// Solution: at a frequency w, the A where arg P = -90 deg (scan of a log grid of A over
// [0.2, 100] x break-away, bisection in ln A); when the sustained cycles of the block lag the drive
// by less than 90 deg at every A (measured: the slip's finite duration), the A closest to it, the
// sustain threshold below which the block sticks (its phase residual is reported). Then the gain
// balance by the fixed point w <- R |P(A(w), w)|. Stability: an exact phase root by Loeb (with
// g(ln A, ln w) = ln(-(R/jw) P) the cycle attracts when Im(g_A / g_w) < 0, finite differences); a
// threshold solution is stable (smaller cycles stick and the integrator winds up again; larger ones
// lag less than the balance needs).
// Validity: the waveform the loop would feed back, u_I = -R int x dt over the predicted cycle,
// against the assumed drive wave (both zero-mean, scaled to the same first harmonic):
// waveform_error = rms(difference) / rms(assumed); and the phase residual of a threshold solution.
// Above kHuntingWaveformLimit or kHuntingPhaseLimit the prediction is flagged as outside the
// describing function's validity (measured against simulation: tests/control/hunting_df_test.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/control/linear_response.hpp"
#include "core/friction/model.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab::control {

// Above this waveform error of the predicted cycle the prediction is flagged as not applying.
inline constexpr double kHuntingWaveformLimit = 0.15;
// Above this |arg P + 90 deg| (the threshold solution's phase residual) likewise [rad] (3 deg;
// measured: the one valid-looking case at 3.4 deg was 25 % off in period, README).
inline constexpr double kHuntingPhaseLimit = 3.0 * 3.14159265358979 / 180.0;

enum class DriveWave { Sine, Triangle };
const char* to_string(DriveWave w);  // "sine" | "triangle"

struct HuntingOptions {
  DriveWave wave = DriveWave::Triangle;
  int steps = 400;       // per period (raised so that the step stays <= max_step)
  int periods = 4;       // periods run; harmonics over the last one
  int amplitudes = 20;   // log grid of A over [0.2, 100] x break-away
  double max_step = 0.0;  // [s]; 0: none (predict_hunting sets limit_fraction x the block's stability limit)
  double limit_fraction = 0.5;  // of the stability limit 2 / sqrt((k + sum k_i + C_f's gain) / m)
  int max_steps = 20000;  // per period: a slower w is outside the prediction's range (no motion)
  int shooting = 12;      // grid points and bisection steps of the stick level X0 (below 12 also
                          // fewer bisection steps in A: 7 on the phase, 5 on the threshold, for 10, 8)
};
// What the Design view recomputes on every drag (200 steps per period, 8 amplitudes, 6 shooting
// steps, 0.9 x the stability limit, <= 4000 steps per period): one drag stays under 16 ms.
HuntingOptions view_rate_hunting_options();

// C_f(s) = d + cst / (s + a) (cst = 0: a gain), acting on e = -x [N].
struct FastPart {
  double d = 0.0;    // high-frequency gain [N/m]
  double cst = 0.0;  // [N/(m s)]
  double a = 0.0;    // pole [rad/s]
};
struct IntegralSplit {
  double R = 0.0;  // integral gain lim s C(s) [N/(m s)]
  FastPart fast;
};
// nullopt unless exactly one section is an integrator (p_i = 0).
std::optional<IntegralSplit> integral_split(const LeadCompensator& c);

// The block driven by u_I (wave of peak A, frequency w) at periodic steady state.
struct PlantHarmonics {
  cplx P;                // X1 / U1 [m/N]
  cplx X1, X3;           // first and third harmonic phasors of x over the last period [m]
  double half_pp = 0.0;  // half peak-to-peak of x over the last period [m]
  double settle = 0.0;   // |X1(last) - X1(previous period)| / |X1(last)| (0 with one period)
  std::vector<double> x;  // x over the last period (detrended), when asked for [m]
};
// Throws InputError for A <= 0, w <= 0, m <= 0, steps < 16 / periods < 1, or a w that needs more
// than max_steps per period.
PlantHarmonics plant_harmonics(const Plant& plant, const FrictionModel& friction, const FastPart& fast, double A,
                               double w, const HuntingOptions& opt = {}, bool keep_x = false);

struct HuntingCycle {
  double force_amplitude = 0.0;  // A: peak of the integral force u_I [N]
  double frequency = 0.0;        // w [rad/s]
  double period = 0.0;           // 2 pi / w [s]
  double amplitude = 0.0;        // half peak-to-peak of x in the predicted cycle [m] (as loop_metrics)
  double first_harmonic = 0.0;   // |X1| [m]
  cplx plant_gain;               // P(A, w) [m/N]
  double waveform_error = 0.0;   // [-], see above
  double phase_residual = 0.0;   // arg P + 90 deg at the solution [rad] (0: exact phase balance)
  bool stable = false;
  bool converged = false;        // the gain balance converged (|ln(R |P| / w)| < 5e-3)
  bool valid = false;            // converged, |phase_residual| <= kHuntingPhaseLimit and
                                 // waveform_error <= kHuntingWaveformLimit
};

struct HuntingReport {
  DriveWave wave = DriveWave::Triangle;
  double break_away = 0.0;           // Fs of the model [N]
  double integral_gain = 0.0;        // R [N/(m s)] (0: no integrator)
  std::vector<HuntingCycle> cycles;  // by increasing A
  std::string note;                  // why none is predicted, when none is
  int evaluations = 0;               // block runs used
  // The valid stable cycle with the smallest A, else the stable one with the smallest A (nullptr:
  // none).
  const HuntingCycle* hunting() const;
};

// Throws InputError for a bad compensator or plant.
HuntingReport predict_hunting(const Plant& plant, const ModelParams& friction, const LeadCompensator& c,
                              const HuntingOptions& opt = {});

}  // namespace gmslab::control
