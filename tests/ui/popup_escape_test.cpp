// Escape closes popups (ImGui 1.86 without keyboard navigation): keys as the GLFW backend reports
// them (io.KeyMap[ImGuiKey_Escape] = GLFW_KEY_ESCAPE). A plot's export menu opened by a right-click
// in the window closes; nested popups close one per press, the topmost first; the "Replace file?"
// modal takes Escape as its Cancel; Escape while a text field is being edited leaves the field and
// keeps the popup. Built only with the app (ImGui).
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>
#include <imgui_stdlib.h>

#include <cfloat>
#include <functional>
#include <string>

#include "core/io/scenario_io.hpp"
#include "tests/ui/imgui_test_context.hpp"
#include "ui/app.hpp"
#include "ui/plot/plot.hpp"
#include "ui/popups.hpp"

using namespace gmslab;

namespace {
constexpr int kEscape = 256;  // GLFW_KEY_ESCAPE

int open_popups() { return GImGui->OpenPopupStack.Size; }

struct Keys {
  Keys() { ImGui::GetIO().KeyMap[ImGuiKey_Escape] = kEscape; }
  // One frame drawn by `draw` with the mouse at `mouse` (buttons 0 and 1 as given) and Escape held.
  static void frame(const std::function<void()>& draw, ImVec2 mouse = ImVec2(-FLT_MAX, -FLT_MAX), bool left = false,
                    bool right = false, bool escape = false) {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = mouse;
    io.MouseDown[0] = left;
    io.MouseDown[1] = right;
    io.KeysDown[kEscape] = escape;
    ImGui::NewFrame();
    draw();
    ImGui::Render();
  }
  // Escape pressed for one frame and released the next.
  static void press_escape(const std::function<void()>& draw) {
    frame(draw, ImVec2(-FLT_MAX, -FLT_MAX), false, false, true);
    frame(draw);
  }
};
}  // namespace

TEST(PopupEscape, ClosesAPlotsExportMenuInTheWindow) {
  uitest::make_headless_imgui(ImVec2(1280, 720));
  {
    ui::ScopedPlotContext plots;
    Keys keys;
    ui::AppState s;
    ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"), "");
    s.view.tab = "Simulation";
    const auto draw = [&] { ui::draw_frame(s); };
    for (int i = 0; i < 3; ++i) Keys::frame(draw);
    const ui::PlotTransform t = ui::LastPlotTransform();
    ASSERT_GT(t.px1 - t.px0, 20.0);
    const ImVec2 at(static_cast<float>(0.5 * (t.px0 + t.px1)), static_cast<float>(0.5 * (t.py0 + t.py1)));
    Keys::frame(draw, at);
    Keys::frame(draw, at, false, true);  // right button down
    Keys::frame(draw, at, false, false);  // released: the export menu opens
    Keys::frame(draw, at);
    ASSERT_EQ(open_popups(), 1) << "the right-click opened no menu";
    Keys::press_escape(draw);
    EXPECT_EQ(open_popups(), 0);
  }
  ImGui::DestroyContext();
}

TEST(PopupEscape, ClosesTheTopmostPopupFirst) {
  uitest::make_headless_imgui(ImVec2(800, 600));
  Keys keys;
  bool open_outer = true, open_inner = false;
  ImGuiID outer_id = 0;
  const auto draw = [&] {
    ui::close_popup_on_escape();
    ImGui::Begin("w");
    outer_id = ImGui::GetID("outer");
    if (open_outer) ImGui::OpenPopup("outer"), open_outer = false;
    if (ImGui::BeginPopup("outer")) {
      ImGui::TextUnformatted("outer");
      if (open_inner) ImGui::OpenPopup("inner"), open_inner = false;
      if (ImGui::BeginPopup("inner")) {
        ImGui::TextUnformatted("inner");
        ImGui::EndPopup();
      }
      ImGui::EndPopup();
    }
    ImGui::End();
  };
  Keys::frame(draw);
  open_inner = true;
  Keys::frame(draw);
  Keys::frame(draw);
  ASSERT_EQ(open_popups(), 2);
  Keys::press_escape(draw);
  EXPECT_EQ(open_popups(), 1);
  EXPECT_EQ(GImGui->OpenPopupStack[0].PopupId, outer_id) << "the outer popup stays open";
  Keys::press_escape(draw);
  EXPECT_EQ(open_popups(), 0);
  ImGui::DestroyContext();
}

TEST(PopupEscape, EscapeInATextFieldLeavesTheFieldNotThePopup) {
  uitest::make_headless_imgui(ImVec2(800, 600));
  Keys keys;
  bool open = true;
  std::string text = "abc";
  ImVec2 field;
  const auto draw = [&] {
    ui::close_popup_on_escape();
    ImGui::Begin("w");
    if (open) ImGui::OpenPopup("p"), open = false;
    if (ImGui::BeginPopup("p")) {
      ImGui::InputText("##t", &text);
      field = ImGui::GetItemRectMin();
      field.x += 5, field.y += 5;
      ImGui::EndPopup();
    }
    ImGui::End();
  };
  Keys::frame(draw);
  Keys::frame(draw);
  Keys::frame(draw, field, true);  // click into the field
  Keys::frame(draw, field, false);
  Keys::frame(draw, field, false);
  ASSERT_TRUE(ImGui::GetIO().WantTextInput) << "the field did not take the keyboard";
  Keys::press_escape(draw);
  EXPECT_EQ(open_popups(), 1) << "Escape while typing closed the popup";
  Keys::frame(draw);
  EXPECT_FALSE(ImGui::GetIO().WantTextInput);
  Keys::press_escape(draw);
  EXPECT_EQ(open_popups(), 0);
  ImGui::DestroyContext();
}

TEST(PopupEscape, TheReplaceModalTakesEscapeAsCancel) {
  uitest::make_headless_imgui(ImVec2(1280, 720));
  {
    ui::ScopedPlotContext plots;
    Keys keys;
    ui::AppState s;
    ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"), "");
    s.confirm_replace = "/tmp/gmslab_popup_escape_never_written.json";
    const auto draw = [&] { ui::draw_frame(s); };
    for (int i = 0; i < 3; ++i) Keys::frame(draw);
    ASSERT_EQ(open_popups(), 1) << "the modal did not open";
    Keys::press_escape(draw);
    EXPECT_EQ(open_popups(), 0);
    EXPECT_TRUE(s.confirm_replace.empty());
    EXPECT_TRUE(s.pending.save_path.empty()) << "Escape saved";
    EXPECT_EQ(s.status, "not saved");
  }
  ImGui::DestroyContext();
}
#endif
