// The Plant tab driven by scripted mouse input (an ImGui context without a renderer, as the
// design view's input tests): dragging from one body (or the ground) to another adds the chosen
// spring, damper or contact between exactly those ends with its default value; a drag released on
// nothing or on the body it started from changes nothing and leaves a hint; undo / redo step over
// the connection. Built only with the app (ImGui).
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <cstdio>
#include <random>
#include <string>

#include "core/io/assembly_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/session_io.hpp"
#include "tests/ui/app_frame.hpp"
#include "ui/app.hpp"
#include "ui/plant/plant_view.hpp"
#include "ui/plot/plot.hpp"

using namespace gmslab;
using ui::PartRef;

namespace {

struct PlantHarness {
  ui::AppState s;
  ui::ScopedPlotContext plots;
  explicit PlantHarness(const std::string& preset) {
    uitest::make_headless_imgui(ImVec2(1600, 1000));
    ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"), "");
    const std::string path = std::string(GMSLAB_SOURCE_DIR) + "/presets/" + preset;
    ui::load_plant(s.plant, load_assembly_scenario(path), path);
    s.view.tab = "Plant";
    for (int i = 0; i < 3; ++i) frame(uitest::kNoMouse, false);
  }
  ~PlantHarness() { ImGui::DestroyContext(); }
  PlantHarness(const PlantHarness&) = delete;
  PlantHarness& operator=(const PlantHarness&) = delete;
  void frame(ImVec2 mouse, bool down) { uitest::draw_app_frame(s, mouse, down); }
  ui::PlantPanelState& p() { return s.plant; }
  // Screen point of canvas point (x, y); a body's block centre as drawn now.
  ImVec2 at(float x, float y) { return ImVec2(p().canvas_x + x, p().canvas_y + y); }
  ImVec2 body(int i) {
    const auto& b = p().canvas_layout.bodies[static_cast<std::size_t>(i)];
    const double dx = p().canvas_pose.x[static_cast<std::size_t>(i)] * p().canvas_mag;
    return at(b.cx() + static_cast<float>(dx), b.cy());
  }
  ImVec2 ground() { return at(0.5f * p().canvas_layout.width, p().canvas_layout.floor_y + 6.0f); }
  // Press at `from`, move in steps, release at `to`.
  void drag(ImVec2 from, ImVec2 to) {
    frame(from, true);
    for (int k = 1; k <= 4; ++k) frame(ImVec2(from.x + (to.x - from.x) * k / 4.0f, from.y + (to.y - from.y) * k / 4.0f), true);
    frame(to, false);
    frame(uitest::kNoMouse, false);
  }
};

std::size_t count(const Assembly& a, PartRef::Kind k) {
  switch (k) {
    case PartRef::Kind::Spring: return a.springs.size();
    case PartRef::Kind::Damper: return a.dampers.size();
    case PartRef::Kind::Contact: return a.contacts.size();
    default: return 0;
  }
}

// The ends (a, b) of the last part of kind k.
std::pair<int, int> last_ends(const Assembly& a, PartRef::Kind k) {
  switch (k) {
    case PartRef::Kind::Spring: return {a.springs.back().a, a.springs.back().b};
    case PartRef::Kind::Damper: return {a.dampers.back().a, a.dampers.back().b};
    default: return {a.contacts.back().a, a.contacts.back().b};
  }
}

}  // namespace

// Random body pairs of every multi-body preset, a random kind each: exactly one part of that kind
// is added, between the two bodies the drag started and ended on, with the palette's value; undo
// restores the plant before it and redo the connected one.
TEST(PlantConnectInput, DraggingFromABodyToAnotherConnectsThemWithTheChosenKind) {
  std::mt19937 rng(1103);
  const PartRef::Kind kinds[] = {PartRef::Kind::Spring, PartRef::Kind::Damper, PartRef::Kind::Contact};
  for (const char* preset : {"two_mass_drive.json", "slider_on_table.json", "three_body_chain.json"}) {
    PlantHarness h(preset);
    ASSERT_TRUE(h.p().sim) << h.p().error;
    const int nb = static_cast<int>(h.p().scenario->plant.bodies.size());
    ASSERT_GE(nb, 2);
    for (int trial = 0; trial < 4; ++trial) {
      const int from = static_cast<int>(rng() % nb);
      const int to = (from + 1 + static_cast<int>(rng() % (nb - 1))) % nb;
      const PartRef::Kind kind = kinds[rng() % 3];
      SCOPED_TRACE(std::string(preset) + " " + std::to_string(from) + " -> " + std::to_string(to) + " " + ui::to_string(kind));
      h.p().connect_kind = kind;
      const AssemblyScenario before = *h.p().scenario;
      const std::size_t undo_depth = h.p().undo.size();
      h.drag(h.body(from), h.body(to));
      const Assembly& a = h.p().scenario->plant;
      ASSERT_TRUE(h.p().edit_msg.empty()) << h.p().edit_msg;
      EXPECT_TRUE(h.p().hint.empty()) << h.p().hint;
      ASSERT_EQ(count(a, kind), count(before.plant, kind) + 1);
      EXPECT_EQ(a.bodies, before.plant.bodies);
      EXPECT_EQ(a.drives, before.plant.drives);
      EXPECT_EQ(last_ends(a, kind), std::make_pair(from, to));
      if (kind == PartRef::Kind::Spring) {
        EXPECT_EQ(a.springs.back().stiffness, 1000.0);
      } else if (kind == PartRef::Kind::Damper) {
        EXPECT_EQ(a.dampers.back().damping, 1.0);
      } else {
        EXPECT_EQ(a.contacts.back().friction, model_info("gms").defaults());
      }
      EXPECT_EQ(h.p().selected.kind, kind) << "the new part is selected for editing";
      EXPECT_EQ(h.p().undo.size(), undo_depth + 1);
      const AssemblyScenario after = *h.p().scenario;
      ui::plant_undo(h.p());
      EXPECT_EQ(*h.p().scenario, before);
      ui::plant_redo(h.p());
      EXPECT_EQ(*h.p().scenario, after);
    }
  }
}

// From the floor to a body and from a body to the floor: the part's end b is ground.
TEST(PlantConnectInput, DraggingBetweenGroundAndABodyConnectsItToGround) {
  PlantHarness h("two_mass_drive.json");
  for (int body = 0; body < 2; ++body)
    for (bool from_ground : {true, false}) {
      SCOPED_TRACE(std::to_string(body) + (from_ground ? " from ground" : " to ground"));
      h.p().connect_kind = PartRef::Kind::Damper;
      const std::size_t n = h.p().scenario->plant.dampers.size();
      if (from_ground) h.drag(h.ground(), h.body(body));
      else h.drag(h.body(body), h.ground());
      const Assembly& a = h.p().scenario->plant;
      ASSERT_EQ(a.dampers.size(), n + 1) << h.p().hint << h.p().edit_msg;
      EXPECT_EQ(a.dampers.back().a, body);
      EXPECT_EQ(a.dampers.back().b, kGround);
    }
}

// Released on empty canvas, on the same body, or from empty canvas: nothing changes (plant, undo
// stack), and a release that connected nothing says why.
TEST(PlantConnectInput, ADragReleasedOnNothingOrOnTheSameBodyConnectsNothingWithAHint) {
  PlantHarness h("three_body_chain.json");
  const AssemblyScenario before = *h.p().scenario;
  const auto& l = h.p().canvas_layout;
  const ImVec2 empty = h.at(0.5f * l.width, 4.0f);  // the top strip above every block
  ASSERT_EQ(ui::attachment_at(l, before.plant, h.p().canvas_pose, h.p().canvas_mag, 0.5f * l.width, 4.0f), ui::kNoEnd);
  for (auto kind : {PartRef::Kind::Spring, PartRef::Kind::Damper, PartRef::Kind::Contact}) {
    h.p().connect_kind = kind;
    h.drag(h.body(0), empty);
    EXPECT_EQ(*h.p().scenario, before);
    EXPECT_NE(h.p().hint.find("Nothing connected"), std::string::npos) << h.p().hint;
    h.p().hint.clear();
    const ImVec2 c = h.body(1);
    h.drag(c, ImVec2(c.x + 12.0f, c.y + 6.0f));  // moved, but still on the same block
    EXPECT_EQ(*h.p().scenario, before);
    EXPECT_NE(h.p().hint.find("two different ends"), std::string::npos) << h.p().hint;
    h.drag(empty, h.body(2));  // started on nothing: no connection
    EXPECT_EQ(*h.p().scenario, before);
    h.drag(h.body(2), h.at(0.5f * l.width, l.height + 40.0f));  // released below the schematic (on the plots)
    EXPECT_EQ(*h.p().scenario, before);
    EXPECT_NE(h.p().hint.find("Nothing connected"), std::string::npos) << h.p().hint;
  }
  EXPECT_TRUE(h.p().undo.empty());
}

// connect_parts directly: ground goes to end b; invalid ends leave the plant as it was.
TEST(PlantConnect, ConnectPartsRejectsBadEndsAndPutsGroundLast) {
  const auto s = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json");
  Assembly a = s.plant;
  EXPECT_EQ(ui::connect_parts(a, PartRef::Kind::Spring, 0, 0), PartRef{});
  EXPECT_EQ(ui::connect_parts(a, PartRef::Kind::Spring, kGround, kGround), PartRef{});
  EXPECT_EQ(ui::connect_parts(a, PartRef::Kind::Spring, 0, ui::kNoEnd), PartRef{});
  EXPECT_EQ(ui::connect_parts(a, PartRef::Kind::Spring, 0, 7), PartRef{});
  EXPECT_EQ(ui::connect_parts(a, PartRef::Kind::Body, 0, 1), PartRef{});
  EXPECT_EQ(a, s.plant);
  const PartRef r = ui::connect_parts(a, PartRef::Kind::Spring, kGround, 1);
  ASSERT_EQ(r.kind, PartRef::Kind::Spring);
  EXPECT_EQ(a.springs[static_cast<std::size_t>(r.index)].a, 1);
  EXPECT_EQ(a.springs[static_cast<std::size_t>(r.index)].b, kGround);
  EXPECT_TRUE(validate(a).empty());
}
// The Plant tab's plant as edited in the window (here: connected by a drag) is saved with the
// session and restored identically into a fresh window, with its path, speed and magnification.
TEST(PlantConnectInput, AnEditedPlantSurvivesTheSession) {
  PlantHarness h("two_mass_drive.json");
  h.p().connect_kind = PartRef::Kind::Contact;
  h.drag(h.body(1), h.body(0));
  ASSERT_EQ(h.p().scenario->plant.contacts.size(), 3u) << h.p().hint << h.p().edit_msg;
  h.p().speed = 0.25;
  h.p().magnification = 12.5f;
  for (std::size_t c = 0; c < h.p().plotted.size(); ++c) h.p().plotted[c] = c % 3 == 1;  // a choice unlike the default
  h.p().tf_output = 1;
  h.p().tf_sliding = false;
  const std::string path = testing::TempDir() + "plant_session.json";
  save_session(ui::make_session(h.s), path);
  ui::AppState fresh;
  ui::restore_session(fresh, load_session(path));
  ASSERT_TRUE(fresh.plant.scenario);
  EXPECT_EQ(*fresh.plant.scenario, *h.p().scenario);
  EXPECT_EQ(fresh.plant.path, h.p().path);
  EXPECT_EQ(fresh.plant.speed, 0.25);
  EXPECT_EQ(fresh.plant.magnification, 12.5f);
  EXPECT_EQ(fresh.plant.plotted, h.p().plotted);
  EXPECT_EQ(fresh.plant.tf_output, 1);
  EXPECT_FALSE(fresh.plant.tf_sliding);
  EXPECT_EQ(fresh.view.tab, "Plant");
  EXPECT_EQ(ui::make_session(fresh), ui::make_session(h.s));
  std::remove(path.c_str());
}
#endif
