#include "ui/popups.hpp"

#include <imgui.h>
#include <imgui_internal.h>

namespace gmslab::ui {

namespace {
// Escape this frame (as the host maps it: io.KeyMap[ImGuiKey_Escape]), not typed into a field.
bool escape_pressed() {
  const int key = ImGui::GetKeyIndex(ImGuiKey_Escape);
  return key >= 0 && !ImGui::GetIO().WantTextInput && ImGui::IsKeyPressed(key, false);
}
}  // namespace

bool close_popup_on_escape() {
  ImGuiContext& g = *GImGui;
  if (g.OpenPopupStack.Size == 0 || !escape_pressed()) return false;
  const ImGuiPopupData& top = g.OpenPopupStack.back();
  if (top.Window && (top.Window->Flags & ImGuiWindowFlags_Modal)) return false;
  ImGui::ClosePopupToLevel(g.OpenPopupStack.Size - 1, true);
  return true;
}

bool escape_cancels_popup() {
  ImGuiContext& g = *GImGui;
  if (g.BeginPopupStack.Size == 0 || g.OpenPopupStack.Size == 0) return false;
  if (g.BeginPopupStack.back().PopupId != g.OpenPopupStack.back().PopupId) return false;
  return escape_pressed();
}

}  // namespace gmslab::ui
