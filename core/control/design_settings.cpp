#include "core/control/design_settings.hpp"

namespace gmslab {

const char* to_string(DesignReference r) {
  switch (r) {
    case DesignReference::Step: return "step";
    case DesignReference::Ramp: return "ramp";
    case DesignReference::Sine: return "sine";
  }
  return "sine";
}

std::optional<DesignReference> design_reference_from_string(std::string_view s) {
  for (auto r : {DesignReference::Step, DesignReference::Ramp, DesignReference::Sine})
    if (s == to_string(r)) return r;
  return std::nullopt;
}

namespace control {
void set_design_inputs(const DesignSettings& s, DesignInputs& in) {
  in.plant = s.plant;
  in.regime = regime_from_string(s.regime);
  in.velocity = s.velocity;
  in.root = design_root(s);
  in.K = s.use_K ? std::optional<double>(s.K) : std::nullopt;
  in.options.max_ratio = s.max_ratio;
  in.type = s.compensator;
  in.reference = s.reference == DesignReference::Step   ? Signal::constant(s.amplitude)
                 : s.reference == DesignReference::Ramp ? Signal::ramp(0.0, s.slope)
                                                        : Signal::sine(0.0, s.amplitude, s.frequency);
  in.compensation = compensation_from_string(s.compensation);
  in.feedforward_source = s.feedforward_source;
  in.mismatch.force = s.mismatch_force;
  in.mismatch.stiffness = s.mismatch_stiffness;
  in.sample_time = s.sample_time;
  in.other_regime = s.other_regime;
  in.zero_degree = s.zero_degree;
}
}  // namespace control

}  // namespace gmslab
