// The design view's settings <-> the session's DesignSettings (core/io/session_io.hpp).
#include "ui/panel_state.hpp"

namespace gmslab::ui {

DesignSettings design_settings(const DesignViewState& d) {
  DesignSettings s;
  s.regime = control::to_string(d.in.regime);
  s.velocity = d.in.velocity;
  s.zeta = d.in.root.zeta;
  s.wn = d.in.root.wn;
  s.use_K = d.use_K;
  s.K = d.K;
  s.max_ratio = d.in.options.max_ratio;
  s.reference = d.reference;
  s.amplitude = d.amplitude;
  s.slope = d.slope;
  s.frequency = d.frequency;
  s.compensation = control::to_string(d.in.compensation);
  s.mismatch_force = d.in.mismatch.force;
  s.mismatch_stiffness = d.in.mismatch.stiffness;
  s.sample_time = d.in.sample_time;
  s.max_overshoot = d.max_overshoot;
  s.settling_time = d.settling_time;
  s.other_regime = d.in.other_regime;
  s.zero_degree = d.in.zero_degree;
  return s;
}

void apply_design_settings(DesignViewState& d, const DesignSettings& s) {
  d.in.regime = control::regime_from_string(s.regime);
  d.in.velocity = s.velocity;
  d.in.root = {s.zeta, s.wn};
  d.use_K = s.use_K;
  d.K = s.K;
  d.in.options.max_ratio = s.max_ratio;
  d.reference = s.reference;
  d.amplitude = s.amplitude;
  d.slope = s.slope;
  d.frequency = s.frequency;
  d.in.compensation = control::compensation_from_string(s.compensation);
  d.in.mismatch.force = s.mismatch_force;
  d.in.mismatch.stiffness = s.mismatch_stiffness;
  d.in.sample_time = s.sample_time;
  d.max_overshoot = s.max_overshoot;
  d.settling_time = s.settling_time;
  d.in.other_regime = s.other_regime;
  d.in.zero_degree = s.zero_degree;
  d.in.manual.reset();
  d.dirty = true;
}

}  // namespace gmslab::ui
