#include "ui/param_editor.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace gmslab::ui {

namespace {
bool font_has(ImWchar c) { return ImGui::GetFont()->FindGlyphNoFallback(c) != nullptr; }

void spec_tooltip(const ParamSpec& s) {
  if (!ImGui::IsItemHovered()) return;
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 28.0f);
  ImGui::Text("%s (%s, key \"%.*s\")", display_symbol(s.symbol).c_str(),
              s.unit == "-" ? "dimensionless" : std::string(s.unit).c_str(),
              static_cast<int>(s.key.size()), s.key.data());
  ImGui::TextUnformatted(s.help.data(), s.help.data() + s.help.size());
  ImGui::TextDisabled("allowed: %s%s", s.range_text().c_str(),
                      s.log_scale ? "  (log slider; Ctrl+click to type)" : "  (drag, or double-click to type)");
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

// Smallest allowed value to use as a slider end.
double low_end(const ParamSpec& s) {
  if (!s.lo_open) return s.lo;
  return s.lo == 0.0 ? std::min(1e-12, s.hi) : std::nextafter(s.lo, s.hi);
}
}  // namespace

std::string display_symbol(std::string_view symbol) {
  static const struct { const char* name; const char* utf8; ImWchar code; } greek[] = {
      {"alpha", "\xCE\xB1", 0x03B1}, {"sigma", "\xCF\x83", 0x03C3}, {"delta", "\xCE\xB4", 0x03B4},
      {"mu", "\xCE\xBC", 0x03BC},    {"tau", "\xCF\x84", 0x03C4},   {"omega", "\xCF\x89", 0x03C9},
      {"zeta", "\xCE\xB6", 0x03B6},  {"beta", "\xCE\xB2", 0x03B2},  {"gamma", "\xCE\xB3", 0x03B3},
      {"lambda", "\xCE\xBB", 0x03BB}, {"theta", "\xCE\xB8", 0x03B8}};
  std::string s(symbol);
  if (ImGui::GetCurrentContext() == nullptr) return s;
  for (const auto& g : greek) {
    const std::size_t n = std::char_traits<char>::length(g.name);
    if (s.compare(0, n, g.name) == 0 && (s.size() == n || s[n] == '_' || std::isdigit(static_cast<unsigned char>(s[n]))) &&
        font_has(g.code))
      return g.utf8 + s.substr(n);
  }
  return s;
}

std::string field_label(const ParamSpec& s) {
  return display_symbol(s.symbol) + " [" + std::string(s.unit) + "]";
}

bool edit_param(const char* id, const ParamSpec& spec, double& value, double reference) {
  double v = value;
  bool changed = false;
  if (spec.log_scale && spec.hi > 0.0) {
    const double ref = reference > 0.0 ? reference : (value > 0.0 ? value : 1.0);
    double lo = std::max(low_end(spec), ref * 1e-3), hi = std::min(spec.hi, ref * 1e3);
    if (!(hi > lo)) lo = low_end(spec), hi = spec.hi;
    changed = ImGui::SliderScalar(id, ImGuiDataType_Double, &v, &lo, &hi, "%.5g",
                                  ImGuiSliderFlags_Logarithmic);
  } else {
    const double span = std::isfinite(spec.hi - spec.lo) ? spec.hi - spec.lo : 1.0;
    const float speed = static_cast<float>(std::max(std::fabs(v) * 0.005, std::min(span * 1e-4, 0.01)));
    double lo = low_end(spec), hi = spec.hi;
    changed = ImGui::DragScalar(id, ImGuiDataType_Double, &v, speed, &lo, &hi, "%.5g");
  }
  spec_tooltip(spec);
  if (!changed || !std::isfinite(v)) return false;
  v = std::clamp(v, low_end(spec), spec.hi);
  if (v == value) return false;
  value = v;
  return true;
}

bool edit_model_choice(const char* label, ModelParams& p) {
  const auto& reg = model_registry();
  const ModelInfo* cur = nullptr;
  for (const auto& m : reg)
    if (m.tag == p.model) cur = &m;
  bool changed = false;
  const std::string preview = cur ? std::string(cur->name) : p.model;
  if (ImGui::BeginCombo(label, preview.c_str())) {
    for (const auto& m : reg) {
      const std::string name(m.name);
      if (ImGui::Selectable(name.c_str(), cur == &m) && cur != &m) {
        p = m.defaults();
        changed = true;
      }
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%.*s\n%.*s", static_cast<int>(m.citation.size()), m.citation.data(),
                          static_cast<int>(m.equation.size()), m.equation.data());
    }
    ImGui::EndCombo();
  }
  if (cur && ImGui::IsItemHovered()) {
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 32.0f);
    ImGui::TextUnformatted(cur->citation.data(), cur->citation.data() + cur->citation.size());
    ImGui::TextUnformatted(cur->equation.data(), cur->equation.data() + cur->equation.size());
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
  }
  return changed;
}

namespace {
bool edit_scalars(const ModelInfo& info, const ModelParams& defaults, ModelParams& p) {
  bool changed = false;
  if (!ImGui::BeginTable("##scalars", 2, ImGuiTableFlags_SizingStretchProp)) return false;
  ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFontSize() * 7.5f);
  ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch);
  for (std::size_t i = 0; i < info.scalars.size() && i < p.scalars.size(); ++i) {
    const ParamSpec& s = info.scalars[i];
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted(field_label(s).c_str());
    spec_tooltip(s);
    ImGui::TableNextColumn();
    ImGui::SetNextItemWidth(-1);
    ImGui::PushID(static_cast<int>(i));
    const double ref = i < defaults.scalars.size() ? defaults.scalars[i] : 0.0;
    changed |= edit_param("##v", s, p.scalars[i], ref);
    ImGui::PopID();
  }
  ImGui::EndTable();
  return changed;
}

bool edit_elements(const ModelInfo& info, const ModelParams& defaults, ModelParams& p,
                   const FrictionModel* live, std::span<const double> state) {
  if (info.columns.empty()) return false;
  bool changed = false;
  const bool show_live = live && live->element_count() == p.elements.size();
  const int ncol = static_cast<int>(info.columns.size()) + 1 + (show_live ? 2 : 0);
  ImGui::Text("Elements (%zu, allowed %zu to %zu)", p.elements.size(), info.min_elements,
              info.max_elements);
  const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                                ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_ScrollY;
  const float row_h = ImGui::GetFrameHeight() + 2.0f * ImGui::GetStyle().CellPadding.y;
  const float rows_h = row_h * static_cast<float>(std::min<std::size_t>(p.elements.size() + 1, 9));
  if (!ImGui::BeginTable("##elements", ncol, flags, ImVec2(0, rows_h + 4))) return false;
  ImGui::TableSetupScrollFreeze(0, 1);
  ImGui::TableSetupColumn("i", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFontSize() * 1.6f);
  std::vector<std::string> heads;
  for (const auto& c : info.columns) heads.push_back(field_label(c));
  for (const auto& h : heads) ImGui::TableSetupColumn(h.c_str(), ImGuiTableColumnFlags_WidthStretch, 1.0f);
  if (show_live) {
    ImGui::TableSetupColumn("F_i [N]", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFontSize() * 4.5f);
    ImGui::TableSetupColumn("state", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFontSize() * 2.8f);
  }
  ImGui::TableHeadersRow();
  std::ptrdiff_t remove = -1;
  // Only the visible rows are drawn (models may have thousands of elements).
  ImGuiListClipper clipper;
  clipper.Begin(static_cast<int>(p.elements.size()));
  while (clipper.Step())
    for (std::size_t r = static_cast<std::size_t>(clipper.DisplayStart); r < static_cast<std::size_t>(clipper.DisplayEnd); ++r) {
      ImGui::PushID(static_cast<int>(r));
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::AlignTextToFramePadding();
      ImGui::Text("%zu", r + 1);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("element %zu: right-click to remove", r + 1);
      if (ImGui::BeginPopupContextItem("##row") ) {
        if (ImGui::MenuItem("Remove this element", nullptr, false, p.elements.size() > info.min_elements))
          remove = static_cast<std::ptrdiff_t>(r);
        ImGui::EndPopup();
      }
      for (std::size_t c = 0; c < info.columns.size(); ++c) {
        ImGui::TableNextColumn();
        ImGui::SetNextItemWidth(-1);
        ImGui::PushID(static_cast<int>(c));
        const double ref = defaults.elements.empty() ? 0.0 : defaults.elements[0][c];
        changed |= edit_param("##v", info.columns[c], p.elements[r][c], ref);
        ImGui::PopID();
      }
      if (show_live) {
        const ElementState e = live->element(state, r);
        ImGui::TableNextColumn();
        ImGui::AlignTextToFramePadding();
        ImGui::Text("%+.4f", e.force);
        ImGui::TableNextColumn();
        ImGui::TextColored(e.slipping ? ImVec4(0.84f, 0.37f, 0.0f, 1) : ImVec4(0.0f, 0.45f, 0.70f, 1),
                           e.slipping ? "slip" : "stick");
      }
      ImGui::PopID();
    }
  ImGui::EndTable();
  if (remove >= 0) {
    p.elements.erase(p.elements.begin() + remove);
    changed = true;
  }
  ImGui::BeginDisabled(p.elements.size() >= info.max_elements);
  if (ImGui::Button("+ element")) {
    p.elements.push_back(p.elements.empty() ? defaults.elements.at(0) : p.elements.back());
    changed = true;
  }
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("Append an element (a copy of the last row)");
  ImGui::SameLine();
  ImGui::BeginDisabled(p.elements.size() <= info.min_elements);
  if (ImGui::Button("- element")) {
    p.elements.pop_back();
    changed = true;
  }
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("Remove the last element (right-click a row number to remove that row)");
  return changed;
}
}  // namespace

bool edit_model_params(const char* id, ModelParams& p, const FrictionModel* live,
                       std::span<const double> live_state) {
  const ModelInfo& info = model_info(p.model);
  const ModelParams defaults = info.defaults();
  ImGui::PushID(id);
  bool changed = edit_scalars(info, defaults, p);
  changed |= edit_elements(info, defaults, p, live, live_state);
  ImGui::PopID();
  return changed;
}

}  // namespace gmslab::ui
