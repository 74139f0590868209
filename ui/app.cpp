#include "ui/app.hpp"

#include <imgui.h>
#include <strings.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"
#include "ui/app_files.hpp"
#include "ui/design/design_view.hpp"
#include "ui/identify/identify_panel.hpp"
#include "ui/panels.hpp"
#include "ui/plant/plant_view.hpp"
#include "ui/plot/plot.hpp"

namespace gmslab::ui {

std::span<const std::uint8_t> LiveRun::phases(double slip_velocity) {
  if (!sim) return {};
  return phase_series.update(sim->one_body_trace(), slip_velocity);
}

namespace {
Scenario with_friction(Scenario sc, const ModelParams& p) {
  sc.friction = p;
  return sc;
}

void rebuild_overlay(AppState& s) {
  s.overlay = {};
  if (!s.compare) return;
  s.overlay.sim = std::make_unique<AssemblySimulation>(
      one_body_simulation(with_friction(*s.main.sim->one_body(), *s.compare),
                          TraceOptions{.max_bytes = s.history_bytes}));
  // Catch up with the main run so both show the same stretch of input.
  const double t = s.main.sim->time();
  while (!s.overlay.sim->finished() && s.overlay.sim->time() + 0.5 * s.scenario.run.dt < t)
    s.overlay.sim->advance(std::min<std::size_t>(
        1u << 16, static_cast<std::size_t>(std::llround((t - s.overlay.sim->time()) / s.scenario.run.dt))));
}

void stop_with(AppState& s, const std::string& who, const SimulationError& e) {
  s.running = false;
  s.report(Panel::Simulation, e, who);
}

// Each request in its own function; errors become messages, never exceptions.
void apply_load(AppState& s, const std::string& path) {
  try {
    const Preset preset = load_preset(path);
    if (preset.assembled()) {
      // An assembled plant (schema 2): it opens in the Plant tab; the scenario stays as it is.
      load_plant(s.plant, preset.scenario, path);
      s.view.tab = "Plant";
      s.select_tab = 2;
      s.note("loaded " + path + " into the Plant tab");
      return;
    }
    load_scenario_into(s, preset.one_body(), path);
    mark_clean(s);
    s.note("loaded " + path);
  } catch (const std::exception& e) {
    s.report(Panel::Simulation, e, "load failed");
  }
}

// Never writes a shipped preset; asks (s.confirm_replace) before replacing any other file than
// the one this window saved last.
void apply_save(AppState& s, const std::string& path, bool confirmed) {
  try {
    if (is_shipped_preset(path))
      throw InputError("'" + path + "' is a shipped preset and is never overwritten; Save writes to " +
                       user_scenarios_dir() + " (or pick a path with File > Save as...)");
    if (!confirmed && path != s.last_saved_path && std::filesystem::exists(path)) {
      s.confirm_replace = path;
      return;
    }
    const auto parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    if (ec) throw IoError("cannot create the folder " + parent.string() + ": " + ec.message());
    save_scenario(s.scenario, path);
    s.scenario_path = path;
    s.last_saved_path = path;
    s.sim_panel.path = path;
    mark_clean(s);
    s.note("saved " + path);
  } catch (const std::exception& e) {
    s.report(Panel::Simulation, e, "save failed");
  }
}

void apply_compare(AppState& s, const ModelParams& p) {
  try {
    const bool same_kind = s.compare && s.compare->model == p.model && s.overlay.sim;
    s.compare = p;
    if (same_kind)
      s.overlay.sim->set_friction(p);
    else
      rebuild_overlay(s);
  } catch (const InputError& e) {
    s.report(Panel::Simulation, e, "overlay model rejected");
  } catch (const SimulationError& e) {
    stop_with(s, "overlay model", e);
  }
}
}  // namespace

void AppState::report(Panel p, ErrorKind k, const std::string& what) {
  const std::string text = std::string(error_label(k)) + ": " + what;
  switch (p) {
    case Panel::Simulation: error = text; break;
    case Panel::Figures: figures.error = text, figures.error_kind = k; break;
    case Panel::Design: design.out.error = text, design.out.error_kind = k; break;
    case Panel::Identify: identify.error = text, identify.error_kind = k; break;
  }
  on_status_[static_cast<int>(p)] = text;
  status = std::string(to_string(p)) + ": " + text;
  status_kind = k;
  status_panel = p;
}

void AppState::report(Panel p, const std::exception& e, const std::string& context) {
  report(p, error_kind_of(e), context.empty() ? std::string(e.what()) : context + ": " + e.what());
}

void AppState::note(const std::string& text) {
  status = text;
  status_kind.reset();
  status_panel.reset();
}

void AppState::clear_error(Panel p) {
  switch (p) {
    case Panel::Simulation: error.clear(); break;
    case Panel::Figures: figures.error.clear(); break;
    case Panel::Design: design.out.error.clear(), design.out.error_kind.reset(); break;
    case Panel::Identify: identify.error.clear(); break;
  }
  forward_error(p);
}

void AppState::forward_error(Panel p) {
  std::string text;
  ErrorKind kind = ErrorKind::Internal;
  switch (p) {
    case Panel::Simulation: text = error, kind = status_kind.value_or(ErrorKind::Input); break;
    case Panel::Figures: text = figures.error, kind = figures.error_kind; break;
    case Panel::Design:
      text = design.out.error, kind = design.out.error_kind.value_or(ErrorKind::Internal);
      break;
    case Panel::Identify:
      // The run's error, else why the records could not be loaded.
      if (!identify.error.empty()) text = identify.error, kind = identify.error_kind;
      else text = identify.preview.error, kind = identify.preview.error_kind;
      break;
  }
  std::string& shown = on_status_[static_cast<int>(p)];
  if (text == shown) return;
  shown = text;
  if (!text.empty()) {
    status = std::string(to_string(p)) + ": " + text;
    status_kind = kind;
    status_panel = p;
  } else if (status_panel == p) {
    note("");
  }
}

std::string presets_dir() { return gmslab::presets_dir(); }

void load_scenario_into(AppState& s, const Scenario& sc, const std::string& path) {
  // Validates before anything changes.
  auto sim = std::make_unique<AssemblySimulation>(
      one_body_simulation(sc, TraceOptions{.max_bytes = s.history_bytes}));
  ++s.generation;
  s.scenario = sc;
  s.scenario_path = path;
  s.main = {};
  s.main.sim = std::move(sim);
  s.running = false;
  s.clear_error(Panel::Simulation);
  if (s.compare) {
    try {
      rebuild_overlay(s);
    } catch (const std::exception& e) {
      s.compare.reset();
      s.overlay = {};
      s.report(Panel::Simulation, e, "overlay removed");
    }
  }
}

Session make_session(const AppState& s) {
  Session out{s.scenario_path, s.scenario, s.compare, s.view, {}, {}, {}};
  out.design = design_settings(s.design);
  out.identify = identify_settings(s.identify);
  if (s.plant.scenario) out.plant = plant_tab_settings(s.plant);
  return out;
}

void restore_session(AppState& s, const Session& session) {
  if (session.compare) build_model(*session.compare);  // validate before changing anything
  load_scenario_into(s, session.scenario, session.scenario_path);
  s.view = session.view;
  apply_design_settings(s.design, session.design);
  apply_identify_settings(s.identify, session.identify);
  if (session.plant) {
    apply_plant_tab_settings(s.plant, *session.plant);
  } else {
    s.plant = PlantPanelState{};
  }
  s.select_tab = 2;
  if (session.compare) apply_compare(s, *session.compare);
  // Unsaved changes are judged against the file the session's scenario came from.
  s.clean_path = s.scenario_path;
  try {
    s.clean_scenario = s.scenario_path.empty() ? Scenario{} : load_scenario(s.scenario_path);
  } catch (const std::exception&) {
    s.clean_scenario = Scenario{};
  }
}

void apply_pending(AppState& s) {
  // An undo / redo turns into the requests that restore the recorded state.
  if (s.pending.undo) s.pending.undo = false, undo(s);
  if (s.pending.redo) s.pending.redo = false, redo(s);
  PendingRequests p = std::move(s.pending);
  s.pending = {};
  // A note on the status line is about the last action: a new one replaces it (errors stay until
  // their panel clears them). The requests below set their own notes.
  const bool any_request = p.scenario || p.friction || p.plant || p.compare || p.clear_compare || p.reset || p.run ||
                           p.pause || !p.load_path.empty() || !p.save_path.empty() || p.rerun;
  if (any_request && !s.status_kind && !p.from_history) s.note("");  // an undo / redo has just said so
  // Every edit is recorded for undo (a drag gesture once); a run that had finished reruns with it.
  const bool edits = !p.load_path.empty() || p.scenario || p.friction || p.plant || p.compare || p.clear_compare;
  const bool gesture = ImGui::GetCurrentContext() != nullptr && ImGui::IsAnyItemActive();
  if (edits && s.main.sim && !p.from_history && !(s.history.gesture_open && gesture)) record_edit(s);
  if (edits) s.history.gesture_open = gesture;
  else if (!gesture) s.history.gesture_open = false;
  const bool was_finished = s.main.sim && s.main.sim->finished() && !s.running;
  if (!p.load_path.empty()) apply_load(s, p.load_path);
  if (p.scenario) {
    try {
      const bool was_running = s.running;
      load_scenario_into(s, *p.scenario, s.scenario_path);
      s.running = was_running || was_finished;
    } catch (const InputError& e) {
      s.report(Panel::Simulation, e, "scenario rejected");
    }
  }
  if (p.friction && s.main.sim) {
    try {
      s.main.sim->set_friction(*p.friction);
      s.scenario.friction = *p.friction;
    } catch (const InputError& e) {
      s.report(Panel::Simulation, e, "friction rejected");
    }
  }
  if (p.plant && s.main.sim) {
    try {
      s.main.sim->set_plant(*p.plant);
      if (s.overlay.sim) s.overlay.sim->set_plant(*p.plant);
      s.scenario.plant = *p.plant;
    } catch (const InputError& e) {
      s.report(Panel::Simulation, e, "plant rejected");
    }
  }
  if (s.overlay_follows_shared && s.compare && s.main.sim && !p.clear_compare &&
      (p.friction || p.scenario || p.compare || !p.load_path.empty())) {
    const ModelParams linked = with_shared_parameters(p.compare ? *p.compare : *s.compare, s.scenario.friction);
    if (!(linked == *s.compare)) p.compare = linked, s.sim_panel.compare = linked;
  }
  if (p.clear_compare) {
    s.compare.reset();
    s.overlay = {};
  }
  if (p.compare && s.main.sim) apply_compare(s, *p.compare);
  if (p.reset && s.main.sim) {
    s.main.sim->reset();
    if (s.overlay.sim) s.overlay.sim->reset();
    s.clear_error(Panel::Simulation);
  }
  if (p.run && s.main.sim) {
    if (s.main.sim->finished()) {  // run again from the start
      s.main.sim->reset();
      if (s.overlay.sim) s.overlay.sim->reset();
    }
    s.clear_error(Panel::Simulation);
    s.running = true;
  }
  if (p.rerun && s.main.sim) {
    s.main.sim->reset();
    if (s.overlay.sim) s.overlay.sim->reset();
    s.clear_error(Panel::Simulation);
    s.running = true;
  }
  if (was_finished && (p.friction || p.plant || p.compare) && s.main.sim && s.error.empty()) {
    // The edit would otherwise show nothing until Rerun: run it again from t = 0.
    s.main.sim->reset();
    if (s.overlay.sim) s.overlay.sim->reset();
    s.running = true;
    s.note("the run had finished: rerunning with the edit");
  }
  if (p.pause) s.running = false;
  if (!p.save_path.empty()) apply_save(s, p.save_path, p.save_confirmed);
}

ModelParams with_shared_parameters(const ModelParams& overlay, const ModelParams& main) {
  ModelParams out = overlay;
  const ModelInfo& a = model_info(overlay.model);
  const ModelInfo& b = model_info(main.model);
  for (const char* key : {"Fs", "Fc", "Vs"}) {
    const auto has = [&](const ModelInfo& m) {
      for (const auto& sp : m.scalars)
        if (sp.key == key) return true;
      return false;
    };
    if (has(a) && has(b)) out.set_scalar(key, main.scalar(key));
  }
  return out;
}

void mark_clean(AppState& s) {
  s.clean_scenario = s.scenario;
  s.clean_path = s.scenario_path;
}

void advance(AppState& s) {
  s.sim_limited = false;
  if (!s.running || !s.main.sim) return;
  const double want = s.view.speed * s.frame_dt / s.scenario.run.dt;
  std::size_t steps = static_cast<std::size_t>(std::max(1.0, std::round(want)));
  if (steps > s.max_steps_per_frame) {
    steps = s.max_steps_per_frame;
    s.sim_limited = true;
  }
  try {
    s.main.sim->advance(steps);
  } catch (const SimulationError& e) {
    return stop_with(s, std::string(model_info(s.scenario.friction.model).name), e);
  }
  if (s.overlay.sim) {
    try {
      s.overlay.sim->advance(steps);
    } catch (const SimulationError& e) {
      return stop_with(s, "overlay " + std::string(model_info(s.compare->model).name), e);
    }
  }
  if (s.main.sim->finished()) s.running = false;
}

void run_until(AppState& s, double t) {
  for (LiveRun* r : {&s.main, &s.overlay}) {
    if (!r->sim) continue;
    while (!r->sim->finished() && (t < 0 || r->sim->time() + 0.5 * s.scenario.run.dt < t))
      r->sim->advance(t < 0 ? (1u << 20)
                            : std::min<std::size_t>(1u << 20, static_cast<std::size_t>(std::llround(
                                                                  (t - r->sim->time()) / s.scenario.run.dt))));
  }
}

void draw_frame(AppState& s) {
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(vp->Pos);
  ImGui::SetNextWindowSize(vp->Size);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_MenuBar;
  ImGui::Begin("gmslab", nullptr, flags);
  draw_menu_bar(s);
  handle_shortcuts(s);
  // The panels above, the status line (when there is one, or the frame time is measured) below.
  const bool perf = s.perf.frame_ms > 0.0;
  const float status_h = s.status.empty() && !perf ? 0.0f : ImGui::GetTextLineHeight() + ImGui::GetStyle().ItemSpacing.y;
  ImGui::BeginChild("##tabs", ImVec2(0, -status_h), false, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  if (ImGui::BeginTabBar("##panels")) {
    for (const PanelEntry& e : panels()) {
      const bool select = s.select_tab > 0 && s.view.tab == e.name;
      const bool open = ImGui::BeginTabItem(e.name, nullptr, select ? ImGuiTabItemFlags_SetSelected : 0);
      if (e.tooltip && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", e.tooltip);
      if (open) {
        if (s.select_tab == 0) s.view.tab = e.name;
        e.draw(s);
        ImGui::EndTabItem();
      }
    }
    if (s.select_tab > 0) --s.select_tab;
    ImGui::EndTabBar();
  }
  ImGui::EndChild();
  if (std::string m = TakePlotMessage(); !m.empty()) {  // an export from a plot or the Figures tab
    if (m.rfind("export failed", 0) == 0) s.report(Panel::Simulation, ErrorKind::Io, m);
    else s.note(m);
  }
  if (!s.status.empty())
    ImGui::TextColored(s.status_kind ? ImVec4(0.75f, 0.10f, 0.10f, 1.0f) : ImVec4(0.35f, 0.35f, 0.38f, 1.0f), "%s",
                       s.status.c_str());
  if (perf) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "frame %.1f ms, %d fps", s.perf.frame_ms, s.perf.fps);
    const float w = ImGui::CalcTextSize(buf).x;
    if (!s.status.empty()) ImGui::SameLine();
    ImGui::SetCursorPosX(std::max(ImGui::GetCursorPosX(), ImGui::GetWindowContentRegionMax().x - w));
    ImGui::TextDisabled("%s", buf);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Time to build and draw the last frame, and frames drawn in the last second (an idle window "
                        "draws only on input)");
  }
  draw_file_dialogs(s);
  ImGui::End();
  apply_pending(s);
  advance(s);
}

FrameActivity frame_activity(AppState& s) {
  FrameActivity a;
  a.sim_running = s.running && s.main.sim;
  a.plant_running = s.plant.running && s.plant.sim && s.view.tab == "Plant";
  a.identifying = identify_busy(s.identify) || hunting_map_busy(s.design);
  a.animating = s.select_tab > 0 || (s.view.tab == "Design" && s.design.dirty) || s.browser.open_request;
  a.text_input = ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantTextInput;
  return a;
}

ActiveRun active_run(const AppState& s) {
  if (s.view.tab == "Plant") return {s.plant.running && s.plant.sim, s.plant.sim ? s.plant.sim->time() : 0.0};
  return {s.running && s.main.sim, s.main.sim ? s.main.sim->time() : 0.0};
}

std::string ui_status_json(const AppState& s, long long frames) {
  std::string tab = s.view.tab;
  for (char& c : tab) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const ActiveRun r = active_run(s);
  char buf[256];
  std::snprintf(buf, sizeof buf, "{\"frames\": %lld, \"tab\": \"%s\", \"running\": %s, \"run_time_s\": %.6g}", frames,
                tab.c_str(), r.running ? "true" : "false", std::isfinite(r.time_s) ? r.time_s : 0.0);
  return buf;
}

std::string resolve_preset(const std::string& preset) {
  return gmslab::resolve_preset(preset, presets_dir(), "--open");
}

namespace {
const char* const kLaunchTabs[] = {"Simulation", "Figures", "Design", "Identify", "Plant"};
}  // namespace

LaunchRequest check_launch(const LaunchRequest& r) {
  LaunchRequest out = r;
  out.preset = resolve_preset(r.preset);
  int schema = 1;
  try {
    const Preset preset = load_preset(out.preset);
    schema = preset.schema_version;
    if (preset.assembled()) (void)AssemblySimulation(preset.scenario);
    else
      (void)one_body_simulation(preset.one_body());
  } catch (const InputError& e) {
    throw InputError(std::string("--open: ") + e.what());
  }
  if (r.tab.empty()) {
    out.tab = schema == 2 ? "Plant" : "Simulation";
  } else {
    out.tab.clear();
    for (const char* t : kLaunchTabs)
      if (strcasecmp(t, r.tab.c_str()) == 0) out.tab = t;
    if (out.tab.empty())
      throw InputError("--tab '" + r.tab + "': no such tab; use simulation, figures, design, identify or plant");
  }
  if (schema == 2 && out.tab == "Simulation")
    throw InputError("--open '" + out.preset + "' is an assembled plant (schema_version 2): the Simulation tab runs "
                     "one-body scenarios; open it with --tab plant (or --tab design)");
  if (r.run && out.tab != "Simulation" && out.tab != "Plant")
    throw InputError("--run starts the Simulation or Plant tab's run; the " + out.tab +
                     " tab has none: drop --run or use --tab simulation or --tab plant");
  return out;
}

void apply_launch(AppState& s, const LaunchRequest& r) {
  const Preset preset = load_preset(r.preset);
  if (!preset.assembled()) {
    load_scenario_into(s, preset.one_body(), r.preset);
    mark_clean(s);
  }
  if (preset.assembled() || r.tab == "Plant") load_plant(s.plant, preset.scenario, r.preset);
  s.view.tab = r.tab;
  s.select_tab = 2;
  if (r.run && r.tab == "Plant") s.plant.running = true;
  if (r.run && r.tab == "Simulation") s.running = true;
  s.note("opened " + r.preset + (r.run ? " (running)" : ""));
}

}  // namespace gmslab::ui
