#include "ui/text_wrap.hpp"

#include <imgui.h>

namespace gmslab::ui {

std::string wrap_at_spaces(std::string_view text, float width, const std::function<float(std::string_view)>& measure) {
  std::string out;
  std::size_t para = 0;
  while (para <= text.size()) {
    std::size_t nl = text.find('\n', para);
    if (nl == std::string_view::npos) nl = text.size();
    const std::string_view line = text.substr(para, nl - para);
    std::string cur;
    std::size_t i = 0;
    while (i < line.size()) {
      std::size_t j = line.find(' ', i);
      if (j == std::string_view::npos) j = line.size();
      const std::string_view word = line.substr(i, j - i);
      const std::string trial = cur.empty() ? std::string(word) : cur + " " + std::string(word);
      if (!cur.empty() && measure(trial) > width) {
        out += cur + "\n";
        cur = std::string(word);
      } else {
        cur = trial;
      }
      i = j + 1;
    }
    out += cur;
    if (nl < text.size()) out += "\n";
    para = nl + 1;
  }
  return out;
}

void TextWrappedAtSpaces(const std::string& text) {
  const float width = ImGui::GetContentRegionAvail().x;
  const std::string w = wrap_at_spaces(text, width, [](std::string_view s) {
    return ImGui::CalcTextSize(s.data(), s.data() + s.size()).x;
  });
  ImGui::TextUnformatted(w.c_str());
}

}  // namespace gmslab::ui
