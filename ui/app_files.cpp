#include "ui/app_files.hpp"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "ui/popups.hpp"

namespace gmslab::ui {

namespace fs = std::filesystem;

std::string user_scenarios_dir() {
  if (const char* d = std::getenv("GMSLAB_USER_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x) return std::string(x) + "/gmslab/scenarios";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : ".") + "/.config/gmslab/scenarios";
}

namespace {
// Absolute, normalised, symlinks resolved where the path exists (so "presets/../presets/x" and a
// link into the presets folder are both recognised).
fs::path canonical_or_absolute(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  if (ec) c = fs::absolute(p, ec).lexically_normal();
  return c;
}

std::string file_stem_for(const AppState& s) {
  if (!s.scenario_path.empty()) return fs::path(s.scenario_path).stem().string();
  std::string out;
  for (char c : s.scenario.name)
    out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return out.empty() ? "scenario" : out;
}
}  // namespace

bool is_shipped_preset(const std::string& path) {
  if (path.empty()) return false;
  const fs::path dir = canonical_or_absolute(presets_dir());
  const fs::path file = canonical_or_absolute(path);
  const auto rel = file.lexically_relative(dir);
  return !rel.empty() && *rel.begin() != "..";
}

std::string save_target(const AppState& s) {
  if (!s.scenario_path.empty() && !is_shipped_preset(s.scenario_path)) return s.scenario_path;
  return (fs::path(user_scenarios_dir()) / (file_stem_for(s) + ".json")).string();
}

bool has_unsaved_changes(const AppState& s) {
  return !(s.scenario == s.clean_scenario) || s.scenario_path != s.clean_path;
}

std::string window_title(const AppState& s) {
  // The Plant tab shows its own assembled preset, not the scenario of the other tabs, and so does
  // the Design tab when it designs on that plant: the title names what is shown.
  const bool shows_plant =
      s.view.tab == "Plant" ||
      (s.view.tab == "Design" && s.design.settings.plant.source == control::PlantSource::Assembly);
  if (shows_plant && s.plant.scenario) {
    std::string t = "gmslab - " + (s.plant.scenario->name.empty() ? std::string("untitled plant") : s.plant.scenario->name);
    if (!s.plant.path.empty()) t += "  (" + s.plant.path + ")";
    return t;
  }
  std::string t = "gmslab - " + (s.scenario.name.empty() ? std::string("untitled") : s.scenario.name);
  if (has_unsaved_changes(s)) t += " *";
  if (!s.scenario_path.empty()) t += "  (" + s.scenario_path + ")";
  return t;
}

EditSnapshot snapshot(const AppState& s) { return {s.scenario, s.scenario_path, s.compare}; }

void record_edit(AppState& s) {
  auto& h = s.history;
  EditSnapshot now = snapshot(s);
  if (h.undo.empty() || !(h.undo.back() == now)) h.undo.push_back(std::move(now));
  if (h.undo.size() > EditHistory::kMaxSteps) h.undo.erase(h.undo.begin());
  h.redo.clear();
}

namespace {
// Requests that bring the state to `t` (applied by apply_pending like any edit).
void request_state(AppState& s, const EditSnapshot& t) {
  PendingRequests& p = s.pending;
  s.scenario_path = t.scenario_path;
  const Scenario& now = s.scenario;
  if (!(t.scenario.drive == now.drive) || !(t.scenario.run == now.run) || t.scenario.name != now.name ||
      t.scenario.description != now.description || t.scenario.friction.model != now.friction.model) {
    p.scenario = t.scenario;
  } else {
    if (!(t.scenario.friction == now.friction)) p.friction = t.scenario.friction;
    if (!(t.scenario.plant == now.plant)) p.plant = t.scenario.plant;
  }
  if (t.compare != s.compare) {
    if (t.compare) p.compare = *t.compare;
    else p.clear_compare = true;
  }
  p.from_history = true;
  ++s.generation;  // the editors show the restored values
}
}  // namespace

bool undo(AppState& s) {
  auto& h = s.history;
  if (h.undo.empty()) return false;
  const EditSnapshot t = h.undo.back();
  h.undo.pop_back();
  h.redo.push_back(snapshot(s));
  request_state(s, t);
  s.note("undone (Ctrl+Shift+Z or Ctrl+Y redoes)");
  return true;
}

bool redo(AppState& s) {
  auto& h = s.history;
  if (h.redo.empty()) return false;
  const EditSnapshot t = h.redo.back();
  h.redo.pop_back();
  h.undo.push_back(snapshot(s));
  request_state(s, t);
  s.note("redone");
  return true;
}

namespace {
bool pressed(int key) { return key >= 0 && ImGui::IsKeyPressed(key, false); }

void open_browser(AppState& s, bool saving) {
  auto& b = s.browser;
  b.open_request = true;
  b.saving = saving;
  b.error.clear();
  const std::string target = save_target(s);
  if (saving) {
    b.dir = fs::path(target).parent_path().string();
    b.name = fs::path(target).filename().string();
  } else {
    b.dir = s.scenario_path.empty() ? presets_dir() : fs::path(s.scenario_path).parent_path().string();
    b.name.clear();
  }
  if (b.dir.empty()) b.dir = ".";
}

void request_save(AppState& s) { s.pending.save_path = save_target(s); }
}  // namespace

void handle_shortcuts(AppState& s) {
  if (close_popup_on_escape()) return;  // Escape closed a menu: it does nothing else
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput) return;  // typing: keys belong to the field
  const bool ctrl = io.KeyCtrl;
  if (pressed(ImGui::GetKeyIndex(ImGuiKey_Space)) && !ctrl) {
    if (s.running) s.pending.pause = true;
    else s.pending.run = true;
  }
  if (ctrl && pressed(s.keys.s)) {
    if (io.KeyShift) open_browser(s, true);
    else request_save(s);
  }
  if (ctrl && pressed(ImGui::GetKeyIndex(ImGuiKey_Z))) {
    if (io.KeyShift) s.pending.redo = true;
    else s.pending.undo = true;
  }
  if (ctrl && pressed(ImGui::GetKeyIndex(ImGuiKey_Y))) s.pending.redo = true;
  if (pressed(s.keys.f5)) s.pending.rerun = true;
}

namespace {
// "Fig. 2A..." -> {2, 'A'}; "Fig. 4 ..." -> {4, ' '}; no figure: {INT_MAX, ' '}.
std::pair<int, char> figure_of(const std::string& name) {
  int fig = 0;
  char panel = ' ';
  int used = 0;
  if (std::sscanf(name.c_str(), "Fig. %d%n", &fig, &used) == 1 && used > 0) {
    const char c = static_cast<std::size_t>(used) < name.size() ? name[static_cast<std::size_t>(used)] : ' ';
    if (c >= 'A' && c <= 'Z') panel = c;
    return {fig, panel};
  }
  return {INT_MAX, ' '};
}

// Natural order: runs of digits compare as numbers.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i])), db = std::isdigit(static_cast<unsigned char>(b[j]));
    if (da && db) {
      std::size_t i2 = i, j2 = j;
      while (i2 < a.size() && std::isdigit(static_cast<unsigned char>(a[i2]))) ++i2;
      while (j2 < b.size() && std::isdigit(static_cast<unsigned char>(b[j2]))) ++j2;
      const std::string na = a.substr(i, i2 - i), nb = b.substr(j, j2 - j);
      const std::string ta = na.substr(std::min(na.find_first_not_of('0'), na.size() - 1));
      const std::string tb = nb.substr(std::min(nb.find_first_not_of('0'), nb.size() - 1));
      if (ta.size() != tb.size()) return ta.size() < tb.size();
      if (ta != tb) return ta < tb;
      i = i2, j = j2;
      continue;
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i, ++j;
  }
  return a.size() - i < b.size() - j;
}
}  // namespace

bool preset_before(const PresetEntry& a, const PresetEntry& b) {
  const auto fa = figure_of(a.name), fb = figure_of(b.name);
  if (fa != fb) return fa < fb;
  if (fa.first == INT_MAX && a.name != b.name) return natural_less(a.name, b.name);
  const bool ca = a.name.find("protocol") != std::string::npos, cb = b.name.find("protocol") != std::string::npos;
  if (ca != cb) return cb;
  const std::string sa = fs::path(a.path).stem().string(), sb = fs::path(b.path).stem().string();
  if (sa != sb) return natural_less(sa, sb);
  return a.path < b.path;
}

std::vector<PresetEntry> list_presets() {
  std::vector<PresetEntry> out;
  for (const bool shipped : {true, false}) {
    const std::string dir = shipped ? presets_dir() : user_scenarios_dir();
    std::vector<PresetEntry> found;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->path().extension() != ".json") continue;
      PresetEntry e{it->path().string(), it->path().stem().string(), "", shipped};
      try {
        std::ifstream in(it->path());
        const auto j = nlohmann::json::parse(in);
        if (j.contains("name") && j["name"].is_string()) e.name = j["name"].get<std::string>();
        if (j.contains("description") && j["description"].is_string())
          e.description = j["description"].get<std::string>();
        e.plant = j.contains("schema_version") && j["schema_version"] == 2;
      } catch (const std::exception& x) {
        e.description = std::string("not readable: ") + x.what();
      }
      found.push_back(std::move(e));
    }
    std::sort(found.begin(), found.end(), preset_before);
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

namespace {
void preset_items(AppState& s, bool shipped) {
  bool any = false;
  for (const PresetEntry& e : list_presets()) {
    if (e.shipped != shipped) continue;
    any = true;
    const std::string label = e.plant ? e.name + "  (plant)" : e.name;
    if (ImGui::MenuItem(label.c_str(), nullptr, e.path == s.scenario_path)) s.pending.load_path = e.path;
    if (ImGui::IsItemHovered()) {
      ImGui::BeginTooltip();
      ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
      if (!e.description.empty()) ImGui::TextUnformatted(e.description.c_str());
      ImGui::TextDisabled("%s", e.path.c_str());
      ImGui::PopTextWrapPos();
      ImGui::EndTooltip();
    }
  }
  if (!any) ImGui::TextDisabled(shipped ? "(none found in %s)" : "(none yet: saves go to %s)",
                                (shipped ? presets_dir() : user_scenarios_dir()).c_str());
}
}  // namespace

void draw_menu_bar(AppState& s) {
  if (!ImGui::BeginMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("Open...")) open_browser(s, false);
    if (ImGui::MenuItem("Save", "Ctrl+S")) request_save(s);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Saves to %s", save_target(s).c_str());
    if (ImGui::MenuItem("Save as...", "Ctrl+Shift+S")) open_browser(s, true);
    ImGui::Separator();
    ImGui::TextDisabled("Shipped presets are never overwritten;");
    ImGui::TextDisabled("saves go to %s", user_scenarios_dir().c_str());
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Presets")) {
    ImGui::TextDisabled("Shipped");
    preset_items(s, true);
    ImGui::Separator();
    ImGui::TextDisabled("Yours");
    preset_items(s, false);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    if (ImGui::MenuItem("Undo", "Ctrl+Z", false, !s.history.undo.empty())) s.pending.undo = true;
    if (ImGui::MenuItem("Redo", "Ctrl+Shift+Z / Ctrl+Y", false, !s.history.redo.empty())) s.pending.redo = true;
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Run")) {
    if (ImGui::MenuItem(s.running ? "Pause" : "Run", "Space")) (s.running ? s.pending.pause : s.pending.run) = true;
    if (ImGui::MenuItem("Rerun from t = 0", "F5")) s.pending.rerun = true;
    if (ImGui::MenuItem("Reset")) s.pending.reset = true;
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Help")) {
    ImGui::TextDisabled("Keyboard shortcuts");
    ImGui::MenuItem("Run / pause", "Space", false, false);
    ImGui::MenuItem("Rerun from t = 0", "F5", false, false);
    ImGui::MenuItem("Save", "Ctrl+S", false, false);
    ImGui::MenuItem("Save as", "Ctrl+Shift+S", false, false);
    ImGui::MenuItem("Undo", "Ctrl+Z", false, false);
    ImGui::MenuItem("Redo", "Ctrl+Shift+Z, Ctrl+Y", false, false);
    ImGui::Separator();
    ImGui::TextDisabled("Fields: click to type; drag the handle to the right of a field");
    ImGui::TextDisabled("(or Alt+drag on the field) to change the value continuously.");
    ImGui::TextDisabled("Plots: right-click for export (PNG, SVG, CSV).");
    ImGui::EndMenu();
  }
  // Unsaved changes, on the right of the menu bar (the window title shows them too).
  const std::string title = window_title(s);
  const float w = ImGui::CalcTextSize(title.c_str()).x;
  const float x = ImGui::GetWindowContentRegionMax().x - w;
  if (x > ImGui::GetCursorPosX()) {
    ImGui::SetCursorPosX(x);
    ImGui::TextDisabled("%s", title.c_str());
  }
  ImGui::EndMenuBar();
}

void draw_file_dialogs(AppState& s) {
  auto& b = s.browser;
  if (b.open_request) {
    ImGui::OpenPopup("##filebrowser");
    b.open_request = false;
  }
  const ImVec2 size(ImGui::GetFontSize() * 36.0f, ImGui::GetFontSize() * 24.0f);
  ImGui::SetNextWindowSize(size, ImGuiCond_Appearing);
  if (ImGui::BeginPopupModal("##filebrowser", nullptr, ImGuiWindowFlags_NoSavedSettings)) {
    ImGui::TextUnformatted(b.saving ? "Save the scenario as" : "Open a scenario");
    if (ImGui::Button("Up")) b.dir = fs::path(b.dir).lexically_normal().parent_path().string();
    ImGui::SameLine();
    if (ImGui::Button("Presets")) b.dir = presets_dir();
    ImGui::SameLine();
    if (ImGui::Button("Mine")) b.dir = user_scenarios_dir();
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    ImGui::InputText("##dir", &b.dir);
    std::vector<fs::directory_entry> entries;
    std::error_code ec;
    for (fs::directory_iterator it(b.dir, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_directory() || it->path().extension() == ".json") entries.push_back(*it);
    b.error = ec ? "cannot list " + b.dir + ": " + ec.message() : "";
    std::sort(entries.begin(), entries.end(), [](const auto& x, const auto& y) {
      return x.is_directory() != y.is_directory() ? x.is_directory() : x.path() < y.path();
    });
    const float foot = ImGui::GetFrameHeightWithSpacing() * 2.0f + ImGui::GetTextLineHeightWithSpacing();
    bool go = false;
    ImGui::BeginChild("##entries", ImVec2(0, -foot), true);
    for (const auto& e : entries) {
      const std::string n = e.path().filename().string() + (e.is_directory() ? "/" : "");
      if (ImGui::Selectable(n.c_str(), !e.is_directory() && n == b.name, ImGuiSelectableFlags_AllowDoubleClick)) {
        if (e.is_directory()) {
          b.dir = e.path().string();
        } else {
          b.name = n;
          go = ImGui::IsMouseDoubleClicked(0);
        }
      }
    }
    ImGui::EndChild();
    if (!b.error.empty()) ImGui::TextColored(ImVec4(0.75f, 0.1f, 0.1f, 1), "%s", b.error.c_str());
    else if (b.saving && is_shipped_preset((fs::path(b.dir) / "x.json").string()))
      ImGui::TextColored(ImVec4(0.75f, 0.1f, 0.1f, 1), "shipped presets folder: pick another folder");
    else
      ImGui::TextDisabled("%s", b.saving ? "an existing file is replaced only after you confirm" : "");
    ImGui::SetNextItemWidth(-ImGui::GetFontSize() * 10.0f);
    go |= ImGui::InputTextWithHint("##name", "file name (.json)", &b.name, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if (ImGui::Button(b.saving ? "Save" : "Open")) go = true;
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || escape_cancels_popup()) ImGui::CloseCurrentPopup();
    if (go && !b.name.empty()) {
      std::string name = b.name;
      if (fs::path(name).extension() != ".json") name += ".json";
      const std::string path = (fs::path(b.dir) / name).string();
      if (b.saving) s.pending.save_path = path;
      else s.pending.load_path = path;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }

  if (!s.confirm_replace.empty() && !ImGui::IsPopupOpen("Replace file?")) ImGui::OpenPopup("Replace file?");
  if (ImGui::BeginPopupModal("Replace file?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("%s already exists.", s.confirm_replace.c_str());
    ImGui::TextUnformatted("Replace it with the scenario as edited?");
    if (ImGui::Button("Replace")) {
      s.pending.save_path = s.confirm_replace;
      s.pending.save_confirmed = true;
      s.confirm_replace.clear();
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || escape_cancels_popup()) {
      s.confirm_replace.clear();
      s.note("not saved");
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
}

}  // namespace gmslab::ui
