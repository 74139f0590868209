// gmslab core: the window's session as JSON (schema_version 1): what the window saves on exit to
// restore itself. Pure data and strict loading, like scenario_io.
//
// {
//   "schema_version": 1,
//   "scenario_path": "presets/fig4_stick_slip.json",   where the scenario came from ("" if none)
//   "scenario": { ...a full scenario, schema_version 1 (core/io/scenario_io.hpp)... },
//   "compare": {"model": "lugre", ...} | null,          overlay model on the same input
//   "view": {"speed": 1.0, "color_phases": true, "slip_velocity": 1e-4, "tab": "Simulation",
//            "friction_against": "auto"}                 auto | displacement | velocity
// }
// Every key is required. Unknown keys, wrong types, non-finite or out-of-range values are
// InputErrors naming the file and the key path ("view.speed") with the allowed range; errors in
// the embedded scenario name the file as "FILE (in 'scenario')".
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/sim/scenario.hpp"

namespace gmslab {

inline constexpr int kSessionSchemaVersion = 1;

// What the user chose to see (the window's view settings).
struct ViewSettings {
  double speed = 1.0;              // simulated seconds per wall-clock second, [1e-3, 1e3]
  bool color_phases = true;        // colour stick and slip phases in the time plots
  double slip_velocity = 1e-4;     // |v| above which the body counts as slipping [m/s], (0, 1e3]
  std::string tab = "Simulation";  // selected panel (at most 64 characters)
  // x axis of the friction plot: "displacement" (hysteresis), "velocity" (frictional lag), or
  // "auto" (velocity for a prescribed-velocity drive, else displacement)
  std::string friction_against = "auto";
  bool operator==(const ViewSettings&) const = default;
};

struct Session {
  std::string scenario_path;           // where the scenario was loaded from, "" if unknown
  Scenario scenario;                   // the scenario as edited
  std::optional<ModelParams> compare;  // overlay model, none if absent
  ViewSettings view;
  bool operator==(const Session&) const = default;
};

nlohmann::json to_json(const Session& s);
// Throws InputError naming `file` and the key path.
Session session_from_json(const nlohmann::json& j, const std::string& file);
Session load_session(const std::string& path);               // throws InputError
void save_session(const Session& s, const std::string& path);  // atomic (write_file_atomic)

}  // namespace gmslab
