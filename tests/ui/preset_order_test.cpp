// The Presets menu lists the shipped presets by figure (Fig. 2A before Fig. 2D with LuGre), the
// presets that name no figure after them, numbers in file names compared as numbers.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ui/app_files.hpp"

using namespace gmslab;

TEST(PresetOrder, ShippedPresetsAreListedByFigure) {
  std::vector<std::string> names;
  for (const ui::PresetEntry& e : ui::list_presets())
    if (e.shipped) names.push_back(std::filesystem::path(e.path).stem().string());
  const std::vector<std::string> expected = {
      "fig2a_presliding",     "fig2b_lag_x1",          "fig2b_lag_x16",          "fig2b_lag_x100",
      "fig2c_periodic_0p1hz", "fig2c_periodic_1hz",    "fig2d_nondrifting",      "compare_fig2d_lugre",
      "fig3_stick_slip_scheme", "fig4_stick_slip",     "compare_fig4_lugre",     "slider_on_table",
      "three_body_chain",     "two_mass_drive"};
  EXPECT_EQ(names, expected);
}

TEST(PresetOrder, FigureThenPanelThenComparisonThenNaturalFileName) {
  auto e = [](std::string name, std::string path) { return ui::PresetEntry{path, name, "", true, false}; };
  EXPECT_TRUE(ui::preset_before(e("Fig. 2A: x", "/p/z.json"), e("Fig. 2D protocol with LuGre", "/p/a.json")));
  EXPECT_TRUE(ui::preset_before(e("Fig. 2D: x", "/p/z.json"), e("Fig. 2D protocol with LuGre", "/p/a.json")));
  EXPECT_TRUE(ui::preset_before(e("Fig. 9: x", "/p/z.json"), e("Fig. 10: x", "/p/a.json")));
  EXPECT_TRUE(ui::preset_before(e("Fig. 10: x", "/p/z.json"), e("A plant", "/p/a.json")));
  EXPECT_TRUE(ui::preset_before(e("Fig. 2B: lag", "/p/lag_x16.json"), e("Fig. 2B: lag", "/p/lag_x100.json")));
  EXPECT_FALSE(ui::preset_before(e("Fig. 2B: lag", "/p/lag_x100.json"), e("Fig. 2B: lag", "/p/lag_x16.json")));
  EXPECT_FALSE(ui::preset_before(e("Fig. 2B: lag", "/p/a.json"), e("Fig. 2B: lag", "/p/a.json")));
}
