// Export from the window's plots and from the Figures tab, through the app's frame: the exported
// CSV holds every sample of every series of the plot (the live trace, in the units shown), the
// SVG is the figure's vector drawing, PNG goes to the host's writer, and an export never
// replaces an existing file.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/io/scenario_io.hpp"
#include "tests/ui/imgui_test_context.hpp"
#include "ui/app.hpp"
#include "ui/plot/plot.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {
struct Harness {
  fs::path dir;
  ui::AppState s;
  ui::ScopedPlotContext plots;
  std::vector<std::string> pngs;
  std::vector<Figure> png_figures;
  explicit Harness(const char* preset) {
    dir = fs::temp_directory_path() / ("gmslab_export_" + std::to_string(getpid()));
    fs::remove_all(dir);
    setenv("GMSLAB_EXPORT_DIR", dir.c_str(), 1);
    uitest::make_headless_imgui(ImVec2(1280, 720));
    ui::SetPlotPngWriter([this](const Figure& f, const std::string& path) {
      pngs.push_back(path);
      png_figures.push_back(f);
      std::ofstream(path) << f.title;
    });
    ui::load_scenario_into(s, load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/" + preset), "");
    ui::run_until(s, -1);
    s.view.tab = "Simulation";
    frame();
  }
  ~Harness() {
    ImGui::DestroyContext();
    unsetenv("GMSLAB_EXPORT_DIR");
    fs::remove_all(dir);
  }
  void frame() {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
    ImGui::NewFrame();
    ui::draw_frame(s);
    ImGui::Render();
  }
};

// CSV rows by series label: (x, y) pairs.
std::map<std::string, std::vector<std::pair<double, double>>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::map<std::string, std::vector<std::pair<double, double>>> out;
  std::getline(in, line);
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string panel, label, x, y;
    std::getline(ss, panel, ',');
    std::getline(ss, label, ',');
    std::getline(ss, x, ',');
    std::getline(ss, y, ',');
    out[label].push_back({std::stod(x), std::stod(y)});
  }
  return out;
}
}  // namespace

TEST(PlotExport, CsvOfAPlotHoldsEverySampleOfItsSeriesAndNothingIsReplaced) {
  for (const char* preset : {"fig4_stick_slip.json", "fig2a_presliding.json"}) {
    Harness h(preset);
    ui::RequestPlotExport("Forces against time", ui::ExportFormat::Csv);
    h.frame();
    const fs::path csv = h.dir / "Forces_against_time.csv";
    ASSERT_TRUE(fs::exists(csv)) << h.s.status;
    EXPECT_NE(h.s.status.find(csv.string()), std::string::npos) << h.s.status;
    const auto rows = read_csv(csv.string());
    const Trace& tr = h.s.main.sim->one_body_trace();
    // The friction series: every sample of the trace, t in s, F in the unit the axis shows
    // (N here: the forces stay between 0.01 and 1000 N).
    bool found = false;
    for (const auto& [label, pts] : rows) {
      if (label.find("friction") == std::string::npos) continue;
      found = true;
      ASSERT_EQ(pts.size(), tr.t.size()) << label;
      for (std::size_t i = 0; i < pts.size(); i += std::max<std::size_t>(1, pts.size() / 500)) {
        EXPECT_NEAR(pts[i].first, tr.t[i], 1e-9 * std::max(1.0, std::abs(tr.t[i])));
        EXPECT_NEAR(pts[i].second, tr.friction[i], 1e-9 * std::max(1.0, std::abs(tr.friction[i])));
      }
    }
    EXPECT_TRUE(found);
    // Again: a new file, the first one kept.
    const auto before = fs::file_size(csv);
    ui::RequestPlotExport("Forces against time", ui::ExportFormat::Csv);
    h.frame();
    EXPECT_TRUE(fs::exists(h.dir / "Forces_against_time-2.csv"));
    EXPECT_EQ(fs::file_size(csv), before);
    // Units in ASCII: the micro prefix as u (the presliding position is in um).
    ui::RequestPlotExport("Position against time", ui::ExportFormat::Csv);
    h.frame();
    {
      std::ifstream in(h.dir / "Position_against_time.csv", std::ios::binary);
      const std::string text((std::istreambuf_iterator<char>(in)), {});
      ASSERT_FALSE(text.empty());
      EXPECT_TRUE(std::all_of(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) < 128; }))
          << "non-ASCII byte in the CSV";
      if (std::string(preset) == "fig2a_presliding.json") {
        EXPECT_NE(text.find("[um]"), std::string::npos) << text.substr(0, 300);
      }
    }
    // SVG and PNG of the same plot.
    ui::RequestPlotExport("Forces against time", ui::ExportFormat::Svg);
    ui::RequestPlotExport("Position against time", ui::ExportFormat::Png);
    h.frame();
    std::ifstream svg(h.dir / "Forces_against_time.svg");
    const std::string text((std::istreambuf_iterator<char>(svg)), {});
    EXPECT_NE(text.find("<svg"), std::string::npos);
    // The title drawn once (one text element; the document's <title> aside).
    std::size_t titles = 0;
    for (std::size_t at = text.find(">Forces against time</text>"); at != std::string::npos;
         at = text.find(">Forces against time</text>", at + 1))
      ++titles;
    EXPECT_EQ(titles, 1u);
    ASSERT_EQ(h.pngs.size(), 1u);
    EXPECT_EQ(fs::path(h.pngs[0]).filename(), "Position_against_time.png");
    ASSERT_EQ(h.png_figures.size(), 1u);
    EXPECT_EQ(h.png_figures[0].title, "Position against time");
    ASSERT_EQ(h.png_figures[0].panels.size(), 1u);
    EXPECT_EQ(h.png_figures[0].panels[0].title, "");  // the figure's title only
  }
}
#endif

#if __has_include(<imgui.h>)
#include <imgui_internal.h>

// The menu itself, by mouse: a right-click on a plot opens the export menu; choosing "SVG" writes
// the plot's SVG.
TEST(PlotExport, RightClickOpensTheExportMenuAndItsItemWrites) {
  const fs::path dir = fs::temp_directory_path() / ("gmslab_export_menu_" + std::to_string(getpid()));
  fs::remove_all(dir);
  setenv("GMSLAB_EXPORT_DIR", dir.c_str(), 1);
  uitest::make_headless_imgui(ImVec2(800, 600));
  {
    ui::ScopedPlotContext plots;
    std::vector<double> x{0, 1, 2, 3}, y{1, 3, 2, 4};
    auto frame = [&](ImVec2 mouse, bool left, bool right) {
      ImGuiIO& io = ImGui::GetIO();
      io.DeltaTime = 1.0f / 60.0f;
      io.MousePos = mouse;
      io.MouseDown[0] = left;
      io.MouseDown[1] = right;
      ImGui::NewFrame();
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(ImVec2(800, 600));
      ImGui::Begin("w", nullptr, ImGuiWindowFlags_NoDecoration);
      ui::PlotOptions o;
      o.title = "menu test";
      if (ui::BeginPlot("##p", ImVec2(-1, -1), o)) {
        ui::SetupAxes("x [-]", "y [-]");
        ui::PlotLine("y", x.data(), y.data(), x.size());
        ui::EndPlot();
      }
      ImGui::End();
      ImGui::Render();
    };
    const ImVec2 in(400, 300);
    frame(in, false, false);
    frame(in, false, true);
    frame(in, false, false);
    ImGuiContext& g = *ImGui::GetCurrentContext();
    ASSERT_EQ(g.OpenPopupStack.Size, 1) << "right-click opens the menu";
    ImGuiWindow* menu = g.OpenPopupStack[0].Window;
    ASSERT_NE(menu, nullptr);
    // Items: the folder line, PNG (disabled: no writer here), SVG, CSV.
    const float line = ImGui::GetTextLineHeightWithSpacing();
    const ImVec2 svg(menu->DC.CursorStartPos.x + 20, menu->DC.CursorStartPos.y + 2.5f * line);
    frame(svg, false, false);
    frame(svg, true, false);
    frame(svg, false, false);
    frame(ImVec2(-FLT_MAX, -FLT_MAX), false, false);
    EXPECT_TRUE(fs::exists(dir / "menu_test.svg")) << ui::TakePlotMessage();
    EXPECT_EQ(g.OpenPopupStack.Size, 0);
  }
  ImGui::DestroyContext();
  unsetenv("GMSLAB_EXPORT_DIR");
  fs::remove_all(dir);
}
#endif
