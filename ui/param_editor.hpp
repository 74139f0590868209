// gmslab ui: generic editors driven by the parameter tables (ParamSpec) of a ModelInfo, so every
// friction model in model_registry() gets the same editor with no model-specific UI code.
//
// Every field shows the paper's symbol and the SI unit, a tooltip with the meaning and the
// allowed range, clamps to that range, and uses a logarithmic slider where ParamSpec::log_scale.
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

// One number field for a spec. Returns true when the value changed (already clamped to range).
// `reference` (> 0, e.g. the model's default) centres the log slider's six decades.
bool edit_param(const char* id, const ParamSpec& spec, double& value, double reference = 0.0);

// Model selector over model_registry(); on change p becomes the new model's defaults().
bool edit_model_choice(const char* label, ModelParams& p);

// Scalars of p, then its element table (add / remove rows within the model's element count,
// one column per ParamSpec). With a live model + state, the table also shows each element's force
// [N] and stick/slip state. Returns true when p changed.
bool edit_model_params(const char* id, ModelParams& p, const FrictionModel* live = nullptr,
                       std::span<const double> live_state = {});

}  // namespace gmslab::ui
