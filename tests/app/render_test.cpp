// `gmslab render` and `gmslab figures` end to end: the executables run, the PNG has the requested
// size, the simulated traces are visible in the plots (decoded pixels), and the output is
// deterministic.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/figures/figure_set.hpp"

namespace fs = std::filesystem;

namespace {
const std::string kPreset = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json";

fs::path tmp_dir() { return fs::temp_directory_path() / ("gmslab_render_test_" + std::to_string(getpid())); }

std::string tmp(const std::string& name) {
  fs::create_directories(tmp_dir());
  return (tmp_dir() / name).string();
}

// The folder of this process's outputs goes when the tests are done.
struct RemoveTmpDir : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(tmp_dir(), ec);
  }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new RemoveTmpDir);

int run(const std::string& cmd) {
  const int rc = std::system((cmd + " 2>/dev/null").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgba;
  bool near(int x, int y, int r, int g, int b, int tol) const {
    const unsigned char* p = &rgba[(static_cast<std::size_t>(y) * w + x) * 4];
    return std::abs(p[0] - r) <= tol && std::abs(p[1] - g) <= tol && std::abs(p[2] - b) <= tol;
  }
};

Image load(const std::string& path) {
  Image im;
  int n = 0;
  unsigned char* d = stbi_load(path.c_str(), &im.w, &im.h, &n, 4);
  if (d) {
    im.rgba.assign(d, d + static_cast<std::size_t>(im.w) * im.h * 4);
    stbi_image_free(d);
  }
  return im;
}
}  // namespace

TEST(RenderCommand, StickSlipPresetGivesPngOfRequestedSizeWithVisibleTraces) {
  const std::string out = tmp("fig4.png");
  ASSERT_EQ(run(std::string(GMSLAB_EXE) + " render " + kPreset + " --out " + out + " --size 800x500"), 0);
  const Image im = load(out);
  ASSERT_EQ(im.w, 800);
  ASSERT_EQ(im.h, 500);
  // The plots fill the right part of the window. Count pixels of the stick colour (blue
  // 0,114,178) and of the slip colour (orange 230,120,0) there: both phases of the stick-slip
  // run must be drawn, as lines (many pixels), not as a legend swatch alone.
  int stick = 0, slip = 0;
  for (int y = 0; y < im.h; ++y)
    for (int x = im.w * 2 / 5; x < im.w; ++x) {
      stick += im.near(x, y, 0, 114, 178, 30);
      slip += im.near(x, y, 230, 120, 0, 30);
    }
  EXPECT_GT(stick, 600) << "stick-phase trace pixels";
  EXPECT_GT(slip, 400) << "slip-phase trace pixels";
  // White plot backgrounds cover much of the right half (the window background is grey): the
  // plots are laid out there, not an empty window.
  int white = 0;
  for (int y = 0; y < im.h; ++y)
    for (int x = im.w / 2; x < im.w; ++x) white += im.near(x, y, 255, 255, 255, 2);
  EXPECT_GT(white, (im.w / 2) * im.h * 3 / 10);
}

TEST(RenderCommand, SameInputGivesIdenticalBytes) {
  const std::string a = tmp("a.png"), b = tmp("b.png");
  const std::string cmd = std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --size 640x400 --time 9 --out ";
  ASSERT_EQ(run(cmd + a), 0);
  ASSERT_EQ(run(cmd + b), 0);
  const std::string ba = bytes(a), bb = bytes(b);
  ASSERT_GT(ba.size(), 1000u);
  EXPECT_TRUE(ba == bb) << "two renders of the same preset differ";
}

TEST(RenderCommand, BadSizeAndUnknownViewAreRejectedWithExitCode2) {
  const std::string out = tmp("bad.png");
  EXPECT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --out " + out + " --size 10x10"), 2);
  EXPECT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --out " + out + " --view nope"), 2);
  // Design-view options: a manual compensator needs 3 or 5 numbers with Kc, z > 0 and p >= 0; the
  // feedforward source is reference or measured; none of them outside the design view.
  const std::string design = std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --out " + out + " --view design";
  EXPECT_EQ(run(design + " --manual '1000 5'"), 2);
  EXPECT_EQ(run(design + " --manual '1000 5 0 x 1'"), 2);
  EXPECT_EQ(run(design + " --manual '1000 -5 0'"), 2);
  EXPECT_EQ(run(design + " --feedforward velocity"), 2);
  EXPECT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --out " + out + " --view simulation --feedforward measured"), 2);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(run(design + " --manual '1000 5 0' --reference step --compensation coulomb --feedforward measured --size 640x400"), 0);
  EXPECT_TRUE(fs::exists(out));
}

TEST(FiguresCommand, WritesPngAndCsvForEachRequestedFigure) {
  const std::string dir = tmp("figs");
  ASSERT_EQ(run(std::string(GMSLAB_EXE) + " figures --out " + dir + " --only fig2a_presliding --size 700x450"), 0);
  const Image im = load(dir + "/fig2a_presliding.png");
  EXPECT_EQ(im.w, 700);
  EXPECT_EQ(im.h, 450);
  int blue = 0;
  for (int y = 0; y < im.h; ++y)
    for (int x = 0; x < im.w; ++x) blue += im.near(x, y, 0, 114, 178, 30);
  EXPECT_GT(blue, 800) << "hysteresis curve pixels";
  std::ifstream csv(dir + "/fig2a_presliding.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "panel,series,x,y,x_label,y_label");
  std::size_t rows = 0;
  for (std::string line; std::getline(csv, line); ++rows) ASSERT_NE(line.rfind('#', 0), 0u) << "comment line: " << line;
  EXPECT_GT(rows, 1000u);
  EXPECT_NE(run(std::string(GMSLAB_EXE) + " figures --out " + dir + " --only no_such_figure"), 0);
}

// The whole set, as `gmslab` with no display would produce it: every figure id gets a PNG of the
// requested size with coloured curves in it (figures with many long series exceed 65536 vertices
// per draw list, which the headless renderer must still draw) and a CSV beside it.
TEST(FiguresCommand, EveryFigureOfTheSetIsWrittenWithItsCurvesVisible) {
  const std::string dir = tmp("all");
  ASSERT_EQ(run(std::string(GMSLAB_EXE) + " figures --out " + dir + " --size 560x360"), 0);
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".png") continue;
    ++n;
    const Image im = load(e.path().string());
    ASSERT_EQ(im.w, 560) << e.path();
    ASSERT_EQ(im.h, 360) << e.path();
    int coloured = 0;  // saturated pixels: curves (text, axes and grid are grey)
    for (std::size_t i = 0; i < im.rgba.size(); i += 4) {
      const int r = im.rgba[i], g = im.rgba[i + 1], b = im.rgba[i + 2];
      coloured += std::max({r, g, b}) - std::min({r, g, b}) > 60;
    }
    EXPECT_GT(coloured, 300) << e.path() << ": no curves drawn";
    fs::path csv = e.path();
    csv.replace_extension(".csv");
    EXPECT_TRUE(fs::exists(csv)) << csv;
  }
  EXPECT_EQ(n, gmslab::figure_ids().size());
}

namespace {
// A small measured-looking record: a triangle-wave motion, a Coulomb-like force, and a pulse_code
// column that switches at t = 1 s and t = 2 s (its edges are masked by --mask-edges).
std::string write_record(const std::string& name) {
  const std::string path = tmp(name);
  std::ofstream o(path);
  o << "t_s,x_m,F_N,pulse_code\n";
  for (int i = 0; i <= 3000; ++i) {
    const double t = 0.001 * i;
    const double ph = std::fmod(t, 1.0);
    const double x = 0.01 * (ph < 0.5 ? ph : 1.0 - ph);
    const double F = (ph < 0.5 ? 20.0 : -20.0) + 2.0 * std::sin(37.0 * t);
    o << t << ',' << x << ',' << F << ',' << (t >= 1.0 && t < 2.0 ? 1 : 0) << '\n';
  }
  return path;
}
}  // namespace

TEST(RenderCommand, IdentifyViewShowsTheLoadedRecordWithTheMaskedSamplesInGrey) {
  const std::string csv = write_record("record.csv"), out = tmp("ident_preview.png");
  ASSERT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --view identify --data " + csv +
                " --mask-edges pulse_code:0.05:0.1 --no-run --size 1200x750 --out " + out),
            0);
  const Image im = load(out);
  ASSERT_EQ(im.w, 1200);
  // The preview plots fill the lower part: the force and position traces (blue) and the masked
  // windows around the two pulse edges (grey 170) must both be drawn there.
  int blue = 0, grey = 0;
  for (int y = im.h / 3; y < im.h; ++y)
    for (int x = 0; x < im.w; ++x) {
      blue += im.near(x, y, 0, 114, 178, 30);
      grey += im.near(x, y, 170, 170, 170, 6);
    }
  EXPECT_GT(blue, 600) << "record trace pixels";
  EXPECT_GT(grey, 40) << "masked-window pixels";
  // The empty view has no such traces.
  const std::string empty = tmp("ident_empty.png");
  ASSERT_EQ(run(std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --view identify --size 1200x750 --out " +
                empty),
            0);
  const Image e = load(empty);
  int blue_empty = 0;
  for (int y = e.h / 3; y < e.h; ++y)
    for (int x = 0; x < e.w; ++x) blue_empty += e.near(x, y, 0, 114, 178, 30);
  EXPECT_LT(blue_empty, 50);
}

TEST(RenderCommand, IdentifyViewRejectsABadRecordNamingItsLine) {
  const std::string csv = tmp("bad_record.csv"), out = tmp("ident_bad.png");
  {
    std::ofstream o(csv);
    o << "t_s,x_m,F_N\n";
    for (int i = 0; i < 30; ++i) o << 0.001 * i << ",0," << (i == 7 ? "oops" : "1.5") << '\n';
  }
  const std::string log = tmp("ident_bad.log");
  const int rc = std::system((std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset + " --view identify --data " +
                              csv + " --out " + out + " 2>" + log)
                                 .c_str());
  EXPECT_EQ(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, 2);
  const std::string msg = bytes(log);
  EXPECT_NE(msg.find("bad_record.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad_record.csv:9:"), std::string::npos) << msg;  // header is line 1, i = 7 is line 9
  EXPECT_NE(msg.find("F_N"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(out));
}
