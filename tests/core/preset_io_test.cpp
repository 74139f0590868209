// One loader for every preset (core/io/preset_io.hpp): each shipped preset loads as the assembly its
// own loader gives; a version-1 file's one-body scenario comes back unchanged from its assembly; an
// assembled plant is no one-body scenario; errors name the file and key as the per-schema loaders do.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <filesystem>
#include <unistd.h>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("gmslab_preset_" + std::to_string(getpid()) + "_" + name)).string();
}

TEST(Preset, EveryShippedPresetLoadsAsItsOwnLoaderGivesIt) {
  int v1 = 0, v2 = 0;
  for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    const std::string path = e.path().string();
    SCOPED_TRACE(path);
    const Preset p = load_preset(path);
    EXPECT_EQ(p.file, path);
    EXPECT_EQ(p.schema_version, preset_schema_version(parse_json(read_file(path), path)));
    EXPECT_EQ(p.scenario, load_assembly_scenario(path));
    if (p.assembled()) {
      ++v2;
      EXPECT_THROW((void)p.one_body(), InputError);
    } else {
      ++v1;
      const Scenario s = load_scenario(path);
      EXPECT_EQ(p.one_body(), s);
      EXPECT_EQ(p.scenario, assembly_from_scenario(s));
    }
  }
  EXPECT_GE(v1, 10);
  EXPECT_GE(v2, 3);
}

TEST(Preset, OneBodyScenarioIsTheInverseOfTheMapping) {
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  for (const auto kind : {Drive::Kind::Displacement, Drive::Kind::Velocity, Drive::Kind::Force, Drive::Kind::Pull}) {
    s.drive.kind = kind;
    s.drive.pull_spring = kind == Drive::Kind::Pull ? 2.0 : 0.0;
    s.drive.pull_damper = kind == Drive::Kind::Pull ? 0.5 : 0.0;
    const auto back = one_body_scenario(assembly_from_scenario(s));
    ASSERT_TRUE(back.has_value()) << to_string(kind);
    EXPECT_EQ(*back, s) << to_string(kind);
  }
  // Any other shape is no one-body scenario.
  AssemblyScenario a = assembly_from_scenario(s);
  a.plant.bodies[0].name = "block";
  EXPECT_FALSE(one_body_scenario(a).has_value());
  a = assembly_from_scenario(s);
  a.plant.bodies.push_back({"second", 1.0});
  EXPECT_FALSE(one_body_scenario(a).has_value());
  a = assembly_from_scenario(s);
  a.plant.drives[0].point_velocity = true;
  EXPECT_FALSE(one_body_scenario(a).has_value());
  const Preset two = load_preset(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json");
  EXPECT_FALSE(one_body_scenario(two.scenario).has_value());
}

TEST(Preset, AnAssembledPlantIsNoOneBodyScenario) {
  const std::string path = std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json";
  std::string via_preset, via_scenario;
  try {
    (void)load_preset(path).one_body();
  } catch (const InputError& e) {
    via_preset = e.what();
  }
  try {
    (void)load_scenario(path);
  } catch (const InputError& e) {
    via_scenario = e.what();
  }
  EXPECT_NE(via_preset.find("version 2 is an assembled plant"), std::string::npos) << via_preset;
  EXPECT_EQ(via_preset, via_scenario);
}

TEST(Preset, ErrorsAreTheSchemaLoadersErrors) {
  // Version 1 (and a missing or unknown version) as load_scenario says it, version 2 as
  // load_assembly_scenario says it.
  const std::string v1 = read_file(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2a_presliding.json");
  for (const std::string& text :
       {std::string(R"({"name": "x"})"), std::string(R"({"schema_version": 7, "name": "x"})"),
        v1.substr(0, v1.find("\"run\"")) + R"("run": {"dt": -1, "duration": 1}})",
        std::string(R"({"schema_version": 2, "name": "t", "plant": {"bodies": [{"name": "m", "mass": -1}]},
                        "run": {"dt": 1e-5, "duration": 1}})")}) {
    const std::string path = temp_path("err.json");
    write_file_atomic(path, text);
    std::string want, got;
    try {
      if (preset_schema_version(parse_json(text, path)) == 2) load_assembly_scenario(path);
      else load_scenario(path);
    } catch (const InputError& e) {
      want = e.what();
    }
    try {
      load_preset(path);
    } catch (const InputError& e) {
      got = e.what();
    }
    fs::remove(path);
    ASSERT_FALSE(want.empty()) << text;
    EXPECT_EQ(got, want);
  }
}

TEST(Preset, HugeFileIsRefusedBeforeReading) {
  const std::string path = temp_path("huge.json");
  const int fd = ::open(path.c_str(), O_CREAT | O_TRUNC | O_WRONLY, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, 65ll << 20), 0);
  ::close(fd);
  try {
    load_preset(path);
    FAIL() << "huge file accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": the file is 68157440 bytes; a preset may be at most 67108864 bytes (64 MiB)");
  }
  fs::remove(path);
}

}  // namespace
}  // namespace gmslab
