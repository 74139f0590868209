// Saving, unsaved changes, undo / redo and the keyboard shortcuts of the window, through the app's
// frame (ui::draw_frame in a headless ImGui context with scripted keys) and through AppState.
// Shipped presets are copied to a temporary folder used as GMSLAB_PRESETS, and saves go to a
// temporary GMSLAB_USER_DIR: the real presets are never at risk.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/io/assembly_io.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/ui/app_frame.hpp"
#include "tests/ui/imgui_test_context.hpp"
#include "ui/app.hpp"
#include "ui/app_files.hpp"
#include "ui/plot/plot.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Temporary presets folder (a copy of the shipped one) and user folder, set in the environment.
struct Folders : ::testing::Test {
  fs::path root, presets, user;
  void SetUp() override {
    root = fs::temp_directory_path() / ("gmslab_files_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root);
    presets = root / "presets";
    user = root / "user" / "scenarios";
    fs::create_directories(presets);
    for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets"))
      fs::copy_file(e.path(), presets / e.path().filename());
    setenv("GMSLAB_PRESETS", presets.c_str(), 1);
    setenv("GMSLAB_USER_DIR", user.c_str(), 1);
  }
  void TearDown() override {
    unsetenv("GMSLAB_PRESETS");
    unsetenv("GMSLAB_USER_DIR");
    fs::remove_all(root);
  }
  std::string preset(const char* name) const { return (presets / name).string(); }
  // The state after opening a preset as the window does (load request, applied).
  void open(ui::AppState& s, const std::string& path) {
    s.pending.load_path = path;
    ui::apply_pending(s);
    ASSERT_TRUE(s.error.empty()) << s.error;
  }
};

// Random friction edit: one scalar of the model scaled within [0.8, 1.2] (valid for the presets).
// Fc goes down, Fs up: both keep Fc <= Fs.
ModelParams edited(const ModelParams& p, std::mt19937& rng, const char* key) {
  ModelParams q = p;
  const bool up = std::string(key) == "Fs";
  q.set_scalar(key, p.scalar(key) * std::uniform_real_distribution<double>(up ? 1.0 : 0.8, up ? 1.25 : 1.0)(rng));
  return q;
}
}  // namespace

TEST_F(Folders, SaveNeverWritesAShippedPresetAndGoesToTheUsersFolder) {
  std::mt19937 rng(15);
  for (const char* name : {"fig4_stick_slip.json", "fig2a_presliding.json", "compare_fig4_lugre.json"}) {
    ui::AppState s;
    open(s, preset(name));
    const std::string before = slurp(preset(name));
    EXPECT_TRUE(ui::is_shipped_preset(preset(name)));
    EXPECT_FALSE(ui::has_unsaved_changes(s));
    s.pending.friction = edited(s.scenario.friction, rng, "Fc");
    ui::apply_pending(s);
    EXPECT_TRUE(ui::has_unsaved_changes(s));
    EXPECT_NE(ui::window_title(s).find(" *"), std::string::npos) << ui::window_title(s);
    const std::string target = ui::save_target(s);
    EXPECT_EQ(fs::path(target).parent_path(), user) << target;
    EXPECT_EQ(fs::path(target).filename(), name);
    s.pending.save_path = target;
    ui::apply_pending(s);
    EXPECT_EQ(slurp(preset(name)), before) << "shipped preset changed";
    ASSERT_TRUE(fs::exists(target));
    EXPECT_EQ(load_scenario(target), s.scenario);
    EXPECT_FALSE(ui::has_unsaved_changes(s));
    EXPECT_EQ(ui::window_title(s).find(" *"), std::string::npos);
    EXPECT_EQ(s.scenario_path, target);
    // Asked explicitly to write the shipped file (a typed path): refused with a message.
    s.pending.save_path = preset(name);
    s.pending.save_confirmed = true;
    ui::apply_pending(s);
    EXPECT_EQ(slurp(preset(name)), before);
    EXPECT_NE(s.status.find("never overwritten"), std::string::npos) << s.status;
  }
}

TEST_F(Folders, ReplacingAFileAsksFirstAndTheAnswerDecides) {
  ui::AppState s;
  open(s, preset("fig4_stick_slip.json"));
  fs::create_directories(user);
  const std::string target = ui::save_target(s);
  { std::ofstream(target) << "{\"not\": \"mine\"}"; }
  s.pending.friction = edited(s.scenario.friction, *std::make_unique<std::mt19937>(3), "Fs");
  ui::apply_pending(s);
  s.pending.save_path = target;
  ui::apply_pending(s);
  EXPECT_EQ(s.confirm_replace, target);  // asked, nothing written
  EXPECT_EQ(slurp(target), "{\"not\": \"mine\"}");
  EXPECT_TRUE(ui::has_unsaved_changes(s));
  // The question is a modal in the frame: "Replace" writes the file.
  uitest::make_headless_imgui(ImVec2(1280, 720));
  {
    ui::ScopedPlotContext plots;
    auto frame = [&](ImVec2 mouse, bool down) { uitest::draw_app_frame(s, mouse, down); };
    frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
    frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
    ImGuiWindow* modal = ImGui::FindWindowByName("Replace file?");
    ASSERT_NE(modal, nullptr);
    ASSERT_TRUE(modal->Active);
    // The "Replace" button is the first button of the modal: click at its place.
    const ImVec2 at(modal->DC.CursorStartPos.x + 20, modal->DC.CursorStartPos.y +
                                                          2 * ImGui::GetTextLineHeightWithSpacing() +
                                                          0.5f * ImGui::GetFrameHeight());
    frame(at, false);
    frame(at, true);
    frame(at, false);
    frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  }
  ImGui::DestroyContext();
  EXPECT_TRUE(s.confirm_replace.empty());
  EXPECT_EQ(load_scenario(target), s.scenario);
  EXPECT_FALSE(ui::has_unsaved_changes(s));
  // Saving again to the file this window wrote does not ask.
  s.pending.friction = edited(s.scenario.friction, *std::make_unique<std::mt19937>(4), "Fs");
  ui::apply_pending(s);
  s.pending.save_path = target;
  ui::apply_pending(s);
  EXPECT_TRUE(s.confirm_replace.empty());
  EXPECT_EQ(load_scenario(target), s.scenario);
}

// A random sequence of edits of every kind (friction, plant, overlay, drive, a load), then undo to
// the start and redo to the end: each step restores exactly the state recorded before / after it,
// in the scenario and in the running simulation.
TEST_F(Folders, UndoAndRedoRestoreEveryEditInOrder) {
  std::mt19937 rng(1515);
  for (int trial = 0; trial < 4; ++trial) {
    ui::AppState s;
    open(s, preset("fig4_stick_slip.json"));
    std::vector<ui::EditSnapshot> states{ui::snapshot(s)};
    std::uniform_int_distribution<int> kind(0, 4);
    for (int i = 0; i < 12; ++i) {
      switch (kind(rng)) {
        case 0: s.pending.friction = edited(s.scenario.friction, rng, "Fs"); break;
        case 1: {
          Plant pl = s.scenario.plant;
          pl.mass *= std::uniform_real_distribution<double>(0.5, 2.0)(rng);
          s.pending.plant = pl;
          break;
        }
        case 2:
          if (s.compare) s.pending.clear_compare = true;
          else s.pending.compare = model_info("lugre").defaults();
          break;
        case 3: {
          Scenario sc = s.scenario;
          sc.run.duration *= std::uniform_real_distribution<double>(0.5, 1.5)(rng);
          s.pending.scenario = sc;
          break;
        }
        case 4:
          s.pending.load_path = preset(rng() % 2 ? "fig2a_presliding.json" : "fig4_stick_slip.json");
          break;
      }
      ui::apply_pending(s);
      ASSERT_TRUE(s.error.empty()) << s.error;
      if (!(ui::snapshot(s) == states.back())) states.push_back(ui::snapshot(s));
    }
    for (std::size_t k = states.size() - 1; k-- > 0;) {
      ASSERT_TRUE(ui::undo(s));
      ui::apply_pending(s);
      EXPECT_TRUE(ui::snapshot(s) == states[k]) << "undo to step " << k;
      EXPECT_EQ(s.main.sim->one_body()->friction, states[k].scenario.friction);
      EXPECT_EQ(s.main.sim->one_body()->plant, states[k].scenario.plant);
      EXPECT_EQ(s.overlay.sim != nullptr, states[k].compare.has_value());
    }
    EXPECT_FALSE(ui::undo(s));
    for (std::size_t k = 1; k < states.size(); ++k) {
      ASSERT_TRUE(ui::redo(s));
      ui::apply_pending(s);
      EXPECT_TRUE(ui::snapshot(s) == states[k]) << "redo to step " << k;
    }
    EXPECT_FALSE(ui::redo(s));
  }
}

TEST_F(Folders, AnEditAfterAFinishedRunRerunsIt) {
  ui::AppState s;
  open(s, preset("fig2a_presliding.json"));
  ui::run_until(s, -1);
  ASSERT_TRUE(s.main.sim->finished());
  std::mt19937 rng(7);
  s.pending.friction = edited(s.scenario.friction, rng, "Fs");
  ui::apply_pending(s);
  EXPECT_TRUE(s.running);
  EXPECT_DOUBLE_EQ(s.main.sim->time(), 0.0);
}

// The shortcuts through the frame: keys pressed as the GLFW backend reports them.
TEST_F(Folders, ShortcutsRunPauseRerunSaveUndoAndRedo) {
  uitest::make_headless_imgui(ImVec2(1280, 720));
  {
    ui::ScopedPlotContext plots;
    ui::AppState s;
    open(s, preset("fig4_stick_slip.json"));
    ImGuiIO& io = ImGui::GetIO();
    io.KeyMap[ImGuiKey_Space] = 32;
    io.KeyMap[ImGuiKey_Z] = 90;
    io.KeyMap[ImGuiKey_Y] = 89;
    s.keys = {83, 294};
    auto frame = [&] {
      io.DeltaTime = 1.0f / 60.0f;
      io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
      ImGui::NewFrame();
      ui::draw_frame(s);
      ImGui::Render();
    };
    auto press = [&](int key, bool ctrl = false, bool shift = false) {
      io.KeyCtrl = ctrl, io.KeyShift = shift;
      io.KeysDown[key] = true;
      frame();
      io.KeysDown[key] = false;
      io.KeyCtrl = io.KeyShift = false;
      frame();
    };
    frame();
    press(32);
    EXPECT_TRUE(s.running);
    for (int i = 0; i < 5; ++i) frame();
    const double t1 = s.main.sim->time();
    EXPECT_GT(t1, 0.0);
    press(32);
    EXPECT_FALSE(s.running);
    press(294);  // F5: from t = 0, running
    EXPECT_TRUE(s.running);
    EXPECT_LT(s.main.sim->time(), t1);
    press(32);
    const ModelParams before = s.scenario.friction;
    std::mt19937 rng(9);
    s.pending.friction = edited(before, rng, "Fc");
    frame();
    const ModelParams after = s.scenario.friction;
    ASSERT_FALSE(after == before);
    press(90, true);  // Ctrl+Z
    EXPECT_EQ(s.scenario.friction, before);
    EXPECT_EQ(s.main.sim->one_body()->friction, before);
    press(90, true, true);  // Ctrl+Shift+Z
    EXPECT_EQ(s.scenario.friction, after);
    press(90, true);
    press(89, true);  // Ctrl+Y
    EXPECT_EQ(s.scenario.friction, after);
    press(83, true);  // Ctrl+S: to the user's folder, not the preset
    const fs::path saved = user / "fig4_stick_slip.json";
    ASSERT_TRUE(fs::exists(saved));
    EXPECT_EQ(load_scenario(saved.string()).friction, after);
    EXPECT_FALSE(ui::has_unsaved_changes(s));
  }
  ImGui::DestroyContext();
}

TEST_F(Folders, PresetsMenuListsShippedAndUserPresetsWithDescriptions) {
  fs::create_directories(user);
  ui::AppState s;
  open(s, preset("fig4_stick_slip.json"));
  s.pending.save_path = (user / "mine.json").string();
  ui::apply_pending(s);
  const auto list = ui::list_presets();
  std::size_t shipped = 0, mine = 0;
  for (const auto& e : list) {
    if (e.shipped && e.plant) {  // schema 2: an assembled plant, opened in the Plant tab
      ++shipped;
      EXPECT_EQ(load_assembly_scenario(e.path).description, e.description) << e.path;
      ui::AppState t;
      t.pending.load_path = e.path;
      ui::apply_pending(t);
      EXPECT_EQ(t.view.tab, "Plant") << e.path;
    } else if (e.shipped) {
      ++shipped;
      EXPECT_EQ(load_scenario(e.path).description, e.description) << e.path;
      EXPECT_EQ(load_scenario(e.path).name, e.name);
    } else {
      ++mine;
      EXPECT_EQ(fs::path(e.path).filename(), "mine.json");
    }
  }
  EXPECT_EQ(shipped, static_cast<std::size_t>(std::distance(fs::directory_iterator(presets), fs::directory_iterator())));
  EXPECT_EQ(mine, 1u);
}
#endif

#if __has_include(<imgui.h>)
// The overlay linked to the main model's shared parameters: every main-model edit (random, fixed
// seed) carries F_s, F_c, V_s over to the overlay (and its running simulation); unlinked, the
// overlay keeps its own.
TEST_F(Folders, OverlayFollowsTheMainModelsSharedParametersWhenLinked) {
  std::mt19937 rng(1212);
  for (const bool linked : {true, false}) {
    ui::AppState s;
    open(s, preset("fig4_stick_slip.json"));
    s.pending.compare = model_info("lugre").defaults();
    ui::apply_pending(s);
    ASSERT_TRUE(s.overlay.sim);
    s.overlay_follows_shared = linked;
    const ModelParams own = *s.compare;
    for (int i = 0; i < 8; ++i) {
      ModelParams m = s.scenario.friction;
      const double fs = std::uniform_real_distribution<double>(0.5, 3.0)(rng);
      m.set_scalar("Fs", fs);
      m.set_scalar("Fc", fs * std::uniform_real_distribution<double>(0.3, 1.0)(rng));
      m.set_scalar("Vs", std::uniform_real_distribution<double>(1e-4, 1e-2)(rng));
      s.pending.friction = m;
      ui::apply_pending(s);
      ASSERT_TRUE(s.error.empty()) << s.error;
      for (const char* k : {"Fs", "Fc", "Vs"}) {
        const double want = linked ? m.scalar(k) : own.scalar(k);
        EXPECT_DOUBLE_EQ(s.compare->scalar(k), want) << k;
        EXPECT_DOUBLE_EQ(s.overlay.sim->one_body()->friction.scalar(k), want) << k;
      }
    }
  }
}
#endif
