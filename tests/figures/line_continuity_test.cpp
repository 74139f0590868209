// Solid lines drawn unbroken at any slope: figures with steep spikes and drops (a force spike
// as at each stick in Fig. 4: up and down again within one pixel column), random positions,
// heights and sizes (fixed seed), drawn by the headless renderer (gmslab-headless plot-figure).
// Every pixel row the spike spans must be covered by the line's colour near the spike column:
// a thinned or dashed stroke leaves rows uncovered.
#if defined(GMSLAB_HEADLESS_EXE)
#include <gtest/gtest.h>
#include <stb_image.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "core/ident/figure_json.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {
// The first palette colour (0, 114, 178) and anti-aliased shades of it on white.
bool bluish(const unsigned char* px) { return px[2] > 110 && px[2] > px[0] + 50; }
}  // namespace

TEST(LineContinuity, SteepSpikesAndDropsAreDrawnWithoutGaps) {
  const fs::path dir = fs::temp_directory_path() / ("gmslab_lines_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::mt19937 rng(404);
  std::uniform_real_distribution<double> u(0, 1);
  const int sizes[][2] = {{800, 500}, {1280, 720}, {1600, 1000}};
  for (int trial = 0; trial < 6; ++trial) {
    const int w = sizes[trial % 3][0], h = sizes[trial % 3][1];
    // A slow ramp with one spike: within 1e-4 of the x range it jumps down by `depth`, back up.
    Figure f;
    f.id = "lines";
    f.title = "continuity";
    Series s;
    s.label = "F";
    const int n = 20000;
    const double at = 0.2 + 0.6 * u(rng), depth = 0.4 + 0.5 * u(rng);
    for (int i = 0; i < n; ++i) {
      const double x = static_cast<double>(i) / (n - 1);
      double y = 0.5 + 0.3 * x;
      if (std::fabs(x - at) < 5e-5) y -= depth;
      s.x.push_back(x);
      s.y.push_back(y);
    }
    f.panels.push_back({"", "spike", "t [s]", "F [N]", {s}});
    const std::string json = (dir / "f.json").string(), png = (dir / "f.png").string();
    save_figure_json(f, json);
    const std::string cmd = std::string(GMSLAB_HEADLESS_EXE) + " plot-figure " + json + " --out " + png +
                            " --size " + std::to_string(w) + "x" + std::to_string(h) + " 2>/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    int iw = 0, ih = 0, c = 0;
    unsigned char* img = stbi_load(png.c_str(), &iw, &ih, &c, 3);
    ASSERT_NE(img, nullptr);
    // The spike column: the one with the most line pixels.
    int best = 0, best_n = -1;
    for (int x = 0; x < iw; ++x) {
      int cnt = 0;
      for (int y = 0; y < ih; ++y) cnt += bluish(img + 3 * (y * iw + x));
      if (cnt > best_n) best_n = cnt, best = x;
    }
    // Its vertical extent (within 3 columns), and the rows of it not covered.
    int top = ih, bottom = -1;
    for (int x = std::max(0, best - 3); x <= std::min(iw - 1, best + 3); ++x)
      for (int y = 0; y < ih; ++y)
        if (bluish(img + 3 * (y * iw + x))) top = std::min(top, y), bottom = std::max(bottom, y);
    int gaps = 0;
    for (int y = top; y <= bottom; ++y) {
      bool any = false;
      for (int x = std::max(0, best - 3); x <= std::min(iw - 1, best + 3); ++x) any |= bluish(img + 3 * (y * iw + x));
      gaps += !any;
    }
    stbi_image_free(img);
    // The spike spans about depth / (y range) of the plot height: a real vertical run.
    EXPECT_GT(bottom - top, static_cast<int>(0.25 * h * depth)) << w << "x" << h;
    EXPECT_EQ(gaps, 0) << w << "x" << h << ": " << gaps << " of " << bottom - top + 1 << " rows uncovered";
  }
  fs::remove_all(dir);
}
#endif
