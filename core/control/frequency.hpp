// gmslab core/control: frequency responses of a loop L(s) = num(s)/den(s) (gain included),
// unity negative feedback, T = L / (1 + L) = num / (den + num).
//
// Margins are found exactly, as polynomial roots in u = w^2 (never by a grid search):
//   with N(jw) = Nr(u) + j w Ni(u), D(jw) = Dr(u) + j w Di(u)  (real polynomials in u = w^2)
//   gain crossovers  |L(jw)| = 1      <=>  Nr^2 + u Ni^2 - Dr^2 - u Di^2 = 0,  u > 0
//   phase crossovers Im L(jw) = 0     <=>  Ni Dr - Nr Di = 0,  u > 0, with Re L(jw) < 0
//   (each root polished by Newton steps on its polynomial).
//   phase margin  PM = 180 deg + arg L(j w_gc) (arg continuous in w, the sum of the factors'
//   angles, so PM is in (-180, 180] per crossover); gain margin GM = -1 / L(j w_pc).
//   The reported margins are the smallest PM over the gain crossovers and the GM closest to 1
//   (in dB) over the phase crossovers, as MATLAB's margin(); every crossover is listed.
// Closed loop: bandwidth w_b = the lowest w > 0 with |T(jw)| = |T(0)| / sqrt(2) (roots of
//   2 |N|^2 - T(0)^2 |D + N|^2 in u); peak M_r = max |T(jw)| at w_r from the roots of
//   d/du (|N|^2 / |D + N|^2) (u = 0 included).
// Nyquist: the winding of 1 + L(s) about 0 tracked along the D-contour: the imaginary axis from
//   -j R to j R with a semicircle of radius eps to the right around every imaginary-axis pole
//   (poles at the origin included), closed by the semicircle of radius R through +R. Steps are
//   refined until arg(1 + L) moves less than 0.3 rad between points, so the count is exact.
//   N = clockwise encirclements of -1, P = open-loop poles with Re > 0 (those on the axis are
//   outside the indented contour), Z = N + P closed-loop poles with Re > 0. A closed-loop pole on
//   the contour (|1 + L| ~ 0 on it) is reported as marginal, and so is a contour that cannot be
//   counted: 1 + L not finite in doubles on it (coefficients near the double range), or more than
//   2,000,000 refinement points.
// Units: w in rad/s; magnitudes in dB (20 log10); phases in degrees.
#pragma once

#include <vector>

#include "core/control/transfer_function.hpp"

namespace gmslab::control {

struct Bode {
  std::vector<double> w;          // [rad/s], log-spaced, increasing
  std::vector<double> mag_db;     // 20 log10 |H(jw)| [dB]
  std::vector<double> phase_deg;  // arg H(jw), continuous in w [deg]
};

struct Margins {
  double gain_margin = 0.0;       // GM [-] (+inf: no phase crossover)
  double gain_margin_db = 0.0;    // 20 log10 GM [dB]
  double phase_crossover = 0.0;   // w_pc of that GM [rad/s] (NaN: none)
  double phase_margin = 0.0;      // PM [deg] (+inf: no gain crossover)
  double gain_crossover = 0.0;    // w_gc of that PM [rad/s] (NaN: none)
  std::vector<double> gain_crossovers;   // every w > 0 with |L| = 1 [rad/s], increasing
  std::vector<double> phase_crossovers;  // every w > 0 with L real negative [rad/s], increasing
};

struct Nyquist {
  std::vector<cplx> curve;  // L(jw) on the Bode grid (w > 0; the w < 0 half is its mirror)
  int open_rhp_poles = 0;   // P: open-loop poles with Re > 0
  int axis_poles = 0;       // open-loop poles on the imaginary axis (indented around)
  int encirclements = 0;    // N: clockwise encirclements of -1
  int closed_rhp_poles = 0; // Z = N + P
  bool marginal = false;    // a closed-loop pole lies on the imaginary axis, or the contour cannot be counted (N undefined)
  bool stable = false;      // Z == 0 and not marginal
};

struct FrequencyReport {
  Bode open;    // L(jw)
  Bode closed;  // T(jw)
  Margins margins;
  double dc_gain = 0.0;    // |T(0)| [-]
  double bandwidth = 0.0;  // w_b [rad/s] (NaN: |T| never drops to |T(0)|/sqrt 2, or T(0) = 0)
  double peak_db = 0.0;    // M_r [dB]
  double peak_w = 0.0;     // w_r [rad/s] (0: the peak is at DC)
  Nyquist nyquist;
};

struct FrequencyOptions {
  int points = 400;    // Bode / Nyquist samples
  double w_min = 0.0;  // [rad/s]; 0: automatic (1/20 of the lowest break or crossover)
  double w_max = 0.0;  // [rad/s]; 0: automatic (20x the highest)
};

// Throws InputError (naming "frequency response") for an improper or zero L.
FrequencyReport frequency_response(const TransferFunction& L, const FrequencyOptions& opt = {});
Margins margins(const TransferFunction& L);
Nyquist nyquist_count(const TransferFunction& L);
// arg H(jw) [rad], continuous in w > 0 (the sum of its factors' angles plus the sign of the gain).
double continuous_phase(const TransferFunction& H, double w);
std::vector<double> continuous_phase(const TransferFunction& H, const std::vector<double>& w);  // [rad]

}  // namespace gmslab::control
