// `gmslab simulate PRESET --out trace.csv` through the command-line layer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/cli/cli.hpp"
#include "core/io/atomic_file.hpp"
#include "test_util.hpp"
#include "tests/core/run_cli.hpp"

namespace gmslab {
namespace {

using gmslab::test_util::run_cli;

TEST(CliSimulate, WritesTraceWithUnitsMatchingTheLibrary) {
  const auto out = (std::filesystem::temp_directory_path() / "gmslab_cli_trace.csv").string();
  const auto preset = test_util::preset_path("fig2a_presliding.json");
  ASSERT_EQ(run_cli({"simulate", preset, "--out", out}), 0);
  std::istringstream csv(read_file(out));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t_s,x_m,v_mps,F_friction_N,F_applied_N,F1_N,", 0), 0u) << header;
  EXPECT_NE(header.find("slip4"), std::string::npos);
  const Trace tr = simulate(load_scenario(preset));
  std::size_t rows = 0;
  std::string line;
  double max_err = 0.0;
  while (std::getline(csv, line)) {
    double t, x, v, f;
    char c;
    std::istringstream row(line);
    row >> t >> c >> x >> c >> v >> c >> f;
    max_err = std::max(max_err, std::abs(f - tr.friction.at(rows)));
    ++rows;
  }
  EXPECT_EQ(rows, tr.size());
  EXPECT_LT(max_err, 1e-8);
}

TEST(CliSimulate, MissingPresetIsAClearErrorNotACrash) {
  ::testing::internal::CaptureStderr();
  const int rc = run_cli({"simulate", "/nonexistent/preset.json", "--out", "/tmp/x.csv"});
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(rc, 2);
  EXPECT_NE(err.find("/nonexistent/preset.json"), std::string::npos) << err;
}

// A preset that loads but cannot be simulated (a step too large for the stiffest mode: the check
// runs when the simulation is built) still names the file it came from, and the limit.
TEST(CliSimulate, StepTooLargeNamesThePresetFileAndTheLimit) {
  std::string text = read_file(test_util::preset_path("fig4_stick_slip.json"));
  const std::string from = "\"dt\": 1e-5";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "\"dt\": 0.01");
  const std::string preset =
      (std::filesystem::temp_directory_path() / ("gmslab_dt_" + std::to_string(::getpid()) + ".json"))
          .string();
  write_file_atomic(preset, text);
  ::testing::internal::CaptureStderr();
  const int rc = run_cli({"simulate", preset, "--out", "-"});
  const std::string err = ::testing::internal::GetCapturedStderr();
  std::filesystem::remove(preset);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(err.find("gmslab: error: " + preset + ": invalid scenario"), std::string::npos) << err;
  EXPECT_NE(err.find("run.dt: 0.01 s is too large for the stiffest mode"), std::string::npos) << err;
}

TEST(CliSimulate, UnknownOptionIsRejected) {
  ::testing::internal::CaptureStderr();
  const int rc = run_cli({"simulate", "x.json", "--out", "y.csv", "--bogus"});
  ::testing::internal::GetCapturedStderr();
  EXPECT_NE(rc, 0);
}

}  // namespace
}  // namespace gmslab
