// Window sessions: round trip through JSON and strict rejection of malformed files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <random>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
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
  s.design.compensator = control::CompensatorType::PID;
  s.design.feedforward_source = control::FeedforwardSource::Measured;
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
  j["schema_version"] = 5;
  EXPECT_NE(expect_rejected(j).find("version 5 is not supported; this gmslab reads version 1 to 4"),
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
  j["design"]["compensator"] = "pd";
  EXPECT_NE(expect_rejected(j).find("design.compensator"), std::string::npos);
  j = good;  // sessions saved before the compensator types: the lead
  j["design"].erase("compensator");
  EXPECT_EQ(session_from_json(j, "s.json").design.compensator, control::CompensatorType::Lead);
  j = good;
  j["design"]["feedforward_source"] = "velocity";
  EXPECT_NE(expect_rejected(j).find("design.feedforward_source"), std::string::npos);
  j = good;
  j["design"]["feedforward_source"] = 1;
  EXPECT_NE(expect_rejected(j).find("design.feedforward_source"), std::string::npos);
  j = good;  // sessions saved before the measured-velocity feedforward: the reference
  j["design"].erase("feedforward_source");
  EXPECT_EQ(session_from_json(j, "s.json").design.feedforward_source, control::FeedforwardSource::Reference);
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
  j.erase("plant");
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
  j.erase("plant");
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

// ---- The Plant tab's assembled plant (schema 4) ----
namespace {
// A random valid assembly: 1-8 bodies of random mass, each tied to an earlier body or ground by a
// spring, random dampers and contacts (random registry model with its defaults, scaled), and a
// force, displacement, velocity or pull drive with a random signal; run.dt under the step limit.
AssemblyScenario random_assembly(std::mt19937& rng) {
  auto U = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  AssemblyScenario s;
  s.name = "random " + std::to_string(rng() % 1000);
  s.description = rng() % 2 ? "" : "a plant with \"quotes\" and unicode µm";
  Assembly& a = s.plant;
  const int nb = 1 + static_cast<int>(rng() % kMaxBodies);
  for (int i = 0; i < nb; ++i) a.bodies.push_back({"b" + std::to_string(i), std::exp(U(std::log(1e-3), std::log(1e3)))});
  const auto& reg = model_registry();
  for (int i = 0; i < nb; ++i) {
    const int other = i == 0 ? kGround : static_cast<int>(rng() % (i + 1)) - 1;
    a.springs.push_back({"k" + std::to_string(i), i, other, std::exp(U(0.0, std::log(1e5)))});
    if (rng() % 2) a.dampers.push_back({"c" + std::to_string(i), i, static_cast<int>(rng() % (i + 1)) - 1, U(0, 10)});
    if (rng() % 2) {
      ModelParams p = reg[rng() % reg.size()].defaults();
      a.contacts.push_back({"f" + std::to_string(i), i, i > 0 && rng() % 2 ? static_cast<int>(rng() % i) : kGround, p});
    }
  }
  DrivePart d;
  d.name = "drive";
  d.kind = static_cast<DrivePart::Kind>(rng() % 4);
  d.body = static_cast<int>(rng() % nb);
  switch (rng() % 3) {
    case 0: d.signal = Signal::constant(U(-2, 2)); break;
    case 1: d.signal = Signal::ramp(U(-1, 1), U(-0.5, 0.5)); break;
    default: d.signal = Signal::sine(U(-1, 1), U(0, 1), U(0.1, 10), U(0, 3)); break;
  }
  if (d.kind == DrivePart::Kind::Pull) d.pull_spring = U(0.5, 1e3), d.pull_damper = U(0, 5), d.point_velocity = rng() % 2;
  a.drives.push_back(d);
  s.run.duration = U(0.01, 5);
  s.run.record_every = 1 + static_cast<int>(rng() % 20);
  s.run.dt = std::min(1e-4, 0.5 * stability_limit_dt(a));
  return s;
}
}  // namespace

// Random assemblies (fixed seed) saved with the session and loaded back give the same plant, path,
// speed and magnification, through the file (atomic write) and through JSON.
TEST(SessionIo, ThePlantTabsAssemblyRoundTripsForRandomAssemblies) {
  std::mt19937 rng(1511);
  const std::string path = (std::filesystem::temp_directory_path() / ("gmslab_plant_session_" + std::to_string(getpid()) + ".json")).string();
  for (int trial = 0; trial < 40; ++trial) {
    Session s = sample();
    s.plant = PlantTabSettings{};
    s.plant->scenario = random_assembly(rng);
    ASSERT_TRUE(validate(s.plant->scenario.plant).empty()) << "trial " << trial << ": " << validate(s.plant->scenario.plant)[0];
    s.plant->path = "presets/plant " + std::to_string(trial) + ".json";
    s.plant->speed = std::exp(std::uniform_real_distribution<double>(std::log(1e-3), std::log(1e3))(rng));
    s.plant->magnification = trial % 3 == 0 ? 0.0 : std::uniform_real_distribution<double>(0.1, 1000)(rng);
    const Assembly& a = s.plant->scenario.plant;
    for (const auto& c : output_channels(a))
      if (rng() % 2) s.plant->plotted.push_back(c.name);
    s.plant->tf_drive = a.drives[rng() % a.drives.size()].name;
    s.plant->tf_output = a.bodies[rng() % a.bodies.size()].name;
    s.plant->tf_sliding = rng() % 2;
    save_session(s, path);
    const Session back = load_session(path);
    ASSERT_TRUE(back.plant.has_value());
    EXPECT_EQ(back.plant->scenario, s.plant->scenario) << "trial " << trial;
    EXPECT_EQ(back, s) << "trial " << trial;
    EXPECT_EQ(to_json(back), to_json(s));
  }
  Session none = sample();
  save_session(none, path);
  EXPECT_FALSE(load_session(path).plant.has_value());
  std::filesystem::remove(path);
}

// Version-3 files (no "plant") load with an empty Plant tab; a version-3 file with "plant" is
// malformed; a version-4 file without it too. Errors inside the plant name the key path.
TEST(SessionIo, PlantKeyIsVersionedAndStrict) {
  Session s = sample();
  s.plant = PlantTabSettings{"presets/two_mass_drive.json",
                             load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json"), 2.0, 0.0,
                             {"x.motor", "F.shaft"}, "motor_force", "load", false};
  nlohmann::json j = to_json(s);
  ASSERT_EQ(j["schema_version"], 4);
  {
    nlohmann::json v3 = j;
    v3["schema_version"] = 3;
    EXPECT_NE(expect_rejected(v3).find("plant"), std::string::npos);
    v3.erase("plant");
    const Session old = session_from_json(v3, "v3.json");
    EXPECT_FALSE(old.plant.has_value());
    EXPECT_EQ(old.identify, s.identify);
  }
  {
    nlohmann::json bad = j;
    bad.erase("plant");
    EXPECT_NE(expect_rejected(bad).find("plant"), std::string::npos);
  }
  auto reject_with = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& needle) {
    nlohmann::json bad = j;
    edit(bad);
    const std::string msg = expect_rejected(bad);
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  };
  reject_with([](nlohmann::json& b) { b["plant"]["speed"] = 0.0; }, "plant.speed");
  reject_with([](nlohmann::json& b) { b["plant"]["magnification"] = -1.0; }, "plant.magnification");
  reject_with([](nlohmann::json& b) { b["plant"]["colour"] = "red"; }, "colour");
  reject_with([](nlohmann::json& b) { b["plant"]["plotted"][1] = "x.lod"; }, "plant.plotted[1]");
  reject_with([](nlohmann::json& b) { b["plant"]["plotted"][1] = "x.motor"; }, "listed twice");
  reject_with([](nlohmann::json& b) { b["plant"]["plotted"] = "x.motor"; }, "plant.plotted");
  reject_with([](nlohmann::json& b) { b["plant"]["linear_plant"]["drive"] = "pull"; }, "plant.linear_plant.drive");
  reject_with([](nlohmann::json& b) { b["plant"]["linear_plant"]["output"] = "ground"; }, "plant.linear_plant.output");
  reject_with([](nlohmann::json& b) { b["plant"]["linear_plant"].erase("sliding"); }, "plant.linear_plant.sliding");
  {
    const Session back = session_from_json(j, "s.json");
    EXPECT_EQ(back, s);
  }
  reject_with([](nlohmann::json& b) { b["plant"] = 3; }, "plant");
  reject_with([](nlohmann::json& b) { b["plant"]["scenario"]["plant"]["springs"][0]["b"] = "lod"; }, "in 'plant.scenario'");
  reject_with([](nlohmann::json& b) { b["plant"]["scenario"]["plant"]["springs"][0]["b"] = "lod"; }, "plant.springs[0].b");
  reject_with([](nlohmann::json& b) { b["plant"]["scenario"]["plant"]["bodies"][0]["mass"] = -1.0; }, "plant.bodies[0].mass");
  reject_with([](nlohmann::json& b) { b["plant"]["scenario"] = to_json(sample().scenario); }, "plant.scenario");
}
