// Presets: round trip, strict loading with messages that name the problem, atomic save.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/io/atomic_file.hpp"
#include "core/sim/assembly.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  const auto dir = fs::temp_directory_path() / "gmslab_tests";
  fs::create_directories(dir);
  return (dir / name).string();
}

TEST(ScenarioIo, EveryShippedPresetRoundTrips) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    if (read_file(e.path().string()).find("\"schema_version\": 2") != std::string::npos) continue;  // assembly_test
    const Scenario a = load_scenario(e.path().string());
    const std::string out = temp_path("roundtrip_" + e.path().filename().string());
    save_scenario(a, out);
    const Scenario b = load_scenario(out);
    EXPECT_EQ(a, b) << e.path();
    ++n;
  }
  EXPECT_GE(n, 2);
}

// Loads `text` as a preset and returns the error message (empty if it loaded).
// Each test writes its own file: CTest runs tests in parallel processes.
std::string load_error(const std::string& text) {
  const std::string path =
      temp_path(std::string("bad_") +
                ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json");
  write_file_atomic(path, text);
  try {
    load_scenario(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string fig4_text() { return read_file(test_util::preset_path("fig4_stick_slip.json")); }

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}

TEST(ScenarioIo, UnknownKeyIsNamedWithItsPath) {
  const auto msg = load_error(replace(fig4_text(), "\"mass\": 1.0", "\"mass\": 1.0, \"mas\": 2"));
  EXPECT_NE(msg.find("plant.mas"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mass"), std::string::npos) << msg;  // lists what is allowed
}

TEST(ScenarioIo, MissingKeyIsNamed) {
  const auto msg = load_error(replace(fig4_text(), "\"dt\": 1e-5, ", ""));
  EXPECT_NE(msg.find("run.dt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
}

TEST(ScenarioIo, OutOfRangeValueNamesKeyAndRange) {
  const auto msg = load_error(replace(fig4_text(), "\"mass\": 1.0", "\"mass\": -1.0"));
  EXPECT_NE(msg.find("plant.mass"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(0, "), std::string::npos) << msg;
  EXPECT_NE(msg.find("kg"), std::string::npos) << msg;
}

TEST(ScenarioIo, WrongTypeIsNamed) {
  const auto msg = load_error(replace(fig4_text(), "\"Fs\": 1.5", "\"Fs\": \"1.5\""));
  EXPECT_NE(msg.find("friction.Fs"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a number"), std::string::npos) << msg;
}

TEST(ScenarioIo, FsBelowFcIsRejected) {
  const auto msg = load_error(replace(fig4_text(), "\"Fs\": 1.5", "\"Fs\": 0.5"));
  EXPECT_NE(msg.find("Fc must not exceed Fs"), std::string::npos) << msg;
}

TEST(ScenarioIo, WeightsNotSummingToOneAreRejected) {
  const auto msg = load_error(replace(fig4_text(), "\"alpha\": 0.4", "\"alpha\": 0.5"));
  EXPECT_NE(msg.find("sum to 1"), std::string::npos) << msg;
}

TEST(ScenarioIo, SyntaxErrorGivesLineAndColumn) {
  const auto msg = load_error("{\n  \"schema_version\": 1,\n  \"name\": oops\n}");
  EXPECT_NE(msg.find("bad_SyntaxErrorGivesLineAndColumn.json:3:"), std::string::npos) << msg;
}

TEST(ScenarioIo, UnknownModelListsKnownModels) {
  const auto msg = load_error(replace(fig4_text(), "\"model\": \"gms\"", "\"model\": \"gmx\""));
  EXPECT_NE(msg.find("gmx"), std::string::npos) << msg;
  EXPECT_NE(msg.find("known models"), std::string::npos) << msg;
}

TEST(ScenarioIo, StepTooLargeForStiffestElementIsRejectedBySimulation) {
  Scenario s = load_scenario(test_util::preset_path("fig4_stick_slip.json"));
  s.run.dt = 0.01;  // omega = sqrt(210002) ~ 458 rad/s -> limit 2/omega ~ 4.4 ms
  try {
    AssemblySimulation sim = one_body_simulation(s);
    FAIL() << "accepted dt = 0.01";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run.dt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("stiffest"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gmslab
