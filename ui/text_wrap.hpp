// gmslab ui: text wrapped at spaces only. ImGui's word wrap also breaks after '.' and ',', which
// splits numbers ("0." / "1 m/s"); here a line breaks only at a space (or an existing newline),
// so a number and its unit's first token stay whole.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace gmslab::ui {

// `text` with spaces turned into newlines where the next word would pass `width` (as measured
// by `measure`); a single word wider than `width` gets a line of its own, unbroken.
std::string wrap_at_spaces(std::string_view text, float width, const std::function<float(std::string_view)>& measure);

// Draws `text` wrapped at spaces to the content region's width (current font and text colour).
void TextWrappedAtSpaces(const std::string& text);

}  // namespace gmslab::ui
