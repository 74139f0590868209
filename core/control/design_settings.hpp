// gmslab core/control: the root-locus design view's settings (the Design tab) as one struct, used
// by the panel (which edits it), the session file (core/io/session_io.hpp saves it as "design") and
// the headless renderer alike. The computation's inputs (DesignInputs) are derived from it in one
// place, set_design_inputs(); nothing else copies it field by field.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/control/design_session.hpp"

namespace gmslab {

// The design loop's reference signal; saved as "step" | "ramp" | "sine".
enum class DesignReference { Step, Ramp, Sine };
const char* to_string(DesignReference r);
// nullopt for any other text.
std::optional<DesignReference> design_reference_from_string(std::string_view s);

// The Design tab's settings; ranges are those of its fields (checked when a session is loaded).
struct DesignSettings {
  control::PlantChoice plant;       // plant source: scenario / assembled drive -> output / typed num/den
  std::string regime = "sliding";   // plant regime: "presliding" | "sliding"
  double velocity = 0.0;            // sliding operating velocity v0 [m/s], [0, 1e3]; 0: automatic
  double zeta = 0.7;                // desired dominant damping ratio [-], [0.02, 0.98]
  double wn = 60.0;                 // desired dominant natural frequency [rad/s], (0, 1e5]
  bool use_K = false;               // target `K` (else the usable maximum)
  double K = 1000.0;                // desired error constant (Kp / Kv / Ka by plant type), (0, 1e7]
  double max_ratio = 20.0;          // bound on the lead's p / z [-], [1.5, 100]
  // Compensator type built from the design (saved as "lead" | "lag" | "lead_lag" | "pi" | "pid").
  control::CompensatorType compensator = control::CompensatorType::Lead;
  DesignReference reference = DesignReference::Sine;  // loop reference
  double amplitude = 0.01;          // step height / sine amplitude [m], (0, 1]
  double slope = 0.01;              // ramp velocity [m/s], (0, 1]
  double frequency = 2.0;           // sine frequency [Hz], (0, 100]
  std::string compensation = "gms";  // friction compensation of the second loop: "coulomb" | "gms"
  // What drives that compensation (saved as "reference" | "measured"): the reference velocity, or the
  // measured one (the DF prediction of that loop then uses the compensated nonlinearity F - F_hat).
  control::FeedforwardSource feedforward_source = control::FeedforwardSource::Reference;
  double mismatch_force = 1.0;      // compensator's Fs, Fc / plant's [-], [0.2, 2]
  double mismatch_stiffness = 1.0;  // compensator's k_i / plant's [-], [0.1, 10]
  double sample_time = 0.0;         // controller sample time [s], [0, 0.01]; 0: continuous
  double max_overshoot = 10.0;      // requirement [%], [0.1, 90] (drawn, not computed from)
  double settling_time = 0.15;      // requirement, 2 % band [s], (0, 100] (drawn, not computed from)
  bool other_regime = false;        // also draw the other regime's locus
  bool zero_degree = false;         // also draw the 0-degree locus
  bool operator==(const DesignSettings&) const = default;
};

namespace control {
// The desired dominant roots of the settings.
inline DominantRoot design_root(const DesignSettings& s) { return {s.zeta, s.wn}; }
// Sets every field of `in` that the settings determine (plant choice, regime, velocity, root, K, options'
// max_ratio, reference signal, compensation, mismatch, sample time, extra loci); leaves the rest
// (scenario, manual compensator, horizon, simulate, locus view) alone. Throws InputError for a
// regime or compensation name that is not one.
void set_design_inputs(const DesignSettings& s, DesignInputs& in);
}  // namespace control

}  // namespace gmslab
