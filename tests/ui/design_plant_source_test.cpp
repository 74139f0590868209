// The Design tab's plant source (ui/design/design_panel.cpp) in the whole window: a typed plant's rejected
// edit keeps the value in force and says why, naming the field; a valid one is designed for; the
// assembled plant of the Plant tab is designed for, collocated or not, with its loops. Built only
// with the app (ImGui).
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "core/io/assembly_io.hpp"
#include "tests/ui/app_frame.hpp"

using namespace gmslab;
using Harness = uitest::DesignHarness;

TEST(DesignPlantSource, RejectedTypedEditKeepsTheValueInForceAndNamesTheField) {
  Harness h;
  DesignSettings ds = ui::design_settings(h.d());
  ds.plant.source = control::PlantSource::Typed;
  ds.plant.num = "4";
  ds.plant.den = "1 2 0";
  ds.zeta = 0.5;
  ds.wn = 4.0;
  ui::apply_design_settings(h.d(), ds);
  for (int i = 0; i < 2; ++i) h.frame(uitest::kNoMouse, false);
  ASSERT_EQ(h.d().out.source, control::PlantSource::Typed);
  EXPECT_TRUE(h.d().out.plain().trace.t.empty());
  EXPECT_FALSE(h.d().out.loop_note.empty());
  const double kc = h.d().out.compensator->Kc;
  std::mt19937 rng(5);
  for (int trial = 0; trial < 6; ++trial) {
    const std::vector<std::pair<bool, std::string>> bad = {
        {true, "0 1 2"}, {true, ""}, {false, "1 2 3 4"}, {false, "4 x"}, {true, "1 nan 0"}, {false, "0"}};
    const auto& [den, text] = bad[rng() % bad.size()];
    EXPECT_FALSE(ui::apply_coefficient_edit(h.d(), den, text));
    const std::string& err = den ? h.d().den_error : h.d().num_error;
    EXPECT_NE(err.find(den ? "den '" : "num '"), std::string::npos) << err;
    EXPECT_NE(err.find(den ? "in force: \"1 2 0\"" : "in force: \"4\""), std::string::npos) << err;
    h.frame(uitest::kNoMouse, false);
    // The value in force is unchanged and shown; the design is still the one for it.
    EXPECT_EQ(h.d().settings.plant.num, "4");
    EXPECT_EQ(h.d().settings.plant.den, "1 2 0");
    EXPECT_EQ(den ? h.d().den_edit : h.d().num_edit, den ? "1 2 0" : "4");
    EXPECT_DOUBLE_EQ(h.d().out.compensator->Kc, kc);
  }
  // A valid edit applies, clears the message, and the design follows: G = 4 / (s^2 + 4 s).
  EXPECT_TRUE(ui::apply_coefficient_edit(h.d(), true, "1, 4, 0"));
  EXPECT_TRUE(h.d().den_error.empty());
  h.frame(uitest::kNoMouse, false);
  EXPECT_EQ(h.d().settings.plant.den, "1, 4, 0");
  EXPECT_DOUBLE_EQ(h.d().out.plant.g.den.descending_coeffs()[1], 4.0);
  EXPECT_NE(h.d().out.compensator->Kc, kc);
}

TEST(DesignPlantSource, AssembledPlantOfThePlantTabIsDesignedFor) {
  const std::string path = std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path;
  Harness h;
  DesignSettings ds = ui::design_settings(h.d());
  ds.plant.source = control::PlantSource::Assembly;
  ds.wn = 10.0;
  ui::apply_design_settings(h.d(), ds);
  h.frame(uitest::kNoMouse, false);
  EXPECT_NE(h.d().out.error.find("no assembled plant"), std::string::npos);  // said, not blank
  ui::load_plant(h.s.plant, load_assembly_scenario(path), path);
  for (int i = 0; i < 2; ++i) h.frame(uitest::kNoMouse, false);
  ASSERT_TRUE(h.d().out.error.empty()) << h.d().out.error;
  EXPECT_EQ(h.d().out.port.output, "x.motor");
  EXPECT_EQ(h.d().out.plant.g.zeros().size(), 2u);  // the collocated pair
  EXPECT_FALSE(h.d().out.compensated().trace.t.empty());
  ds.plant.output = "x.load";
  ui::apply_design_settings(h.d(), ds);
  for (int i = 0; i < 2; ++i) h.frame(uitest::kNoMouse, false);
  EXPECT_EQ(h.d().out.port.output, "x.load");
  EXPECT_EQ(h.d().out.plant.g.zeros().size(), 1u);  // the shaft damper's real zero only
  EXPECT_FALSE(h.d().out.plain().trace.t.empty());
}

// Issue 11: the Design tab on an assembled plant with a pull drive (presets/fig3_stick_slip_scheme.json)
// designs with the pull point's position as u, so its gain units are m/m (Kc's label and tooltip
// take them from loop_units of the design's port); its v output keeps a zero at s = 0 and the view
// says so; a force drive's v.BODY outputs (the combo's) are designed for, the free train's pole at
// 0 cancelled by v = s x (N s/m).
TEST(DesignPlantSource, PullDriveGainIsInMetresPerMetreAndVelocityOutputIsDesignedFor) {
  const std::string path = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig3_stick_slip_scheme.json";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path;
  Harness h;
  const AssemblyScenario sc = load_assembly_scenario(path);
  ui::load_plant(h.s.plant, sc, path);
  DesignSettings ds = ui::design_settings(h.d());
  ds.plant.source = control::PlantSource::Assembly;
  ds.wn = 5.0;
  ui::apply_design_settings(h.d(), ds);
  for (int i = 0; i < 2; ++i) h.frame(uitest::kNoMouse, false);
  ASSERT_TRUE(h.d().out.error.empty()) << h.d().out.error;
  EXPECT_TRUE(h.d().out.port.pull);
  EXPECT_EQ(control::loop_units(h.d().out.source, h.d().out.port).gain, "m/m");
  // Its velocity output has a zero at s = 0 (the pull spring holds the block): the design says so
  // in the view instead of designing.
  ds.plant.output = "v." + sc.plant.bodies[0].name;
  ui::apply_design_settings(h.d(), ds);
  for (int i = 0; i < 2; ++i) h.frame(uitest::kNoMouse, false);
  EXPECT_NE(h.d().out.error.find("zero at s = 0"), std::string::npos) << h.d().out.error;
  // A force drive's velocity output (two-mass train, v of each body, as offered by the combo).
  const std::string two = std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json";
  const AssemblyScenario tm = load_assembly_scenario(two);
  ui::load_plant(h.s.plant, tm, two);
  int designed = 0;
  for (const std::string& y : control::assembly_outputs(tm.plant)) {
    if (y[0] != 'v') continue;
    SCOPED_TRACE(y);
    ds.plant.drive = "";
    ds.plant.output = y;
    ui::apply_design_settings(h.d(), ds);
    for (int i = 0; i < 2; ++i) h.frame(uitest::kNoMouse, false);
    ASSERT_TRUE(h.d().out.error.empty()) << h.d().out.error;
    EXPECT_EQ(h.d().out.port.output, y);
    EXPECT_TRUE(h.d().out.port.velocity);
    EXPECT_FALSE(h.d().out.port.pull);
    EXPECT_EQ(control::loop_units(h.d().out.source, h.d().out.port).gain, "N s/m");
    // v = s x cancels the free train's pole at 0: a type-0 plant (position output: type 1).
    ASSERT_TRUE(h.d().out.report.has_value());
    EXPECT_EQ(h.d().out.report->type.n, 0);
    ++designed;
  }
  EXPECT_EQ(designed, 2);
}
#endif
