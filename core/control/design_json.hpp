// gmslab core/control: JSON form of a lead design report, its frequency responses, limit cycles,
// compensator and loop metrics (the parts of core/control/design_report.hpp's JSON).
// Non-finite numbers (K_max where no lead applies, NaN metrics) are written as null.
// Keys: applicable, reason, phi_deg, beta_deg, s_d [re, im], type, constant ("Kp"/"Kv"/"Ka"),
// K0, M, K_max, K_max_usable, max_ratio, pd_limit {Kd, z}, usable_design {z, p, Kc, K},
// and when a design exists: z, p, Kc, K, ratio (p/z), within_max_ratio, closed_loop_poles
// [[re, im], ...], dominant, notes; when K is out of reach: relocations [{path (= name), found, wn, zeta,
// z, p, Kc, K, K_max, closed_loop_poles | reason, peak_K, peak_wn, peak_zeta}].
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/control/describing_function.hpp"
#include "core/control/discrete.hpp"
#include "core/control/frequency.hpp"
#include "core/control/hunting.hpp"
#include "core/control/lead_design.hpp"
#include "core/control/loop_simulation.hpp"

namespace gmslab::control {

nlohmann::json to_json(const LeadReport& r);
nlohmann::json to_json(const LoopMetrics& m);
nlohmann::json poles_json(const std::vector<cplx>& poles);
// The "frequency" key: margins {gain_margin, gain_margin_db, phase_crossover_rad_s,
// phase_margin_deg, gain_crossover_rad_s, gain_crossovers_rad_s [..], phase_crossovers_rad_s [..]},
// closed_loop {dc_gain, bandwidth_rad_s, peak_db, peak_rad_s}, nyquist {open_rhp_poles (P),
// axis_poles, encirclements (N, clockwise), closed_rhp_poles (Z = N + P), marginal, stable}.
// Infinite margins (no crossover) are null.
nlohmann::json to_json(const FrequencyReport& f);
// The sampled loop: {sample_time_s, nyquist_frequency_rad_s, margins {...as above}, nyquist {...},
// closed_loop_poles_z [[re, im], ...]}.
nlohmann::json to_json(const DiscreteFrequencyReport& f);
// The z-plane locus's key facts: unit-circle crossings {z [re, im], omega_rad_s, gain}, stable gain
// intervals [[lo, hi | null for +inf]], whether the gain Kc is inside one, open-loop poles/zeros in z.
nlohmann::json to_json(const ZLocus& z, double Kc);
// The "limit_cycles" key: cycles [{velocity_amplitude_m_s, amplitude_m, frequency_rad_s, period_s,
// stable, converged}], note.
nlohmann::json to_json(const LimitCycleReport& r);
// The hunting prediction (core/control/hunting.hpp), key limit_cycles.hunting: cycles
// [{force_amplitude_N (peak of the integral force), frequency_rad_s, period_s, amplitude_m (half
// peak-to-peak of x), first_harmonic_m, waveform_error, phase_residual_deg, stable, converged, valid}], wave,
// break_away_N, integral_gain_N_per_m_s, waveform_error_limit, note.
nlohmann::json to_json(const HuntingReport& r);
// The compensator Kc prod_i (s + z_i) / (s + p_i) for export: {"num": Kc prod (s + z_i), "den":
// prod (s + p_i) (highest power first; one section: [Kc, Kc z], [1, p]), "Kc", "z", "p" (the first
// section), "sections": [{z, p}, ...], "matlab": "C = tf([...], [...]);", "python": "C =
// control.tf([...], [...])"}.
// Coefficients written with 17 significant digits (round-trip exact).
nlohmann::json compensator_json(const LeadCompensator& c);
std::string compensator_matlab(const LeadCompensator& c);
std::string compensator_python(const LeadCompensator& c);

}  // namespace gmslab::control
