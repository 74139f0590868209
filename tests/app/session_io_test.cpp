// Window sessions: round trip through JSON and strict rejection of malformed files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "core/error.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/session_io.hpp"

using namespace gmslab;

namespace {
Session sample() {
  Session s;
  s.scenario_path = "presets/fig4_stick_slip.json";
  s.scenario = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  s.compare = model_registry().front().defaults();
  s.compare->scalars[0] *= 1.25;
  s.view.speed = 0.125;
  s.view.color_phases = false;
  s.view.slip_velocity = 3e-4;
  s.view.tab = "Figures";
  s.view.friction_against = "velocity";
  s.design.regime = "presliding";
  s.design.zeta = 0.45;
  s.design.wn = 250.0;
  s.design.use_K = true;
  s.design.K = 3.5e4;
  s.design.reference = DesignReference::Ramp;
  s.design.compensation = "coulomb";
  s.design.mismatch_stiffness = 0.5;
  s.design.sample_time = 1e-3;
  s.design.zero_degree = true;
  s.identify.data = "/data/run 1/train.csv";
  s.identify.validate = "val.csv";
  s.identify.columns = "t=time_s,x=x_mm,F=F_N";
  s.identify.mask = "1:2,7:7.5";
  s.identify.mask_edges = "";
  s.identify.model = "lugre";
  s.identify.elements = 7;
  s.identify.compare = true;
  return s;
}

std::string expect_rejected(nlohmann::json j) {
  try {
    session_from_json(j, "s.json");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << j.dump();
  return "";
}
}  // namespace

TEST(SessionIo, SaveThenLoadGivesTheSameSession) {
  const Session s = sample();
  const std::string path =
      (std::filesystem::temp_directory_path() / ("gmslab_session_" + std::to_string(getpid()) + ".json")).string();
  save_session(s, path);
  const Session back = load_session(path);
  EXPECT_EQ(back, s);
  std::filesystem::remove(path);
  Session none = s;
  none.compare.reset();
  EXPECT_EQ(session_from_json(to_json(none), "x"), none);
}

TEST(SessionIo, MalformedSessionsAreRejectedNamingTheKey) {
  const nlohmann::json good = to_json(sample());
  auto j = good;
  j["view"]["speed"] = 1e9;
  EXPECT_NE(expect_rejected(j).find("view.speed"), std::string::npos);
  j = good;
  j["view"]["zoom"] = 2;
  EXPECT_NE(expect_rejected(j).find("zoom"), std::string::npos);
  j = good;
  j["view"].erase("tab");
  EXPECT_NE(expect_rejected(j).find("view.tab"), std::string::npos);
  j = good;
  j["schema_version"] = 4;
  EXPECT_NE(expect_rejected(j).find("version 4 is not supported; this gmslab reads version 1 to 3"),
            std::string::npos);
  j = good;
  j["identify"]["model"] = "no_such_model";
  EXPECT_NE(expect_rejected(j).find("identify.model"), std::string::npos);
  j = good;
  j["identify"]["elements"] = 65;
  EXPECT_NE(expect_rejected(j).find("identify.elements"), std::string::npos);
  j = good;
  j["identify"]["data"] = std::string(5000, 'a');
  EXPECT_NE(expect_rejected(j).find("identify.data"), std::string::npos);
  j = good;
  j["identify"].erase("mask_edges");
  EXPECT_NE(expect_rejected(j).find("identify.mask_edges"), std::string::npos);
  j = good;
  j.erase("identify");  // required in version 3
  EXPECT_NE(expect_rejected(j).find("identify"), std::string::npos);
  j = good;
  j["design"]["zeta"] = 1.0;
  EXPECT_NE(expect_rejected(j).find("design.zeta"), std::string::npos);
  j = good;
  j["design"]["compensation"] = "none";
  EXPECT_NE(expect_rejected(j).find("design.compensation"), std::string::npos);
  j = good;
  j["design"]["wn"] = 0;
  EXPECT_NE(expect_rejected(j).find("design.wn"), std::string::npos);
  j = good;
  j["design"].erase("max_ratio");
  EXPECT_NE(expect_rejected(j).find("design.max_ratio"), std::string::npos);
  j = good;
  j.erase("design");  // required from version 2 on
  EXPECT_NE(expect_rejected(j).find("design"), std::string::npos);
  j = good;
  j["compare"]["model"] = "no_such_model";
  EXPECT_NE(expect_rejected(j).find("compare.model"), std::string::npos);
  j = good;
  j["scenario"]["plant"]["mass"] = -1;
  const std::string m = expect_rejected(j);
  EXPECT_NE(m.find("(in 'scenario')"), std::string::npos) << m;
  EXPECT_NE(m.find("plant.mass"), std::string::npos) << m;
  j = good;
  j["view"]["friction_against"] = "time";
  EXPECT_NE(expect_rejected(j).find("view.friction_against"), std::string::npos);
  j = good;
  j["view"]["color_phases"] = "yes";
  EXPECT_NE(expect_rejected(j).find("view.color_phases"), std::string::npos);
  EXPECT_THROW(session_from_json(nlohmann::json::array(), "s.json"), InputError);
}

// A version-1 file (saved before the design settings existed) still loads, with the design view's
// defaults; a version-1 file that has a "design" key is malformed (unknown key).
TEST(SessionIo, VersionOneSessionsLoadWithDefaultDesignSettings) {
  nlohmann::json j = to_json(sample());
  j["schema_version"] = 1;
  j.erase("design");
  j.erase("identify");
  const Session s = session_from_json(j, "old.json");
  EXPECT_EQ(s.design, DesignSettings{});
  EXPECT_EQ(s.identify, IdentifySettings{});
  EXPECT_EQ(s.view, sample().view);
  EXPECT_EQ(s.scenario, sample().scenario);
  j["design"] = to_json(sample())["design"];
  EXPECT_NE(expect_rejected(j).find("design"), std::string::npos);
}

// A version-2 file (design settings, no identify settings) loads with the Identify tab's defaults;
// a version-2 file with an "identify" key is malformed.
TEST(SessionIo, VersionTwoSessionsLoadWithDefaultIdentifySettings) {
  nlohmann::json j = to_json(sample());
  j["schema_version"] = 2;
  j.erase("identify");
  const Session s = session_from_json(j, "v2.json");
  EXPECT_EQ(s.identify, IdentifySettings{});
  EXPECT_EQ(s.design, sample().design);
  j["identify"] = to_json(sample())["identify"];
  EXPECT_NE(expect_rejected(j).find("identify"), std::string::npos);
}

// The design reference is an enum saved by name; every name reads back, anything else is refused.
TEST(SessionIo, DesignReferenceIsAnEnumSavedByName) {
  for (auto r : {DesignReference::Step, DesignReference::Ramp, DesignReference::Sine}) {
    ASSERT_EQ(design_reference_from_string(to_string(r)), r);
    Session s = sample();
    s.design.reference = r;
    EXPECT_EQ(to_json(s)["design"]["reference"], to_string(r));
  }
  EXPECT_STREQ(to_string(DesignReference::Ramp), "ramp");
  EXPECT_FALSE(design_reference_from_string("Sine").has_value());
  EXPECT_FALSE(design_reference_from_string("square").has_value());
  auto j = to_json(sample());
  j["design"]["reference"] = "square";
  const std::string msg = expect_rejected(j);
  EXPECT_NE(msg.find("design.reference"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sine"), std::string::npos) << msg;
}
