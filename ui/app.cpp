#include "ui/app.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.hpp"
#include "core/io/scenario_io.hpp"
#include "ui/panels.hpp"

namespace gmslab::ui {

std::span<const std::uint8_t> LiveRun::phases(double slip_velocity) {
  if (!sim) return {};
  return phase_series.update(sim->trace(), slip_velocity);
}

namespace {
Scenario with_friction(Scenario sc, const ModelParams& p) {
  sc.friction = p;
  return sc;
}

void rebuild_overlay(AppState& s) {
  s.overlay = {};
  if (!s.compare) return;
  s.overlay.sim = std::make_unique<Simulation>(with_friction(s.main.sim->scenario(), *s.compare),
                                               TraceOptions{.max_bytes = s.history_bytes});
  // Catch up with the main run so both show the same stretch of input.
  const double t = s.main.sim->time();
  while (!s.overlay.sim->finished() && s.overlay.sim->time() + 0.5 * s.scenario.run.dt < t)
    s.overlay.sim->advance(std::min<std::size_t>(
        1u << 16, static_cast<std::size_t>(std::llround((t - s.overlay.sim->time()) / s.scenario.run.dt))));
}

void stop_with(AppState& s, const std::string& who, const SimulationError& e) {
  s.running = false;
  s.error = who + ": " + e.what();
}

// Each request in its own function; errors become messages, never exceptions.
void apply_load(AppState& s, const std::string& path) {
  try {
    load_scenario_into(s, load_scenario(path), path);
    s.status = "loaded " + path;
  } catch (const std::exception& e) {
    s.status = std::string("load failed: ") + e.what();
  }
}

void apply_save(AppState& s, const std::string& path) {
  try {
    save_scenario(s.scenario, path);
    s.scenario_path = path;
    s.status = "saved " + path;
  } catch (const std::exception& e) {
    s.status = std::string("save failed: ") + e.what();
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
    s.status = std::string("overlay model rejected: ") + e.what();
  } catch (const SimulationError& e) {
    stop_with(s, "overlay model", e);
  }
}
}  // namespace

std::string presets_dir() {
  const char* env = std::getenv("GMSLAB_PRESETS");
  return env && *env ? env : GMSLAB_SOURCE_DIR "/presets";
}

void load_scenario_into(AppState& s, const Scenario& sc, const std::string& path) {
  // Validates before anything changes.
  auto sim = std::make_unique<Simulation>(sc, TraceOptions{.max_bytes = s.history_bytes});
  ++s.generation;
  s.scenario = sc;
  s.scenario_path = path;
  s.main = {};
  s.main.sim = std::move(sim);
  s.running = false;
  s.error.clear();
  if (s.compare) {
    try {
      rebuild_overlay(s);
    } catch (const std::exception& e) {
      s.compare.reset();
      s.overlay = {};
      s.status = std::string("overlay removed: ") + e.what();
    }
  }
}

Session make_session(const AppState& s) {
  Session out{s.scenario_path, s.scenario, s.compare, s.view, {}, {}};
  out.design = design_settings(s.design);
  out.identify = identify_settings(s.identify);
  return out;
}

void restore_session(AppState& s, const Session& session) {
  if (session.compare) build_model(*session.compare);  // validate before changing anything
  load_scenario_into(s, session.scenario, session.scenario_path);
  s.view = session.view;
  apply_design_settings(s.design, session.design);
  apply_identify_settings(s.identify, session.identify);
  s.select_tab = 2;
  if (session.compare) apply_compare(s, *session.compare);
}

void apply_pending(AppState& s) {
  PendingRequests p = std::move(s.pending);
  s.pending = {};
  if (!p.load_path.empty()) apply_load(s, p.load_path);
  if (p.scenario) {
    try {
      const bool was_running = s.running;
      load_scenario_into(s, *p.scenario, s.scenario_path);
      s.running = was_running;
    } catch (const InputError& e) {
      s.status = std::string("scenario rejected: ") + e.what();
    }
  }
  if (p.friction && s.main.sim) {
    try {
      s.main.sim->set_friction(*p.friction);
      s.scenario.friction = *p.friction;
    } catch (const InputError& e) {
      s.status = std::string("friction rejected: ") + e.what();
    }
  }
  if (p.plant && s.main.sim) {
    try {
      s.main.sim->set_plant(*p.plant);
      if (s.overlay.sim) s.overlay.sim->set_plant(*p.plant);
      s.scenario.plant = *p.plant;
    } catch (const InputError& e) {
      s.status = std::string("plant rejected: ") + e.what();
    }
  }
  if (p.clear_compare) {
    s.compare.reset();
    s.overlay = {};
  }
  if (p.compare && s.main.sim) apply_compare(s, *p.compare);
  if (p.reset && s.main.sim) {
    s.main.sim->reset();
    if (s.overlay.sim) s.overlay.sim->reset();
    s.error.clear();
  }
  if (p.run && s.main.sim) {
    if (s.main.sim->finished()) {  // run again from the start
      s.main.sim->reset();
      if (s.overlay.sim) s.overlay.sim->reset();
    }
    s.error.clear();
    s.running = true;
  }
  if (p.pause) s.running = false;
  if (!p.save_path.empty()) apply_save(s, p.save_path);
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
                                 ImGuiWindowFlags_NoBringToFrontOnFocus;
  ImGui::Begin("gmslab", nullptr, flags);
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
  ImGui::End();
  apply_pending(s);
  advance(s);
}

}  // namespace gmslab::ui
