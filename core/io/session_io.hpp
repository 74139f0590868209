// gmslab core: the window's session as JSON (schema_version 3): what the window saves on exit to
// restore itself. Pure data and strict loading, like scenario_io.
//
// {
//   "schema_version": 4,
//   "scenario_path": "presets/fig4_stick_slip.json",   where the scenario came from ("" if none)
//   "scenario": { ...a full scenario, schema_version 1 (core/io/scenario_io.hpp)... },
//   "compare": {"model": "lugre", ...} | null,          overlay model on the same input
//   "view": {"speed": 1.0, "color_phases": true, "slip_velocity": 1e-4, "tab": "Simulation",
//            "friction_against": "auto"},                auto | displacement | velocity
//   "design": {"plant": {"source": "scenario", "num": "1", "den": "1 2 0", "drive": "", "output": ""},
//              "regime": "sliding", "velocity": 0, "zeta": 0.7, "wn": 60, "use_K": false,
//              "K": 1000, "max_ratio": 20, "reference": "sine", "amplitude": 0.01,
//              "slope": 0.01, "frequency": 2, "compensation": "gms", "mismatch_force": 1,
//              "mismatch_stiffness": 1, "sample_time": 0, "max_overshoot": 10,
//              "settling_time": 0.15, "other_regime": false, "zero_degree": false},
//   "identify": {"data": "", "validate": "", "columns": "", "mask": "", "validate_mask": "",
//                "mask_edges": "", "model": "gms", "elements": 4,
//                "compare": false},
//   "plant": {"path": "presets/two_mass_drive.json", "speed": 1.0, "magnification": 0,
//             "plotted": ["x.motor", "F.motor_friction"],    outputs shown in the plots
//             "linear_plant": {"drive": "motor_force", "output": "motor", "sliding": true},
//             "scenario": { ...the Plant tab's assembled plant as edited, schema_version 2
//                           (core/io/assembly_io.hpp)... }} | null      Plant tab empty
// }
// Every key is required, except "design.plant" (older sessions have none: the scenario's plant).
// design.plant.source: scenario | assembly | typed; num / den: coefficients highest power first,
// checked (finite, den's leading coefficient non-zero, deg num <= deg den). Versions 1 (no
// "design", no "identify"), 2 (no "identify") and 3 (no "plant") are still read; what they lack
// gets the defaults below, as those versions had no way to save it. Unknown keys, wrong types,
// non-finite or out-of-range values are InputErrors naming the file and the key path
// ("view.speed") with the allowed range; errors in the embedded scenario name the file as
// "FILE (in 'scenario')", those in the Plant tab's plant "FILE (in 'plant.scenario')".
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/control/design_settings.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab {

inline constexpr int kSessionSchemaVersion = 4;
inline constexpr int kOldestSessionSchemaVersion = 1;

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

// The Design tab's settings: DesignSettings, DesignReference (core/control/design_settings.hpp).

// The Identify tab's fields (what to identify; the run and its report are not saved).
struct IdentifySettings {
  std::string data;           // training CSV path (at most 4096 characters, as every field here)
  std::string validate;       // validation CSV path; "" = hold out a part of the training record
  std::string columns;        // column map "t=t_s,x=x_m,F=F_N"; "" = found by name
  std::string mask;           // training time windows "t0:t1,..." [s]
  std::string validate_mask;  // validation time windows [s]
  std::string mask_edges;     // COLUMN:BEFORE:AFTER [s]; "" = none (as the CLI's --mask-edges)
  std::string model = "gms";  // base model: a registry tag
  int elements = 4;           // element count of multi-element models, [1, 64]; 0 = auto
  bool compare = false;       // compare every model after the loop
  bool operator==(const IdentifySettings&) const = default;
};

// The Plant tab: its assembled plant as edited (the run and the undo history are not saved).
struct PlantTabSettings {
  std::string path;              // where it was loaded from / saves to (at most 4096 characters)
  AssemblyScenario scenario;     // validated as a schema-2 preset
  double speed = 1.0;            // simulated s per wall-clock s, [1e-3, 1e3]
  double magnification = 0.0;    // schematic [px per mm], [0, 1e6]; 0 = auto
  std::vector<std::string> plotted;  // output names (output_channels) shown in the plots, no repeats
  // The linear plant's input drive (a drive's name, "" when the plant has none), output body's
  // name, and whether the contacts are sliding (else stuck).
  std::string tf_drive, tf_output;
  bool tf_sliding = true;
  bool operator==(const PlantTabSettings&) const = default;
};

struct Session {
  std::string scenario_path;           // where the scenario was loaded from, "" if unknown
  Scenario scenario;                   // the scenario as edited
  std::optional<ModelParams> compare;  // overlay model, none if absent
  ViewSettings view;
  DesignSettings design;
  IdentifySettings identify;
  std::optional<PlantTabSettings> plant;  // none: the Plant tab had no plant
  bool operator==(const Session&) const = default;
};

nlohmann::json to_json(const Session& s);
// Throws InputError naming `file` and the key path.
Session session_from_json(const nlohmann::json& j, const std::string& file);
Session load_session(const std::string& path);               // throws InputError
void save_session(const Session& s, const std::string& path);  // atomic (write_file_atomic)

}  // namespace gmslab
