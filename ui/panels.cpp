#include "ui/panels.hpp"

#include "ui/app_files.hpp"
#include "ui/design/design_view.hpp"
#include "ui/identify/identify_panel.hpp"
#include "ui/figures/panel_figures.hpp"

#include <strings.h>

namespace gmslab::ui {

const std::vector<PanelEntry>& panels() {
  static const std::vector<PanelEntry> list = {
      {"Simulation", "Plant, drive and friction model; run it and watch the forces live",
       draw_simulation_panel},
      // Each panel gets its own typed state and only what it needs of the app.
      {"Figures", "The seed paper's figures, recomputed from the presets",
       [](AppState& s) {
         draw_figures_panel(s.figures, presets_dir());
         s.forward_error(Panel::Figures);
       }},
      {"Design", "Phase-lead design on the root locus, simulated with the friction",
       [](AppState& s) {
         draw_design_panel(s.design, s.scenario, s.generation, s.plant.scenario.get());
         s.forward_error(Panel::Design);
       }},
      {"Identify", "Fit a friction model to measured data and find what it lacks",
       [](AppState& s) {
         draw_identify_panel(s.identify, s.pending.scenario);
         s.forward_error(Panel::Identify);
       }},
      {"Plant", "The assembled plant as a schematic (bodies, springs, dampers, contacts, drives), animated while it runs",
       [](AppState& s) {
         draw_plant_panel(s.plant, s.frame_dt, [] {
           // Assembled plants first, then one-body scenarios (loaded as one body), each in menu order.
           std::vector<PresetChoice> plants, bodies;
           for (const PresetEntry& e : list_presets())
             (e.plant ? plants : bodies).push_back({e.plant ? e.name : e.name + "  (one body)", e.path});
           plants.insert(plants.end(), bodies.begin(), bodies.end());
           return plants;
         });
       }},
      // Add panels here (see ui/panels.hpp), e.g. {"Design", "...", draw_design_panel},
  };
  return list;
}

const PanelEntry* find_panel(const char* view) {
  const auto& list = panels();
  if (!view || !*view || strcasecmp(view, "auto") == 0) return list.empty() ? nullptr : &list[0];
  for (const auto& e : list)
    if (strcasecmp(view, e.name) == 0) return &e;
  return nullptr;
}

}  // namespace gmslab::ui
