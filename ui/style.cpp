#include "ui/style.hpp"

#include <imgui.h>

#include <cstdio>

namespace gmslab::ui {

namespace {
bool file_exists(const char* path) {
  if (FILE* f = std::fopen(path, "rb")) {
    std::fclose(f);
    return true;
  }
  return false;
}
}  // namespace

const char* setup_style(float font_px) {
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // the layout is fixed; sessions save what matters
  static const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  const char* used = "";
  io.Fonts->Clear();
  if (file_exists(kFont)) {
    ImFontConfig cfg;
    cfg.OversampleH = 2;
    cfg.OversampleV = 1;
    // Latin-1 (includes the micro sign) plus Greek for parameter symbols.
    static const ImWchar ranges[] = {0x0020, 0x00FF, 0x0370, 0x03FF, 0x2212, 0x2212, 0};
    if (io.Fonts->AddFontFromFileTTF(kFont, font_px, &cfg, ranges)) used = kFont;
  }
  if (!*used) {
    io.Fonts->AddFontDefault();
    io.FontGlobalScale = font_px / 13.0f;
  }

  ImGui::StyleColorsLight();
  ImGuiStyle& s = ImGui::GetStyle();
  s.WindowRounding = 0.0f;
  s.FrameRounding = 3.0f;
  s.GrabRounding = 3.0f;
  s.TabRounding = 3.0f;
  s.FramePadding = ImVec2(6, 4);
  s.ItemSpacing = ImVec2(8, 6);
  s.WindowPadding = ImVec2(10, 8);
  s.FrameBorderSize = 1.0f;
  s.Colors[ImGuiCol_WindowBg] = ImVec4(0.95f, 0.95f, 0.96f, 1.0f);
  s.Colors[ImGuiCol_ChildBg] = ImVec4(0, 0, 0, 0);
  s.Colors[ImGuiCol_FrameBg] = ImVec4(1, 1, 1, 1);
  s.Colors[ImGuiCol_Border] = ImVec4(0.72f, 0.72f, 0.76f, 1.0f);
  return used;
}

}  // namespace gmslab::ui
