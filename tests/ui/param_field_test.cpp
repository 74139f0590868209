// The one number field (ui::edit_param) driven by scripted mouse and keyboard input: a single
// click never sets a value (it starts typing), typed text sets it, dragging the handle changes it
// (log fields by a decade per 200 px), and an out-of-range value is rejected on the field itself
// (the value in force stays, the field is marked with the message). Fields over random specs and
// values, fixed seed.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "tests/ui/imgui_test_context.hpp"
#include "ui/param_editor.hpp"

using namespace gmslab;

namespace {
constexpr float kWidth = 300.0f;

struct Field {
  ImVec2 origin;  // top-left of the field
  double value;
  ParamSpec spec;
  ui::FieldMarks marks;
  bool use_marks = true;
  Field(const ParamSpec& s, double v) : value(v), spec(s) {
    ImGuiIO& io = ImGui::GetIO();
    io.KeyMap[ImGuiKey_Enter] = 13;
    io.KeyMap[ImGuiKey_Backspace] = 8;
    io.KeyMap[ImGuiKey_A] = 65;
    frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  }
  bool frame(ImVec2 mouse, bool down, const char* chars = nullptr, int key = -1) {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = mouse;
    io.MouseDown[0] = down;
    if (chars) io.AddInputCharactersUTF8(chars);
    if (key >= 0) io.KeysDown[key] = true;
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(600, 300));
    ImGui::Begin("field", nullptr, ImGuiWindowFlags_NoDecoration);
    origin = ImGui::GetCursorScreenPos();
    ImGui::SetNextItemWidth(kWidth);
    const bool c = ui::edit_param("##x", spec, value, 0.0, use_marks ? &marks : nullptr);
    ImGui::End();
    ImGui::Render();
    if (key >= 0) io.KeysDown[key] = false;
    return c;
  }
  float mid_y() const { return origin.y + 0.5f * ImGui::GetFrameHeight(); }
  ImVec2 text_at() const { return ImVec2(origin.x + 0.3f * kWidth, mid_y()); }
  ImVec2 handle_at() const { return ImVec2(origin.x + kWidth - 0.4f * ImGui::GetFrameHeight(), mid_y()); }
  void click(ImVec2 at) {
    frame(at, false);
    frame(at, true);
    frame(at, false);
  }
  // Click, select all, type, Enter.
  void type(const std::string& text) {
    click(text_at());
    ImGuiIO& io = ImGui::GetIO();
    io.KeyCtrl = true;
    frame(text_at(), false, nullptr, 65);
    io.KeyCtrl = false;
    frame(text_at(), false, text.c_str());
    frame(text_at(), false, nullptr, 13);
    frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  }
};

ParamSpec random_spec(std::mt19937& rng, bool log) {
  const double lo = log ? std::pow(10.0, std::uniform_real_distribution<double>(-6, -1)(rng)) : -5.0;
  const double hi = log ? lo * std::pow(10.0, std::uniform_real_distribution<double>(4, 8)(rng)) : 5.0;
  return ParamSpec{"x", "x", "N", "test field", lo, hi, false, log};
}
}  // namespace

TEST(ParamField, ASingleClickNeverSetsAValueTypingDoes) {
  std::mt19937 rng(2015);
  for (int trial = 0; trial < 12; ++trial) {
    uitest::make_headless_imgui(ImVec2(800, 400));
    const bool log = trial % 2 == 0;
    const ParamSpec spec = random_spec(rng, log);
    const double v0 = log ? std::sqrt(spec.lo * spec.hi) : std::uniform_real_distribution<double>(-4, 4)(rng);
    Field f(spec, v0);
    // Clicks anywhere along the field: the value stays.
    for (float x : {0.05f, 0.5f, 0.8f}) {
      f.click(ImVec2(f.origin.x + x * (kWidth - 30), f.mid_y()));
      EXPECT_EQ(f.value, v0) << "click at " << x;
    }
    f.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
    // Typed: exactly the value typed.
    const double want = log ? spec.lo * std::pow(10.0, std::uniform_real_distribution<double>(0.5, 3.5)(rng))
                            : std::uniform_real_distribution<double>(-4.5, 4.5)(rng);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", want);
    f.type(buf);
    EXPECT_DOUBLE_EQ(f.value, std::stod(buf)) << buf;
    EXPECT_EQ(f.marks.rejected, 0u);
    ImGui::DestroyContext();
  }
}

TEST(ParamField, DraggingTheHandleChangesTheValueByTheDistance) {
  std::mt19937 rng(515);
  for (int trial = 0; trial < 10; ++trial) {
    uitest::make_headless_imgui(ImVec2(800, 400));
    const bool log = trial % 2 == 0;
    const ParamSpec spec = random_spec(rng, log);
    const double v0 = log ? std::sqrt(spec.lo * spec.hi) : 0.5;
    Field f(spec, v0);
    // Whole pixels: ImGui floors the mouse position.
    const float dx = std::round(std::uniform_real_distribution<float>(40.0f, 120.0f)(rng)) * (trial % 3 == 0 ? -1.0f : 1.0f);
    const ImVec2 a(std::floor(f.handle_at().x), std::floor(f.handle_at().y));
    f.frame(a, false);
    f.frame(a, true);
    f.frame(ImVec2(a.x + std::round(0.5f * dx), a.y), true);
    f.frame(ImVec2(a.x + dx, a.y), true);
    f.frame(ImVec2(a.x + dx, a.y), false);
    if (log)
      EXPECT_NEAR(std::log10(f.value / v0), dx / 200.0, 1e-9) << "log field: a decade per 200 px";
    else
      EXPECT_NEAR(f.value - v0, dx * std::max(0.5 * 0.005, std::min(10.0 * 1e-4, 0.01)), 1e-9);
    ImGui::DestroyContext();
  }
}

TEST(ParamField, AnOutOfRangeValueIsRejectedOnTheFieldWithItsMessage) {
  std::mt19937 rng(77);
  for (int trial = 0; trial < 6; ++trial) {
    uitest::make_headless_imgui(ImVec2(800, 400));
    const bool log = trial % 2 == 0;
    const ParamSpec spec = random_spec(rng, log);
    const double v0 = log ? std::sqrt(spec.lo * spec.hi) : 1.0;
    Field f(spec, v0);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", spec.hi * (log ? 10.0 : 2.0));
    f.type(buf);
    EXPECT_EQ(f.value, v0) << "the value in force stays";
    EXPECT_NE(f.marks.rejected, 0u);
    EXPECT_NE(f.marks.message.find("allowed"), std::string::npos) << f.marks.message;
    EXPECT_NE(f.marks.message.find(spec.range_text()), std::string::npos) << f.marks.message;
    // A valid value clears the mark.
    std::snprintf(buf, sizeof buf, "%.6g", log ? spec.lo * 100 : -2.5);
    f.type(buf);
    EXPECT_DOUBLE_EQ(f.value, std::stod(buf));
    EXPECT_EQ(f.marks.rejected, 0u);
    // Without marks (the design panel's settings) the value is clamped to the range.
    f.use_marks = false;
    std::snprintf(buf, sizeof buf, "%.6g", spec.hi * 3);
    f.type(buf);
    EXPECT_DOUBLE_EQ(f.value, spec.hi);
    ImGui::DestroyContext();
  }
}
#endif
