#include "ui/param_editor.hpp"

#include "ui/text_wrap.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
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
                      "  (click to type; drag the <> handle or Alt+drag to change)");
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

namespace {
const ImVec4 kRejected(0.80f, 0.10f, 0.10f, 1.0f);

// The drag step per pixel of a linear field.
double linear_step(const ParamSpec& spec, double value, double reference) {
  const double span = std::isfinite(spec.hi - spec.lo) ? spec.hi - spec.lo : 1.0;
  const double scale = std::max({std::fabs(value), std::fabs(reference), 0.0});
  return std::max(scale * 0.005, std::min(span * 1e-4, 0.01));
}

// New value after dragging dx pixels from `start`.
double dragged(const ParamSpec& spec, double start, double dx, double reference) {
  if (spec.log_scale && start > 0.0) return start * std::pow(10.0, dx / 200.0);
  return start + dx * linear_step(spec, start, reference);
}
}  // namespace

bool edit_param(const char* id, const ParamSpec& spec, double& value, double reference, FieldMarks* marks) {
  ImGui::PushID(id);
  const ImGuiID field = ImGui::GetID("##field");
  const bool marked = marks && marks->rejected == field;
  const float handle_w = ImGui::GetFrameHeight() * 0.8f;
  const float spacing = 2.0f;
  const float full = ImGui::CalcItemWidth();
  double v = value;
  bool changed = false;
  if (marked) {
    ImGui::PushStyleColor(ImGuiCol_Border, kRejected);
    ImGui::PushStyleVar(ImGuiStyleVar_FrameBorderSize, 2.0f);
  }
  ImGui::SetNextItemWidth(std::max(full - handle_w - spacing, ImGui::GetFontSize() * 2.0f));
  // Typed: live while typing, as any field; Enter or clicking away ends the edit.
  const bool typed = ImGui::InputScalar("##field", ImGuiDataType_Double, &v, nullptr, nullptr, "%.6g",
                                        ImGuiInputTextFlags_CharsScientific);
  const bool typing_ended = ImGui::IsItemDeactivated();
  if (marked) {
    ImGui::PopStyleVar();
    ImGui::PopStyleColor();
  }
  spec_tooltip(spec);
  if (marks && typing_ended && marks->typing == field) {
    marks->rejected = field;
    marks->message = marks->typing_message;
    marks->typing = 0;
  }
  ImGuiStorage* st = ImGui::GetStateStorage();
  const ImGuiID start_key = ImGui::GetID("##dragstart");
  // Alt+drag on the field changes it continuously, like the handle.
  const bool alt_drag = ImGui::IsItemHovered() && ImGui::GetIO().KeyAlt && ImGui::IsMouseDragging(0, 0.0f);
  ImGui::SameLine(0.0f, spacing);
  ImGui::Button("##handle", ImVec2(handle_w, 0.0f));
  {  // a left-right arrow: drag me
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    const float cy = 0.5f * (a.y + b.y), h = 0.22f * (b.y - a.y), m = 0.5f * (a.x + b.x);
    const ImU32 col = ImGui::GetColorU32(ImGuiCol_Text);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->AddTriangleFilled(ImVec2(a.x + 2.0f, cy), ImVec2(m - 1.0f, cy - h), ImVec2(m - 1.0f, cy + h), col);
    dl->AddTriangleFilled(ImVec2(b.x - 2.0f, cy), ImVec2(m + 1.0f, cy - h), ImVec2(m + 1.0f, cy + h), col);
  }
  if (ImGui::IsItemHovered() && !ImGui::IsItemActive())
    ImGui::SetTooltip("drag left / right to change %s%s", display_symbol(spec.symbol).c_str(),
                      spec.log_scale ? " (logarithmic)" : "");
  const bool handle_drag = ImGui::IsItemActive();
  if (handle_drag || alt_drag) {
    // The value when the drag began, kept in ImGui's per-window storage (as a float pair would
    // lose digits: stored as the bit pattern split over two ints).
    if (ImGui::IsMouseClicked(0) || (handle_drag && ImGui::IsItemActivated()) || !st->GetBool(start_key + 2)) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &value, sizeof bits);
      st->SetInt(start_key, static_cast<int>(bits & 0xffffffffu));
      st->SetInt(start_key + 1, static_cast<int>(bits >> 32));
      st->SetBool(start_key + 2, true);
    }
    const std::uint64_t bits = static_cast<std::uint32_t>(st->GetInt(start_key)) |
                               (static_cast<std::uint64_t>(static_cast<std::uint32_t>(st->GetInt(start_key + 1))) << 32);
    double start = 0.0;
    std::memcpy(&start, &bits, sizeof start);
    const double dx = ImGui::GetMouseDragDelta(0, 0.0f).x;
    if (dx != 0.0) {
      v = dragged(spec, start, dx, reference);
      v = std::clamp(v, low_end(spec), spec.hi);
      changed = true;
    }
  } else if (st->GetBool(start_key + 2) && !ImGui::IsMouseDown(0)) {
    st->SetBool(start_key + 2, false);
  }
  if (typed && std::isfinite(v)) changed = true;
  if (marked) {
    ImGui::PushStyleColor(ImGuiCol_Text, kRejected);
    TextWrappedAtSpaces(marks->message);
    ImGui::PopStyleColor();
  }
  ImGui::PopID();
  if (!changed || !std::isfinite(v) || v == value) return false;
  if (marks) marks->last_edited = field;
  const bool in_range = spec.allowed(v);
  if (!in_range) {
    if (marks) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.6g", v);
      const std::string why = "rejected " + std::string(buf) + ": allowed " + spec.range_text();
      if (typed) {  // still typing ("0" on the way to "0.25"): judged when the typing ends
        marks->typing = field;
        marks->typing_message = why;
      } else {
        marks->rejected = field;
        marks->message = why;
      }
      return false;
    }
    v = std::clamp(v, low_end(spec), spec.hi);
    if (v == value) return false;
  }
  if (marks && marks->rejected == field) marks->clear();
  if (marks && marks->typing == field) marks->typing = 0;
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
bool edit_scalars(const ModelInfo& info, const ModelParams& defaults, ModelParams& p, FieldMarks* marks) {
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
    changed |= edit_param("##v", s, p.scalars[i], ref, marks);
    ImGui::PopID();
  }
  ImGui::EndTable();
  return changed;
}

bool edit_elements(const ModelInfo& info, const ModelParams& defaults, ModelParams& p,
                   const FrictionModel* live, std::span<const double> state, FieldMarks* marks) {
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
        changed |= edit_param("##v", info.columns[c], p.elements[r][c], ref, marks);
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
                       std::span<const double> live_state, FieldMarks* marks) {
  const ModelInfo& info = model_info(p.model);
  const ModelParams defaults = info.defaults();
  ImGui::PushID(id);
  bool changed = edit_scalars(info, defaults, p, marks);
  changed |= edit_elements(info, defaults, p, live, live_state, marks);
  ImGui::PopID();
  return changed;
}

}  // namespace gmslab::ui
