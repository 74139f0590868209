// A shipped preset by its bare name (core/io/preset_io.hpp: presets_dir, resolve_preset), as every
// front end takes it: the CLI's simulate, design and render (render: tests/app), the window's
// --open (tests/app/exit_codes_test.cpp) and Python's load_scenario
// (tests/python/test_pythonic.py). From a folder outside the source tree the name gives the same
// file, and the same output as the full path; a name that is no preset is an error that names the
// closest preset and lists them all.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/preset_io.hpp"
#include "core/text/closest_word.hpp"
#include "tests/core/run_cli.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;
using test_util::run_cli;

std::vector<std::string> shipped_names() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(presets_dir()))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Runs the test body in a fresh folder outside the source tree (restores the working folder).
class PresetLookup : public ::testing::Test {
 protected:
  void SetUp() override {
    home_ = fs::current_path();
    dir_ = fs::temp_directory_path() / ("gmslab_lookup_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    fs::current_path(dir_);
  }
  void TearDown() override {
    fs::current_path(home_);
    fs::remove_all(dir_);
  }
  fs::path home_, dir_;
};

TEST_F(PresetLookup, EveryShippedPresetResolvesByItsBareNameWithOrWithoutJson) {
  const std::string dir = presets_dir();
  const auto names = shipped_names();
  ASSERT_GE(names.size(), 10u);
  for (const auto& n : names) {
    const std::string file = (fs::path(dir) / (n + ".json")).string();
    EXPECT_EQ(resolve_preset(n, dir), file);
    EXPECT_EQ(resolve_preset(n + ".json", dir), file);
    EXPECT_EQ(resolve_preset("presets/" + n + ".json", dir), file);  // as the README writes it
    EXPECT_EQ(load_preset(resolve_preset(n, dir)).scenario, load_preset(file).scenario);
  }
}

TEST_F(PresetLookup, AFileInTheWorkingFolderComesFirst) {
  const std::string dir = presets_dir();
  write_file_atomic("fig4_stick_slip.json", read_file(dir + "/fig2a_presliding.json"));
  EXPECT_EQ(resolve_preset("fig4_stick_slip.json", dir), "fig4_stick_slip.json");
  EXPECT_EQ(resolve_preset("fig4_stick_slip", dir),
            dir + "/fig4_stick_slip.json");  // no such file here
}

TEST_F(PresetLookup, CliSimulateByNameWritesWhatTheFullPathWrites) {
  const std::string file = presets_dir() + "/fig2a_presliding.json";
  ASSERT_EQ(run_cli({"simulate", "fig2a_presliding", "--out", "by_name.csv"}), 0);
  ASSERT_EQ(run_cli({"simulate", file, "--out", "by_path.csv"}), 0);
  const std::string a = read_file("by_name.csv"), b = read_file("by_path.csv");
  EXPECT_GT(a.size(), 10000u);
  EXPECT_EQ(a, b);
}

TEST_F(PresetLookup, CliDesignByNameGivesTheFullPathsReport) {
  const std::string file = presets_dir() + "/fig4_stick_slip.json";
  ASSERT_EQ(run_cli({"design", "--preset", "fig4_stick_slip", "--zeta", "0.7", "--wn", "60",
                     "--json", "n.json"}),
            0);
  ASSERT_EQ(
      run_cli({"design", "--preset", file, "--zeta", "0.7", "--wn", "60", "--json", "p.json"}), 0);
  const std::string a = read_file("n.json");
  EXPECT_NE(a.find("closed_loop_poles"), std::string::npos);
  EXPECT_EQ(a, read_file("p.json"));
}

// Random one-letter typos (deleted, replaced or doubled) of random presets: the error says "no such
// file", names the closest preset (the one typed at, or one as close) and lists every preset.
TEST_F(PresetLookup, AnUnknownNameNamesTheClosestPresetAndListsThemAll) {
  const std::string dir = presets_dir();
  const auto names = shipped_names();
  std::mt19937 rng(2511);
  int cases = 0;
  for (int i = 0; i < 60; ++i) {
    const std::string& want = names[rng() % names.size()];
    std::string typo = want;
    const std::size_t at = rng() % typo.size();
    switch (rng() % 3) {
      case 0:
        typo.erase(at, 1);
        break;
      case 1:
        typo[at] = typo[at] == 'q' ? 'z' : 'q';
        break;
      default:
        typo.insert(at, 1, typo[at]);
        break;
    }
    if (std::find(names.begin(), names.end(), typo) != names.end()) continue;
    SCOPED_TRACE(typo);
    try {
      (void)resolve_preset(typo, dir);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("'" + typo + "': no such file, and no preset '" + typo + "' in " + dir, 0),
                0u)
          << m;
      const auto said = m.find("did you mean '");
      ASSERT_NE(said, std::string::npos) << m;
      const std::string near = m.substr(said + 14, m.find('\'', said + 14) - said - 14);
      EXPECT_LE(edit_distance(typo, near), edit_distance(typo, want)) << m;
      for (const auto& n : names)
        EXPECT_NE(m.find(n), std::string::npos) << n << " not listed: " << m;
      ++cases;
    }
  }
  EXPECT_GE(cases, 55);
}

TEST_F(PresetLookup, TheCliSaysWhichPresetsThereAreAndExits2) {
  ::testing::internal::CaptureStderr();
  const int rc = run_cli({"simulate", "fig4_stick_slp", "--out", "x.csv"});
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(rc, 2);
  EXPECT_NE(err.find("'fig4_stick_slp': no such file, and no preset 'fig4_stick_slp' in "),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("did you mean 'fig4_stick_slip'?"), std::string::npos) << err;
  EXPECT_NE(err.find("two_mass_drive"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists("x.csv"));
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(run_cli({"design", "--preset", "nothing_like_it", "--zeta", "0.7", "--wn", "60"}), 2);
  const std::string derr = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(derr.find("--preset 'nothing_like_it': no such file, and no preset"), std::string::npos)
      << derr;
  EXPECT_EQ(derr.find("did you mean"), std::string::npos) << derr;  // nothing close
}

TEST_F(PresetLookup, APathInAnotherFolderIsNeverLookedUpAmongThePresets) {
  // As given: the loader names it ("cannot open file"), not the list of presets.
  EXPECT_EQ(resolve_preset("elsewhere/fig4_stick_slip.json", presets_dir(), "--open"),
            "elsewhere/fig4_stick_slip.json");
  try {
    (void)load_preset(resolve_preset("elsewhere/fig4_stick_slip.json", presets_dir()));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("elsewhere/fig4_stick_slip.json: ", 0), 0u) << m;
    EXPECT_EQ(m.find("presets:"), std::string::npos) << m;
  }
  EXPECT_THROW((void)resolve_preset("", presets_dir()), InputError);
}

TEST(PresetsDir, TheEnvironmentComesFirst) {
  const char* old = std::getenv("GMSLAB_PRESETS");
  const std::string keep = old ? old : "";
  ::setenv("GMSLAB_PRESETS", "/some/where", 1);
  EXPECT_EQ(presets_dir(), "/some/where");
  ::setenv("GMSLAB_PRESETS", "", 1);  // empty: as unset
  EXPECT_EQ(presets_dir(), std::string(GMSLAB_SOURCE_DIR) + "/presets");
  if (old)
    ::setenv("GMSLAB_PRESETS", keep.c_str(), 1);
  else
    ::unsetenv("GMSLAB_PRESETS");
}

}  // namespace
}  // namespace gmslab
