#include "ui/figures/figure_view.hpp"

#include <imgui.h>

#include <string>

#include <algorithm>
#include <cmath>
#include <optional>

#include "ui/plot/plot.hpp"
#include "ui/text_wrap.hpp"

namespace gmslab::ui {

namespace {
std::string micro_sign(std::string s) {
  for (std::size_t i = 0; (i = s.find("[um]", i)) != std::string::npos; i += 4) s.replace(i, 4, "[\xC2\xB5m]");
  return s;
}
}  // namespace

namespace {
LineStyle line_style(Series::Style s) {
  switch (s) {
    case Series::Style::Dashed: return LineStyle::Dashed;
    case Series::Style::Dotted: return LineStyle::Dotted;
    case Series::Style::Solid: break;
  }
  return LineStyle::Solid;
}

void draw_panel(const Panel& p, std::size_t index, ImVec2 size, bool interactive, std::optional<YRange> y) {
  PlotOptions opt;
  opt.title = p.title.empty() ? nullptr : p.title.c_str();  // none: no title line
  opt.letter = p.letter.empty() ? nullptr : p.letter.c_str();
  opt.paper = true;
  opt.interactive = interactive;
  ImGui::PushID(static_cast<int>(index));
  if (BeginPlot("##panel", size, opt)) {
    // "um" in the data's labels (ASCII, for CSV) is drawn as µm, as everywhere in the window.
    const std::string xl = micro_sign(p.x_label), yl = micro_sign(p.y_label);
    SetupAxes(xl.c_str(), yl.c_str());
    if (y) SetupFitRangeY(y->lo, y->hi);
    for (std::size_t k = 0; k < p.series.size(); ++k) {
      const Series& s = p.series[k];
      SeriesStyle st;
      st.color = s.color >= 0 ? s.color : static_cast<int>(k);
      st.line = line_style(s.style);
      st.thickness = 2.0f;
      st.x_sorted = std::is_sorted(s.x.begin(), s.x.end());
      PlotLine(s.label.c_str(), s.x.data(), s.y.data(), std::min(s.x.size(), s.y.size()), st);
    }
    EndPlot();
  }
  ImGui::PopID();
}
}  // namespace

std::optional<YRange> shared_y_range(const Figure& f) {
  if (!f.shared_y) return std::nullopt;
  YRange r{INFINITY, -INFINITY};
  for (const auto& p : f.panels)
    for (const auto& s : p.series)
      for (double v : s.y)
        if (std::isfinite(v)) r.lo = std::min(r.lo, v), r.hi = std::max(r.hi, v);
  if (!(r.hi >= r.lo)) return std::nullopt;
  return r;
}

void draw_figure(const Figure& f, bool interactive) {
  ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(0, 0, 0, 255));
  const ImVec2 title_pos = ImGui::GetCursorScreenPos();
  ImGui::TextUnformatted(f.title.c_str());
  // Bold by double-strike: the one font stays crisp at every size.
  ImGui::GetWindowDrawList()->AddText(ImVec2(title_pos.x + 1, title_pos.y), IM_COL32(0, 0, 0, 255),
                                      f.title.c_str());
  ImGui::PopStyleColor();
  ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(70, 70, 70, 255));
  TextWrappedAtSpaces(f.caption);
  ImGui::PopStyleColor();
  ImGui::Spacing();
  const std::size_t n = std::max<std::size_t>(1, f.panels.size());
  const std::optional<YRange> shared = shared_y_range(f);
  const float gap = ImGui::GetStyle().ItemSpacing.x;
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float w = (avail.x - gap * static_cast<float>(n - 1)) / static_cast<float>(n);
  for (std::size_t i = 0; i < f.panels.size(); ++i) {
    if (i > 0) ImGui::SameLine();
    draw_panel(f.panels[i], i, ImVec2(w, avail.y), interactive, shared);
  }
}

}  // namespace gmslab::ui
