// gmslab ui: the look shared by the window and the headless renderer (light theme, one font).
// Call once after ImGui::CreateContext() and before the backend builds the font texture.
#pragma once

namespace gmslab::ui {

// font_px: pixel height of the UI font. Uses DejaVu Sans (Debian fonts-dejavu-core) when
// installed, else ImGui's built-in font scaled to about that size. Returns the font file used
// ("" for the built-in one).
const char* setup_style(float font_px = 17.0f);

}  // namespace gmslab::ui
