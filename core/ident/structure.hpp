// gmslab identification: structure in a residual, measured against the noise.
//
//   noise_level      the force noise standard deviation estimated from the data alone: second
//                    differences of F during rests (F held constant there), robust (MAD), or, with
//                    too few rest samples, over all used samples (an upper bound then).
//   ripple_search    a least-squares periodogram over position (Lomb-Scargle type, generalised to
//                    four columns sin, cos, g sin, g cos: an additive ripple and a ripple of the
//                    friction level, whose sign follows the direction) on sliding samples only
//                    (|v| > 5 v_rest and more than 4 x_ba of travel since the last reversal, so no
//                    presliding transient), after removing the residual's static-curve trend
//                    (1, sgn v, v, v|v|, Stribeck-like e^(-|v|/0.2 v_ref) sgn v) and a cubic in x.
//                    Wavelengths from 3x the 90th percentile of the position step between sliding
//                    samples (what the sampling resolves) up to half the sliding span (two periods).
//                    Each peak gets a false-alarm probability: the F statistic of its four columns
//                    against the larger of the residual variance and the local periodogram level
//                    (so coloured misfit is not read as a ripple), over the number of independent
//                    wavelengths scanned. Significant peaks are removed one by one (prewhitening),
//                    up to max_peaks ripples.
//   residual_structure  after the loop: is the final residual more than noise, and where (by
//                    velocity, by position, over time, after reversals, in the position spectrum)?
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/ident/effects.hpp"

namespace gmslab::ident {

struct NoiseEstimate {
  double sigma = 0;          // force noise standard deviation [N]
  std::size_t samples = 0;   // second differences used
  bool from_rests = false;   // false: from all used samples (includes signal; an upper bound)
  double quantum = 0;        // encoder step found in x (smallest position step) [m]
  double quantisation = 0;   // RMS force error that step gives through the model's stiffness [N]
  double sampling = 0;       // RMS force the unmeasured path between samples can change [N]
  // A second estimate of the sampling share (add_sampling_halving) [N]; < 0: not made.
  double sampling_halving = -1;
  // What noise, quantisation and sampling alone leave [N].
  double floor() const { return std::sqrt(sigma * sigma + quantisation * quantisation + sampling * sampling); }
};
NoiseEstimate noise_level(const Dataset& d, const EffectContext& c);
// Adds the quantisation share: x is known to +-q/2, so the force is known to Fc |dg/dx| q / sqrt(12)
// while moving (f = the fitted friction force along d, physical units).
void add_quantisation(NoiseEstimate& e, const Dataset& d, const EffectContext& c, const std::vector<double>& f);
// Adds the sampling share: the RMS over d's used samples of the fitted friction along the path
// the fit uses (f: the cubic through the samples where it is curved, dataset.hpp) less the same
// along straight lines between all samples (f_straight), over sqrt(3) (the true path taken
// anywhere between the two). A reversal or a stick-slip transition between two samples makes
// these differ; no model driven by the samples alone can resolve that.
void add_sampling(NoiseEstimate& e, const Dataset& d, const std::vector<double>& f,
                  const std::vector<double>& f_straight);
// Sets e.sampling_halving: the RMS over every 2nd used sample of f less the model along the path
// through every 2nd sample only (f_half[k / 2], the same velocities: dataset.hpp, decimated), over
// 2: what doubling the step changes. A path error that grows in proportion to the step and is
// independent between the two paths makes that difference sqrt(5) x the error at the record's
// own step; one that grows faster (a smooth motion's cubic), more. On random records it tracks
// what the path leaves far closer than add_sampling (docs/identification.md, *How close the floor
// estimate is*), but through a fitted model it can fall below what the fit leaves; the credit
// bound, which must not skip the rounds on a floor estimate set too high, takes the smaller of
// the two.
void add_sampling_halving(NoiseEstimate& e, const Dataset& d, const std::vector<double>& f,
                          const std::vector<double>& f_half);

struct RipplePeak {
  double wavelength = 0;       // [m]
  double amplitude = 0;        // RMS-equivalent sine amplitude of the four-column fit [N]
  double additive = 0;         // amplitude of the additive part [N]
  double modulation = 0;       // amplitude of the friction-level part [N per unit g]
  double f_statistic = 0;      // F(4, n) of the peak's columns
  double false_alarm = 1;      // probability that noise alone gives a peak this high [-]
  int harmonic_of = -1;        // index of an earlier peak whose wavelength is an integer multiple
};

struct RippleSearch {
  std::vector<double> wavelength, power;  // the scan: [m], SSR reduction [N^2] (descending L)
  double lmin = 0, lmax = 0;               // scanned range [m]
  double independent = 0;                  // independent wavelengths in the range
  std::size_t samples = 0;                 // sliding samples used
  std::vector<RipplePeak> peaks;           // significant peaks, in the order found
};

// The periodogram scans at most this many sliding samples (a fixed pseudo-random subset beyond).
inline constexpr std::size_t kRippleScan = 3000;
// r: residual, g: unit friction of the current fit (empty: sgn v). fap: largest false-alarm
// probability that counts as a ripple.
RippleSearch ripple_search(const Dataset& d, const EffectContext& c, const std::vector<double>& r,
                           const std::vector<double>& g, double fap = 1e-3, int max_peaks = 3);
nlohmann::json to_json(const RippleSearch& s);

// Remaining structure of a residual.
struct StructureFinding {
  std::string where;       // "velocity", "position", "time", "after_reversal", "position_spectrum"
  std::string detail;      // e.g. "|v| 10-20 mm/s", "wavelength 1.3 mm"
  double size = 0;         // RMS (or amplitude) of the structure [N]
  double size_to_noise = 0;  // size / noise floor (noise and quantisation) [-]
  double p_value = 1;      // chance of this under noise alone (after the number of bins tried)
};

struct ResidualStructure {
  NoiseEstimate noise;
  double rms = 0;                  // residual RMS on used samples [N]
  double rms_to_noise = 0;         // rms / noise floor (noise and quantisation) [-]
  std::vector<StructureFinding> findings;  // significant ones, largest first
  std::string summary;             // one line for a person (CLI, panel)
};
ResidualStructure residual_structure(const Dataset& d, const EffectContext& c,
                                     const std::vector<double>& r, const std::vector<double>& g,
                                     const NoiseEstimate& noise);
nlohmann::json to_json(const ResidualStructure& s);

}  // namespace gmslab::ident
