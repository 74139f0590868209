#include "core/io/preset_io.hpp"

#include <filesystem>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/scenario_io.hpp"

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

}  // namespace gmslab
