// gmslab core: one loader for every preset file.
//
// A preset is a plant and its run settings. A schema_version 1 file (a one-body scenario,
// core/io/scenario_io.hpp) and a schema_version 2 file (an assembled plant,
// core/io/assembly_io.hpp) both load as an AssemblyScenario: the one-body scenario is the assembly
// of one body "mass", its spring "spring" and damper "damper" to ground, one contact "friction"
// and one drive "drive" (assembly_from_scenario), and one_body() gives the scenario back.
// load_preset reads the file once, bounds its size and checks its schema_version once; every front
// end (window, render, CLI, Python) opens presets through it.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/sim/assembly.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab {

struct Preset {
  std::string file;            // where it was read from ("" for JSON handed in)
  int schema_version = 1;      // 1: a one-body scenario, 2: an assembled plant
  AssemblyScenario scenario;   // the plant and run settings (a version-1 file: its one-body assembly)
  bool assembled() const { return schema_version == 2; }
  // The one-body scenario of a version-1 file (one_body_scenario of the assembly). Throws
  // InputError naming the file for an assembled plant.
  Scenario one_body() const;
};

// Largest preset file read [bytes] (1e6 signal points fit in ~30 MB).
inline constexpr std::uintmax_t kMaxPresetBytes = 64u << 20;

// A schema_version 2 JSON as an assembled plant, anything else as a version-1 scenario (whose
// loader names the version found and the ones this gmslab reads). Throws InputError naming `file`
// and the key path.
Preset preset_from_json(const nlohmann::json& j, const std::string& file);
// Reads `path` once: refuses a file over kMaxPresetBytes before reading it, parses it, checks it.
Preset load_preset(const std::string& path);

// The folder of the shipped presets, the first that applies of: env GMSLAB_PRESETS (non-empty);
// the presets installed with this front end, `beside`, when that folder exists (default: those of
// this process's executable, EXE/../share/gmslab/presets, so an installed gmslab uses its own at
// any prefix; the Python module passes PREFIX/share/gmslab/presets from its package); the source
// tree's presets/ when it exists (a build tree); the configured install prefix's.
std::string presets_dir(const std::optional<std::string>& beside = std::nullopt);
// A preset argument as every front end takes it (CLI simulate / design / render, the window's
// --open, Python's load_scenario): `arg` when a file of that name exists; else a bare name
// ("fig4_stick_slip" or "fig4_stick_slip.json", also "presets/NAME.json" typed outside the source
// tree) resolved among the presets in `dir`; a path into another folder as given (its loader names
// it when it cannot be read). Throws InputError for a name that is neither: "WHAT 'ARG': no such
// file, and no preset 'NAME' in DIR; did you mean 'CLOSEST'? (presets: a, b, ...)" (`what` names
// the option, e.g. "--open"; "" for a positional argument).
std::string resolve_preset(const std::string& arg, const std::string& dir,
                           const std::string& what = "");

}  // namespace gmslab
