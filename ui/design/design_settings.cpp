// The design view's settings from a session (the view holds them as one DesignSettings).
#include "ui/panel_state.hpp"

namespace gmslab::ui {

void apply_design_settings(DesignViewState& d, const DesignSettings& s) {
  control::DesignInputs in = d.in;
  control::set_design_inputs(s, in);  // throws InputError before anything is changed
  d.in = std::move(in);
  d.settings = s;
  d.in.manual.reset();
  d.dirty = true;
}

}  // namespace gmslab::ui
