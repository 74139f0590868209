// Golden renders of the app's views (issue 15: nothing clipped or wrapped mid-number at projector
// and desktop sizes; issue 11: the Plant schematic). Plant, Simulation, Design and Figures; not
// Identify (its render runs an identification of the EMPS data, ~20 s, and needs the data set).
// `gmslab-headless render PRESET --view VIEW
// --size WxH` is run from the source directory (so the title's preset path is the same in every
// checkout) and compared with tests/golden/views/VIEW_WxH.png. The goldens are stored at half
// resolution (2x2 means, to keep them small); the render is halved the same way and compared with
// golden_compare.hpp's tolerance on 4x4 blocks (the 8x8 area of the full render): rounding-level
// differences pass, a moved block, label, panel or curve does not. The test also shows that
// headless renders are deterministic (two renders are byte-identical) and that the comparison can
// fail (a schematic shifted by 4 px, an erased label).
// Regenerate after an intended change of a view:
//   GMSLAB_UPDATE_GOLDEN=1 ./build/gmslab_tests --gtest_filter='GoldenViews*'
// then look at every PNG in tests/golden/views/ (and at the full-size renders the test leaves in
// $TMPDIR/gmslab_views_PID when it fails) before committing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#ifdef GMSLAB_HEADLESS_EXE
#include <stb_image_write.h>
#include <unistd.h>

#include "tests/figures/golden_compare.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;
using namespace golden;

const std::string kGoldenViews = std::string(GMSLAB_SOURCE_DIR) + "/tests/golden/views";

fs::path views_dir() { return fs::temp_directory_path() / ("gmslab_views_" + std::to_string(getpid())); }

struct RemoveViewRendersIfPassed : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    if (::testing::UnitTest::GetInstance()->Passed()) fs::remove_all(views_dir(), ec);
  }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new RemoveViewRendersIfPassed);

struct ViewCase {
  const char* view;
  const char* preset;
  int w, h;
  std::string name() const { return std::string(view) + "_" + std::to_string(w) + "x" + std::to_string(h); }
};
const ViewCase kCases[] = {
    {"plant", "presets/two_mass_drive.json", 1280, 720},  {"plant", "presets/two_mass_drive.json", 1600, 1000},
    {"simulation", "presets/fig4_stick_slip.json", 1280, 720}, {"simulation", "presets/fig4_stick_slip.json", 1600, 1000},
    {"design", "presets/fig4_stick_slip.json", 1280, 720},  {"design", "presets/fig4_stick_slip.json", 1600, 1000},
    {"figures", "presets/fig4_stick_slip.json", 1280, 720}, {"figures", "presets/fig4_stick_slip.json", 1600, 1000},
};

// Renders one case (whole run) into the temp dir; returns the PNG's path.
std::string render(const ViewCase& c, const std::string& suffix = "") {
  fs::create_directories(views_dir());
  const std::string out = (views_dir() / (c.name() + suffix + ".png")).string();
  const std::string cmd = "cd '" + std::string(GMSLAB_SOURCE_DIR) + "' && '" + std::string(GMSLAB_HEADLESS_EXE) + "' render " +
                          c.preset + " --view " + c.view + " --size " + std::to_string(c.w) + "x" + std::to_string(c.h) +
                          " --out '" + out + "' 2>/dev/null >/dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return out;
}

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Stored with each channel rounded to a multiple of 8 levels (error <= 4, far inside the
// tolerance) and the strongest zlib level: the PNG compresses to about half.
void save_png(const Image& im, const std::string& path) {
  Image q = im;
  for (auto& v : q.rgb) v = static_cast<unsigned char>(std::min(248, (v + 4) / 8 * 8));
  stbi_write_png_compression_level = 9;
  ASSERT_TRUE(stbi_write_png(path.c_str(), q.w, q.h, 3, q.rgb.data(), q.w * 3)) << path;
}

TEST(GoldenViews, EveryViewMatchesItsGoldenAtProjectorAndDesktopSize) {
  const bool update = std::getenv("GMSLAB_UPDATE_GOLDEN") != nullptr;
  for (const ViewCase& c : kCases) {
    SCOPED_TRACE(c.name());
    const Image full = load(render(c));
    ASSERT_EQ(full.w, c.w);
    ASSERT_EQ(full.h, c.h);
    const Image now = half(full);
    const std::string gold = kGoldenViews + "/" + c.name() + ".png";
    if (update) save_png(now, gold);
    const Image ref = load(gold);
    ASSERT_EQ(ref.w, c.w / 2) << gold << " (missing golden? see the comment at the top)";
    ASSERT_EQ(ref.h, c.h / 2);
    const Difference d = compare(now, ref, 4);
    EXPECT_TRUE(acceptable(d, now)) << d.strong_pixels << " strongly different pixels, worst 4x4 block (8x8 px) "
                                    << d.worst_block << " levels; renders kept in " << views_dir();
  }
}

// OSMesa (llvmpipe) renders are deterministic: the same command twice gives the same bytes.
TEST(GoldenViews, HeadlessRendersAreDeterministic) {
  for (const ViewCase& c : {kCases[0], kCases[4]}) {
    const std::string a = bytes(render(c, "_a")), b = bytes(render(c, "_b"));
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << c.name() << ": two renders differ";
  }
}

// The tolerance catches a layout change and a missing label: the schematic area of the plant
// golden shifted right by 2 half-res pixels (4 px), and one label's text erased.
TEST(GoldenViews, ComparisonCatchesAShiftedSchematicAndAMissingLabel) {
  const Image ref = load(kGoldenViews + "/plant_1600x1000.png");
  ASSERT_EQ(ref.w, 800);
  // The schematic: right of the left column, from the top to ~45 % height.
  Image shifted = ref;
  const int x0 = ref.w * 24 / 100, y0 = ref.h * 6 / 100, y1 = ref.h * 45 / 100;
  for (int y = y0; y < y1; ++y)
    for (int x = ref.w - 1; x >= x0 + 2; --x)
      for (int c = 0; c < 3; ++c) shifted.ref(x, y, c) = ref.at(x - 2, y, c);
  EXPECT_FALSE(acceptable(compare(shifted, ref, 4), ref)) << "a 4 px shift of the schematic went unnoticed";
  // Erase the dark text in one 40x8 box of the schematic with the most dark pixels (a label).
  int best = 0, bx = 0, by = 0;
  for (int y = y0; y + 8 <= y1; y += 2)
    for (int x = x0; x + 40 <= ref.w; x += 4) {
      int dark = 0;
      for (int v = y; v < y + 8; ++v)
        for (int u = x; u < x + 40; ++u) dark += ref.at(u, v, 0) < 110 && ref.at(u, v, 2) < 110;
      if (dark > best) best = dark, bx = x, by = y;
    }
  ASSERT_GT(best, 20);
  Image erased = ref;
  for (int v = by; v < by + 8; ++v)
    for (int u = bx; u < bx + 40; ++u)
      for (int c = 0; c < 3; ++c) erased.ref(u, v, c) = 255;
  EXPECT_FALSE(acceptable(compare(erased, ref, 4), ref)) << "an erased label went unnoticed";
}

}  // namespace
}  // namespace gmslab
#else
TEST(GoldenViews, EveryViewMatchesItsGoldenAtProjectorAndDesktopSize) {
  GTEST_SKIP() << "built without the app (GMSLAB_BUILD_APP=OFF): no headless renderer";
}
#endif
