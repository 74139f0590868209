// The Plant view: the schematic's layout is structurally sound for every shipped preset and for
// random assemblies (fixed seeds), and `gmslab render PRESET --view plant` draws the schematic
// with stick and slip colours that follow the run.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>

#include "core/friction/gms.hpp"
#include "core/io/assembly_io.hpp"
#include "ui/plant/plant_view.hpp"

namespace gmslab::ui {
namespace {

namespace fs = std::filesystem;

bool overlap(const Box& a, const Box& b) { return a.x0 < b.x1 - 0.5f && b.x0 < a.x1 - 0.5f && a.y0 < b.y1 - 0.5f && b.y0 < a.y1 - 0.5f; }

void expect_sound(const Assembly& a, float W, float H) {
  const PlantLayout l = layout_plant(a, W, H);
  ASSERT_EQ(l.bodies.size(), a.bodies.size());
  ASSERT_EQ(l.springs.size(), a.springs.size());
  ASSERT_EQ(l.dampers.size(), a.dampers.size());
  ASSERT_EQ(l.contacts.size(), a.contacts.size());
  ASSERT_EQ(l.drives.size(), a.drives.size());
  for (std::size_t i = 0; i < l.bodies.size(); ++i) {
    const Box& b = l.bodies[i];
    EXPECT_GT(b.x1 - b.x0, 10.0f) << "body " << i;
    EXPECT_GT(b.y1 - b.y0, 10.0f) << "body " << i;
    EXPECT_GE(b.x0, 0.0f);
    EXPECT_LE(b.x1, W);
    EXPECT_GE(b.y0, 0.0f);
    EXPECT_LE(b.y1, l.floor_y) << "body " << i << " stands on or above the floor";
    for (std::size_t j = 0; j < i; ++j) EXPECT_FALSE(overlap(b, l.bodies[j])) << "bodies " << i << " and " << j;
  }
  for (std::size_t j = 0; j < a.contacts.size(); ++j) {
    const auto& c = a.contacts[j];
    const Box& p = l.contacts[j];
    const Box& A = l.bodies[c.a];
    EXPECT_FLOAT_EQ(p.y0, A.y1) << "contact " << j << " pad starts at its body's bottom";
    EXPECT_GT(p.y1, p.y0);
    if (c.b == kGround) {
      EXPECT_FLOAT_EQ(p.y1, l.floor_y);
    }
    EXPECT_GE(p.x0, A.x0);
    EXPECT_LE(p.x1, A.x1);
  }
  auto on_face = [&](int body, float x) {
    const Box& b = l.bodies[body];
    return std::abs(x - b.x0) < 0.01f || std::abs(x - b.x1) < 0.01f || std::abs(x - b.cx()) < 0.01f;
  };
  for (std::size_t i = 0; i < a.springs.size(); ++i) {
    EXPECT_TRUE(on_face(a.springs[i].a, l.springs[i].ax)) << "spring " << i;
    if (a.springs[i].b != kGround) EXPECT_TRUE(on_face(a.springs[i].b, l.springs[i].bx)) << "spring " << i;
    else EXPECT_LE(l.springs[i].bx, l.bodies[a.springs[i].a].x0) << "ground ends lie left of the body";
  }
}

TEST(PlantLayout, EveryPresetIsLaidOutSoundly) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    SCOPED_TRACE(e.path().string());
    const auto s = load_assembly_scenario(e.path().string());
    for (auto [w, h] : {std::pair{1200.0f, 420.0f}, std::pair{700.0f, 300.0f}}) expect_sound(s.plant, w, h);
    ++n;
  }
  EXPECT_GE(n, 14);
}

TEST(PlantLayout, RandomAssembliesAreLaidOutSoundly) {
  std::mt19937 rng(1111);
  const ModelParams gms = GmsParams::reference(true).to_params();
  for (int trial = 0; trial < 200; ++trial) {
    Assembly a;
    const int nb = 1 + static_cast<int>(rng() % kMaxBodies);
    for (int i = 0; i < nb; ++i) a.bodies.push_back({"b" + std::to_string(i), 1.0});
    auto other = [&](int i) {
      int j = static_cast<int>(rng() % (nb + 1)) - 1;
      return j == i ? kGround : j;
    };
    for (int i = 0; i < nb; ++i) {
      a.springs.push_back({"k" + std::to_string(i), i, other(i), 10.0});
      if (rng() % 2) a.dampers.push_back({"c" + std::to_string(i), i, other(i), 1.0});
      if (rng() % 2) a.contacts.push_back({"f" + std::to_string(i), i, other(i), gms});
    }
    a.drives.push_back({"d", DrivePart::Kind::Force, static_cast<int>(rng() % nb), Signal::constant(1.0)});
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_sound(a, 1200.0f, 420.0f);
  }
}

TEST(PlantEdit, HitTestFindsEachPartWhereItIsDrawn) {
  for (const char* name : {"two_mass_drive.json", "slider_on_table.json", "three_body_chain.json"}) {
    SCOPED_TRACE(name);
    const auto s = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name);
    const Assembly& a = s.plant;
    const PlantLayout l = layout_plant(a, 1200.0f, 420.0f);
    PlantPose pose = rest_pose(a);
    std::mt19937 rng(7);
    for (auto& x : pose.x) x = std::uniform_real_distribution<double>(-0.01, 0.01)(rng);  // moved bodies
    const double mag = 2000.0;  // px per m
    auto off = [&](int b) { return static_cast<float>(pose.x[b] * mag); };
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
      const Box& b = l.bodies[i];
      EXPECT_EQ(hit_test(l, a, pose, mag, b.x0 + off(i) + 3.0f, b.y0 + 3.0f), (PartRef{PartRef::Kind::Body, static_cast<int>(i)}));
    }
    for (std::size_t j = 0; j < a.contacts.size(); ++j) {
      const Box& p = l.contacts[j];
      EXPECT_EQ(hit_test(l, a, pose, mag, p.cx() + off(a.contacts[j].a), p.cy()), (PartRef{PartRef::Kind::Contact, static_cast<int>(j)}));
    }
    for (std::size_t i = 0; i < a.springs.size(); ++i) {
      const auto& k = l.springs[i];
      const float ax = k.ax + off(a.springs[i].a), bx = k.bx + (a.springs[i].b >= 0 ? off(a.springs[i].b) : 0.0f);
      EXPECT_EQ(hit_test(l, a, pose, mag, 0.5f * (ax + bx), 0.5f * (k.ay + k.by) - k.lift),
                (PartRef{PartRef::Kind::Spring, static_cast<int>(i)}));
    }
    EXPECT_EQ(hit_test(l, a, pose, mag, 2.0f, 2.0f), PartRef{});  // empty corner
  }
}

TEST(PlantEdit, RemovingABodyRemovesItsPartsAndRenumbers) {
  const auto s = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/three_body_chain.json");
  const Assembly a = remove_part(s.plant, {PartRef::Kind::Body, 1});  // the middle body
  ASSERT_EQ(a.bodies.size(), 2u);
  EXPECT_EQ(a.bodies[1].name, "b3");
  EXPECT_TRUE(a.springs.empty()) << "both chain springs touched b2";
  EXPECT_TRUE(a.dampers.empty());
  ASSERT_EQ(a.contacts.size(), 2u);
  EXPECT_EQ(a.contacts[1].a, 1) << "b3's contact now names index 1";
  EXPECT_TRUE(validate(a).empty());  // both bodies still have a contact to ground
  // Removing a drive or a part by index drops exactly it.
  EXPECT_EQ(remove_part(s.plant, {PartRef::Kind::Spring, 0}).springs.size(), 1u);
  EXPECT_EQ(remove_part(s.plant, {PartRef::Kind::Spring, 0}).springs[0].name, "k23");
}

TEST(PlantEdit, EditsApplyOnlyWhenValidAndUndoRedoRestore) {
  PlantPanelState st;
  const auto s = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json");
  load_plant(st, s, "two_mass_drive.json");
  AssemblyScenario ed = *st.scenario;
  const PartRef body = add_part(ed.plant, PartRef::Kind::Body, 1);
  EXPECT_EQ(ed.plant.bodies[body.index].name, "body1");
  ASSERT_TRUE(apply_plant_edit(st, ed));
  EXPECT_EQ(st.scenario->plant.bodies.size(), 3u);
  // A negative mass is not applied; the message names the key.
  AssemblyScenario bad = *st.scenario;
  bad.plant.bodies[0].mass = -1.0;
  EXPECT_FALSE(apply_plant_edit(st, bad));
  EXPECT_NE(st.edit_msg.find("plant.bodies[0].mass"), std::string::npos) << st.edit_msg;
  EXPECT_EQ(st.scenario->plant.bodies[0].mass, 0.5);
  // Removing the load's spring leaves the new body floating: rejected.
  AssemblyScenario floating = *st.scenario;
  floating.plant = remove_part(floating.plant, {PartRef::Kind::Spring, 1});
  EXPECT_FALSE(apply_plant_edit(st, floating));
  plant_undo(st);
  EXPECT_EQ(*st.scenario, s);
  plant_redo(st);
  EXPECT_EQ(st.scenario->plant.bodies.size(), 3u);
  EXPECT_NO_THROW(plant_run_until(st, 0.1));
}

int run(const std::string& cmd) {
  const int rc = std::system((cmd + " 2>/dev/null").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

struct Counts {
  int stick = 0, slip = 0, body = 0;
};

Counts count(const std::string& png) {
  int w = 0, h = 0, n = 0;
  unsigned char* d = stbi_load(png.c_str(), &w, &h, &n, 4);
  Counts c;
  if (!d) return c;
  // The schematic is the upper half of the right part of the window.
  for (int y = 0; y < h / 2; ++y)
    for (int x = w / 4; x < w; ++x) {
      const unsigned char* p = d + (static_cast<std::size_t>(y) * w + x) * 4;
      auto near = [&](int r, int g, int b) { return std::abs(p[0] - r) < 12 && std::abs(p[1] - g) < 12 && std::abs(p[2] - b) < 12; };
      c.stick += near(0, 114, 178);
      c.slip += near(230, 120, 0);
      c.body += near(205, 215, 228);
    }
  stbi_image_free(d);
  return c;
}

TEST(PlantRender, TwoMassTrainDrawsBodiesAndContactsColouredByTheRun) {
  const fs::path dir = fs::temp_directory_path() / ("gmslab_plant_render_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string preset = std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json";
  const std::string cmd = std::string(GMSLAB_HEADLESS_EXE) + " render " + preset + " --view plant --size 1000x700 ";
  // At rest both contacts stick; at t = 0.8 s (the force near its peak) both slip.
  ASSERT_EQ(run(cmd + "--time 0 --out " + (dir / "rest.png").string()), 0);
  ASSERT_EQ(run(cmd + "--time 0.8 --out " + (dir / "slip.png").string()), 0);
  const Counts rest = count((dir / "rest.png").string()), slip = count((dir / "slip.png").string());
  std::cout << "rest: stick " << rest.stick << " slip " << rest.slip << " body " << rest.body << "; t = 0.8 s: stick "
            << slip.stick << " slip " << slip.slip << " body " << slip.body << "\n";
  EXPECT_GT(rest.body, 2 * 60 * 40) << "two blocks drawn";
  // The legend has one swatch of each colour (the same pixels in both images); the pads add theirs.
  EXPECT_GT(rest.stick, slip.stick + 150) << "pads blue while stuck";
  EXPECT_GT(slip.slip, rest.slip + 150) << "pads orange while slipping";
  EXPECT_EQ(rest.slip, slip.stick) << "at rest only the legend is orange, while slipping only the legend is blue";
  EXPECT_GT(slip.body, 2 * 60 * 40);
  // A version-1 preset draws too (as one body); an unknown file fails with exit code 2.
  EXPECT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + std::string(GMSLAB_SOURCE_DIR) +
                "/presets/fig2a_presliding.json --view plant --size 800x500 --out " + (dir / "v1.png").string()),
            0);
  EXPECT_GT(count((dir / "v1.png").string()).body, 60 * 40);
  {
    std::ofstream bad(dir / "bad.json");
    bad << R"({"schema_version": 2, "name": "bad", "plant": {"bodies": [{"name": "m", "mass": 1}],
      "springs": [{"name": "k", "a": "m", "b": "m", "stiffness": 1}]}, "run": {"dt": 1e-4, "duration": 1}})";
  }
  EXPECT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + (dir / "bad.json").string() +
                " --view plant --out " + (dir / "bad.png").string()),
            2);
  EXPECT_FALSE(fs::exists(dir / "bad.png"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gmslab::ui
