// Test helper: an ImGui context for drawing without a window (no ini file, font atlas built).
#pragma once

#include <imgui.h>

namespace gmslab::uitest {

// Creates a context of the given display size, makes it current and returns it.
inline ImGuiContext* make_headless_imgui(ImVec2 size) {
  ImGuiContext* c = ImGui::CreateContext();
  ImGui::SetCurrentContext(c);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = size;
  io.IniFilename = nullptr;
  unsigned char* px = nullptr;
  int w = 0, h = 0;
  io.Fonts->GetTexDataAsRGBA32(&px, &w, &h);
  return c;
}

}  // namespace gmslab::uitest
