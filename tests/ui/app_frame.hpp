// Test helper: one frame of the whole window (ui::draw_frame) under scripted mouse input, and a
// harness with the Design tab open on the Fig. 4 preset. Built only with the app (ImGui).
#pragma once

#include <imgui.h>

#include <cfloat>
#include <string>

#include "core/io/scenario_io.hpp"
#include "tests/ui/imgui_test_context.hpp"
#include "ui/app.hpp"
#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"

namespace gmslab::uitest {

inline const ImVec2 kNoMouse(-FLT_MAX, -FLT_MAX);

// One frame at 60 Hz with the mouse at `mouse` and its left button `down`.
inline void draw_app_frame(ui::AppState& s, ImVec2 mouse, bool down) {
  ImGuiIO& io = ImGui::GetIO();
  io.DeltaTime = 1.0f / 60.0f;
  io.MousePos = mouse;
  io.MouseDown[0] = down;
  ImGui::NewFrame();
  ui::draw_frame(s);
  ImGui::Render();
}

// The window at 1600x1000 with the Design tab open on presets/fig4_stick_slip.json.
struct DesignHarness {
  ui::AppState s;
  ui::ScopedPlotContext plots;
  DesignHarness() {
    make_headless_imgui(ImVec2(1600, 1000));
    ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"), "");
    s.view.tab = "Design";
    for (int i = 0; i < 3; ++i) frame(kNoMouse, false);
  }
  ~DesignHarness() { ImGui::DestroyContext(); }
  DesignHarness(const DesignHarness&) = delete;
  DesignHarness& operator=(const DesignHarness&) = delete;
  void frame(ImVec2 mouse, bool down) { draw_app_frame(s, mouse, down); }
  ui::DesignViewState& d() { return s.design; }
  // Screen position of the s-plane point z on the locus canvas.
  ImVec2 px(control::cplx z) {
    const auto& t = s.design.canvas;
    return ImVec2(static_cast<float>(t.to_px_x(z.real())), static_cast<float>(t.to_px_y(z.imag())));
  }
};

}  // namespace gmslab::uitest
