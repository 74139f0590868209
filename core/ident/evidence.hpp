// gmslab identification: evidence a person can read for each effect of the catalog, computed from
// the residual r = F_meas - F_fit on the training record (used samples only).
//
//   inertia              corr(r, a)
//   offset               mean(r) [N]
//   direction_asymmetry  mean r for v > 0 and v < 0 while sliding [N], corr(r, |v|)
//   position_periodic    the ripple search (structure.hpp): significant peaks of the residual's
//                        periodogram over position on sliding samples, with false-alarm probability
//   position_dependent   corr(r, x), corr(r, g x)
//   time_drift           corr(r, t), corr(r, g t)
//   velocity_extra       mean of r sgn(v) per |v| bin [N] (the residual static curve)
//   dwell_stiction       per motion start after a rest: rest duration [s], peak of r sgn(v) over
//                        the first s0 of travel [N]; corr(ln(1 + T_d / tau_d), peak)
//   normal_load          corr(r, g (Fn / Fn0 - 1))
//   time_shift           tau [s, samples], corr(r, g(t - tau) - g), corr(r, a)
//   sensor_filter        T [s, samples], corr(r, lowpass_T(g) - g)
//   backlash             b [m], corr(r, g_b - g), mean r sgn(v) over the first 2 b after reversals
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "core/ident/effects.hpp"

namespace gmslab::ident {

struct Spectrum {
  std::vector<double> wavelength;  // [m]
  std::vector<double> amplitude;   // [N]
  double peak_wavelength = 0;      // [m], 0 when there is no clear peak
  double peak_amplitude = 0;       // [N]
  double peak_to_median = 0;       // [-]
};

struct RippleSearch;

// Position-domain amplitude spectrum of the residual (the report figure's panel D).
Spectrum position_spectrum(const Dataset& d, const EffectContext& c, const std::vector<double>& r);

// Evidence for one effect (a JSON object of named numbers and small tables).
// g_contact (backlash): the unit output along the contact's motion through the dead band.
nlohmann::json effect_evidence(Effect e, const Dataset& d, const EffectContext& c,
                               const std::vector<double>& r, const std::vector<double>& g,
                               const RippleSearch& ripples,
                               const std::vector<double>* g_contact = nullptr);

}  // namespace gmslab::ident
