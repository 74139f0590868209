// The Plant schematic's labels never collide: for every shipped assembled preset, at the golden
// views' two window sizes (1280x720, 1600x1000), with the UI font and the run's forces shown
// (t = 1 s), no two label boxes overlap and no label overlaps a body. Built only with the app.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/ui/app_frame.hpp"
#include "ui/app.hpp"
#include "ui/plant/plant_view.hpp"
#include "ui/plot/plot.hpp"
#include "ui/style.hpp"

using namespace gmslab;

namespace {
bool overlap(const ui::Box& a, const ui::Box& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}
std::string str(const ui::Box& b) {
  return "[" + std::to_string(b.x0) + ", " + std::to_string(b.y0) + " .. " + std::to_string(b.x1) + ", " +
         std::to_string(b.y1) + "]";
}
}  // namespace

TEST(PlantLabels, NoTwoLabelsOverlapAndNoneCoversABodyInTheShippedPlants) {
  const std::string dir = std::string(GMSLAB_SOURCE_DIR) + "/presets";
  int checked = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string path = e.path().string();
    if (e.path().extension() != ".json" || preset_schema_version(parse_json(read_file(path), path)) != 2) continue;
    for (const ImVec2 size : {ImVec2(1280, 720), ImVec2(1600, 1000)}) {
      SCOPED_TRACE(path + " at " + std::to_string(static_cast<int>(size.x)) + "x" + std::to_string(static_cast<int>(size.y)));
      ImGui::CreateContext();
      ImGuiIO& io = ImGui::GetIO();
      io.DisplaySize = size;
      io.IniFilename = nullptr;
      ui::setup_style(std::clamp(17.0f * size.y / 1000.0f, 12.0f, 26.0f));  // as the headless renderer
      unsigned char* px = nullptr;
      int w = 0, h = 0;
      io.Fonts->GetTexDataAsRGBA32(&px, &w, &h);
      {
        const ui::ScopedPlotContext plots;
        ui::AppState s;
        ui::load_scenario_into(s, load_scenario(dir + "/fig4_stick_slip.json"), "");
        ui::load_plant(s.plant, load_assembly_scenario(path), path);
        ui::plant_run_until(s.plant, 1.0);
        s.view.tab = "Plant";
        for (int i = 0; i < 3; ++i) uitest::draw_app_frame(s, uitest::kNoMouse, false);
        const ui::PlantDrawn& d = s.plant.canvas_drawn;
        EXPECT_GE(d.labels.size(), s.plant.scenario->plant.contacts.size() + s.plant.scenario->plant.drives.size());
        for (std::size_t i = 0; i < d.labels.size(); ++i) {
          for (std::size_t j = i + 1; j < d.labels.size(); ++j)
            EXPECT_FALSE(overlap(d.labels[i], d.labels[j])) << "labels " << i << " " << str(d.labels[i]) << " and " << j
                                                             << " " << str(d.labels[j]);
          for (std::size_t b = 0; b < d.bodies.size(); ++b)
            EXPECT_FALSE(overlap(d.labels[i], d.bodies[b]))
                << "label " << i << " " << str(d.labels[i]) << " on body " << b << " " << str(d.bodies[b]);
        }
      }
      ImGui::DestroyContext();
      ++checked;
    }
  }
  EXPECT_GE(checked, 8);  // four shipped plants, two sizes
}
#endif
