// gmslab core: scenario presets as JSON (schema_version 1), strict loading, atomic saving.
//
// {
//   "schema_version": 1,
//   "name": "...", "description": "...",
//   "friction": {"model": "gms", "Fs": 1.5, ..., "elements": [{"alpha": 0.1, "k": 75000, ...}]},
//   "plant": {"mass": 1.0, "spring": 0.0, "damper": 0.0},            [kg, N/m, N s/m]
//   "drive": {"type": "pull", "signal": {"type": "ramp", "value": 0, "slope": 0.1},
//             "spring": 2.0, "damper": 0.0},                           (spring/damper: pull only)
//   "run": {"dt": 1e-5, "duration": 25, "record_every": 10}           [s, s, -]
// }
// Every key is required unless marked optional in the loader (description, plant.spring,
// plant.damper, run.record_every); unknown keys, wrong types, non-finite or out-of-range values
// are errors naming the file and the key path.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/io/json_reader.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab {

inline constexpr int kScenarioSchemaVersion = 1;

nlohmann::json to_json(const ModelParams& p);
nlohmann::json to_json(const Signal& s);
nlohmann::json to_json(const Scenario& s);

ModelParams model_params_from_json(JsonReader& r);  // reads "model" and the model's keys
Signal signal_from_json(JsonReader& r);
// The "run" object (dt, duration, record_every; at most 1e10 steps), finished.
RunSettings run_settings_from_json(JsonReader& run);
Scenario scenario_from_json(const nlohmann::json& j, const std::string& file);

Scenario load_scenario(const std::string& path);
// A shipped preset by its bare name ("two_mass_drive" or "two_mass_drive.json") in `dir`: its
// path, or empty when there is none (or `name` names a folder).
std::string shipped_preset(const std::string& name, const std::string& dir);
// The names (stems) of the presets in `dir`, sorted, comma-separated (empty: none).
std::string preset_names(const std::string& dir);
void save_scenario(const Scenario& s, const std::string& path);  // atomic

}  // namespace gmslab
