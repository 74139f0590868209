// gmslab core: assembled-plant presets (schema_version 2), strict loading, atomic saving.
//
// {
//   "schema_version": 2,
//   "name": "...", "description": "...",                          (description optional)
//   "plant": {
//     "bodies":   [{"name": "motor", "mass": 0.5}, ...],             1 to 8 bodies [kg]
//     "springs":  [{"name": "shaft", "a": "motor", "b": "load", "stiffness": 2000}],    [N/m]
//     "dampers":  [{"name": "loss", "a": "motor", "b": "ground", "damping": 0.1}],      [N s/m]
//     "contacts": [{"name": "pad", "a": "slider", "b": "table", "friction": {"model": "gms", ...}}],
//     "drives":   [{"name": "motor", "type": "force", "body": "motor", "signal": {...}},
//                  {"name": "pull", "type": "pull", "body": "block", "signal": {...},
//                   "spring": 2.0, "damper": 0.0, "point_velocity": false}]   (pull only)
//   },                                       springs, dampers, contacts, drives: optional, [] default
//   "run": {"dt": 1e-5, "duration": 10, "record_every": 10}
// }
// Parts name their ends by body name or "ground". Errors name the file and key path: an unknown
// body ("plant.springs[0].b: unknown body 'lod'"), a part to itself, a body connected neither to
// ground nor to a drive, a negative mass, unknown keys. Version-1 files load as one-body assemblies
// (assembly_from_scenario), unchanged.
#pragma once

#include <nlohmann/json.hpp>
#include <functional>
#include <ostream>
#include <string_view>
#include <string>

#include "core/sim/assembly.hpp"

namespace gmslab {

inline constexpr int kAssemblySchemaVersion = 2;

nlohmann::json to_json(const AssemblyScenario& s);
// Reads schema_version 2, or 1 (mapped onto the general plant).
AssemblyScenario assembly_scenario_from_json(const nlohmann::json& j, const std::string& file);
AssemblyScenario load_assembly_scenario(const std::string& path);
void save_assembly_scenario(const AssemblyScenario& s, const std::string& path);  // atomic
// The trace as CSV: t_s, every output channel (name_unit: x.motor_m, v.motor_mps, F.shaft_N), then
// each contact's gross-slip flag (slip.CONTACT, 1 = slipping). Full precision (%.17g).
void write_assembly_trace_csv(const AssemblyTrace& tr, std::ostream& out);
// Simulates and hands the CSV to `sink` in pieces as it is computed (header first, then chunks of
// rows): constant memory whatever the run length, as the one-body stream_trace_csv. Returns the
// sample count.
std::size_t stream_assembly_trace_csv(const AssemblyScenario& s, const std::function<void(std::string_view)>& sink);
// The same into a file written atomically (temporary file, renamed once the run is complete).
std::size_t save_assembly_trace_csv(const AssemblyScenario& s, const std::string& path);
// schema_version of a preset file's JSON (0 when absent or not an integer).
int preset_schema_version(const nlohmann::json& j);

}  // namespace gmslab
