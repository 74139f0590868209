// gmslab ui: the Figures panel: pick one of the paper's figures (core/figures/figure_set.hpp),
// recompute it from its presets and draw it like the paper (the same drawing as `gmslab figures`).
#include <imgui.h>

#include "core/figures/figure_set.hpp"
#include "ui/figures/figure_export.hpp"
#include "ui/figures/figure_view.hpp"
#include "ui/plot/plot.hpp"
#include "ui/figures/panel_figures.hpp"

namespace gmslab::ui {


void draw_figures_panel(FiguresState& f, const std::string& presets) {
  const auto ids = figure_ids();
  if (f.id.empty() && !ids.empty()) f.id = ids.front();
  std::string pick;
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 18.0f);
  if (ImGui::BeginCombo("figure id", f.id.c_str())) {
    for (const auto& id : ids)
      if (ImGui::Selectable(id.c_str(), id == f.id)) pick = id;
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Figures of the seed paper, recomputed from the presets in %s", presets.c_str());
  if (!pick.empty() && pick != f.id) {
    f.id = pick;
    f.figure = {};
  }
  if (f.figure.id != f.id && f.error.empty()) {
    try {
      f.figure = make_figure(f.id, presets);
    } catch (const std::exception& e) {
      f.error = e.what();
      f.error_kind = error_kind_of(e);
    }
  }
  if (!pick.empty()) f.error.clear();
  if (!f.error.empty()) {
    ImGui::TextColored(ImVec4(0.75f, 0.1f, 0.1f, 1), "%s", f.error.c_str());
    return;
  }
  // Export the figure shown (the same data as `gmslab figures`), into export_dir().
  ImGui::SameLine();
  ImGui::TextUnformatted("export:");
  const struct { const char* label; ExportFormat format; } kinds[] = {
      {"PNG", ExportFormat::Png}, {"SVG", ExportFormat::Svg}, {"CSV", ExportFormat::Csv}};
  for (const auto& k : kinds) {
    ImGui::SameLine();
    ImGui::BeginDisabled(k.format == ExportFormat::Png && !GetPlotPngWriter());
    if (ImGui::SmallButton(k.label)) PostPlotMessage(export_figure(f.figure, k.format, GetPlotPngWriter()));
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
      ImGui::SetTooltip("Write this figure as %s into %s (never over an existing file)", k.label, export_dir().c_str());
  }
  ImGui::BeginChild("##figure", ImVec2(0, 0), true, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  draw_figure(f.figure, true);
  ImGui::EndChild();
}

}  // namespace gmslab::ui
