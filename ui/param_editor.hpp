// gmslab ui: generic editors driven by the parameter tables (ParamSpec) of a ModelInfo, so every
// friction model in model_registry() gets the same editor with no model-specific UI code.
//
// Every field shows the paper's symbol and the SI unit, a tooltip with the meaning and the
// allowed range, and drags logarithmically where ParamSpec::log_scale.
#pragma once

#include <span>
#include <string>

#include "core/friction/model.hpp"

namespace gmslab::ui {

// Pretty symbol for display: Greek names become letters when the font has them ("sigma_2" ->
// "σ_2"). Returns UTF-8.
std::string display_symbol(std::string_view symbol);
// "F_s [N]": symbol and unit.
std::string field_label(const ParamSpec& s);

// Rejected values, marked on their field: the field (ImGui id) whose value was rejected, the value
// typed and why. A panel owns one and passes it to its editors; it sets `rejected` from
// `last_edited` when a whole-scenario check refuses an edit (e.g. F_c above F_s).
struct FieldMarks {
  unsigned rejected = 0;     // ImGuiID of the marked field (0: none)
  std::string message;       // shown next to that field, in red
  unsigned last_edited = 0;  // the field changed last
  unsigned typing = 0;       // a field being typed into holds an out-of-range value...
  std::string typing_message;  // ...rejected (marked) only when the typing ends
  void reject(std::string why) { rejected = last_edited, message = std::move(why); }
  void clear() { rejected = 0, message.clear(); }
};

// One number field for a spec, the same everywhere: click to type (Enter or clicking away keeps
// it), drag the handle at its right (log specs: multiplicatively, 200 px per decade; linear:
// proportionally) or Alt+drag on the field. Returns true when the value changed.
// With marks, a typed value out of the spec's range is rejected: the field keeps the value in
// force, gets a red frame and the message under it; without marks it is clamped to the range.
// `reference` (> 0, e.g. the model's default) sets the drag step of linear fields near 0.
bool edit_param(const char* id, const ParamSpec& spec, double& value, double reference = 0.0,
                FieldMarks* marks = nullptr);

// Model selector over model_registry(); on change p becomes the new model's defaults().
bool edit_model_choice(const char* label, ModelParams& p);

// Scalars of p, then its element table (add / remove rows within the model's element count,
// one column per ParamSpec). With a live model + state, the table also shows each element's force
// [N] and stick/slip state. Returns true when p changed.
bool edit_model_params(const char* id, ModelParams& p, const FrictionModel* live = nullptr,
                       std::span<const double> live_state = {}, FieldMarks* marks = nullptr);

}  // namespace gmslab::ui
