#include "core/io/preset_io.hpp"

#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/scenario_io.hpp"
#include "core/text/closest_word.hpp"

#ifndef GMSLAB_INSTALLED_PRESETS
#define GMSLAB_INSTALLED_PRESETS "/usr/share/gmslab/presets"
#endif

namespace gmslab {

Scenario Preset::one_body() const {
  if (auto s = one_body_scenario(scenario); s && !assembled()) return *s;
  throw InputError(file + ": key 'schema_version': version 2 is an assembled plant (core/io/assembly_io.hpp); "
                   "it opens in the Plant view (gmslab render FILE --view plant), not as a one-body scenario");
}

Preset preset_from_json(const nlohmann::json& j, const std::string& file) {
  Preset p;
  p.file = file;
  if (preset_schema_version(j) == kAssemblySchemaVersion) {
    p.schema_version = kAssemblySchemaVersion;
    p.scenario = assembly_scenario_from_json(j, file);
  } else {
    p.schema_version = kScenarioSchemaVersion;
    p.scenario = assembly_from_scenario(scenario_from_json(j, file));
  }
  return p;
}

Preset load_preset(const std::string& path) {
  std::error_code ec;
  if (const auto bytes = std::filesystem::file_size(path, ec); !ec && bytes > kMaxPresetBytes)
    throw InputError(path + ": the file is " + std::to_string(bytes) + " bytes; a preset may be at most " +
                     std::to_string(kMaxPresetBytes) + " bytes (64 MiB)");
  return preset_from_json(parse_json(read_file(path), path), path);
}

namespace {
namespace fs = std::filesystem;

// EXE/../share/gmslab/presets for this process's executable ("" when it cannot be read).
std::string presets_beside_executable() {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return {};
  const fs::path exe(std::string(buf, static_cast<std::size_t>(n)));
  return (exe.parent_path().parent_path() / "share" / "gmslab" / "presets").string();
}

std::vector<std::string> preset_stems(const std::string& dir) {
  std::error_code ec;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  return names;
}
}  // namespace

std::string presets_dir(const std::optional<std::string>& beside) {
  if (const char* env = std::getenv("GMSLAB_PRESETS"); env && *env) return env;
  std::error_code ec;
  const std::string own = beside ? *beside : presets_beside_executable();
  if (!own.empty() && fs::is_directory(own, ec)) return fs::path(own).lexically_normal().string();
#ifdef GMSLAB_SOURCE_DIR
  if (fs::is_directory(GMSLAB_SOURCE_DIR "/presets", ec)) return GMSLAB_SOURCE_DIR "/presets";
#endif
  return GMSLAB_INSTALLED_PRESETS;
}

std::string resolve_preset(const std::string& arg, const std::string& dir,
                           const std::string& what) {
  std::error_code ec;
  const std::string named = (what.empty() ? "" : what + " ") + "'" + arg + "'";
  if (arg.empty())
    throw InputError(named + ": no preset given; name a preset file or a shipped preset");
  if (fs::is_regular_file(arg, ec)) return arg;
  fs::path p(arg);
  // "presets/NAME.json" as the README writes it, typed outside the source tree.
  if (p.is_relative() && p.has_parent_path() && *p.begin() == "presets")
    p = p.lexically_relative("presets");
  if (p.has_parent_path() && p.parent_path() != ".")
    return arg;  // another folder: its loader says what is wrong
  if (std::string found = shipped_preset(p.filename().string(), dir); !found.empty()) return found;
  const std::string stem = p.extension() == ".json" ? p.stem().string() : p.filename().string();
  const std::string list = preset_names(dir);
  const std::string near = closest_word(stem, preset_stems(dir));
  throw InputError(named + ": no such file, and no preset '" + stem + "' in " + dir +
                   (near.empty() ? "" : "; did you mean '" + near + "'?") +
                   " (presets: " + (list.empty() ? "none found" : list) + ")");
}

}  // namespace gmslab
