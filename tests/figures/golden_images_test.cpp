// Golden images: `gmslab-headless figures` renders the whole set and every PNG is compared with
// the checked-in one in tests/golden/ (same size), with the tolerance of golden_compare.hpp.
// The test also proves it can fail: erasing one curve or one axis from a golden image must trip it.
// Regenerate after an intended change: GMSLAB_UPDATE_GOLDEN=1 ./build/gmslab_tests
// --gtest_filter='GoldenImages*' (then look at every PNG before committing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <filesystem>
#include <string>
#include <vector>

#include "core/figures/figure_set.hpp"

#ifdef GMSLAB_HEADLESS_EXE
#include <unistd.h>

#include "tests/figures/golden_compare.hpp"
#endif

namespace gmslab {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 1000, kHeight = 560;

#ifdef GMSLAB_HEADLESS_EXE
using golden::acceptable;
using golden::compare;
using golden::Difference;
using golden::Image;
using golden::load;

const std::string kGolden = std::string(GMSLAB_SOURCE_DIR) + "/tests/golden";

fs::path render_dir() { return fs::temp_directory_path() / ("gmslab_golden_" + std::to_string(getpid())); }

// The renders are kept for inspection when a comparison failed, removed otherwise.
struct RemoveRendersIfPassed : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    if (::testing::UnitTest::GetInstance()->Passed()) fs::remove_all(render_dir(), ec);
  }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new RemoveRendersIfPassed);

// Renders the set once for all tests of this file.
const std::string& rendered_dir() {
  static const std::string dir = [] {
    const fs::path d = render_dir();
    fs::create_directories(d);
    const std::string cmd = std::string(GMSLAB_HEADLESS_EXE) + " figures --out " + d.string() +
                            " --size " + std::to_string(kWidth) + "x" + std::to_string(kHeight) +
                            " 2>/dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return d.string();
  }();
  return dir;
}

TEST(GoldenImages, EveryFigureMatchesItsGoldenImage) {
  const bool update = std::getenv("GMSLAB_UPDATE_GOLDEN") != nullptr;
  for (const auto& id : figure_ids()) {
    const std::string out = rendered_dir() + "/" + id + ".png", gold = kGolden + "/" + id + ".png";
    if (update) fs::copy_file(out, gold, fs::copy_options::overwrite_existing);
    const Image a = load(out), b = load(gold);
    ASSERT_EQ(a.w, kWidth) << out;
    ASSERT_EQ(b.w, kWidth) << gold << " (missing golden image? see the comment at the top)";
    ASSERT_EQ(a.h, b.h) << id;
    const Difference d = compare(a, b);
    EXPECT_TRUE(acceptable(d, a)) << id << ": " << d.strong_pixels << " strongly different pixels, "
                                  << "worst 8x8 block " << d.worst_block << " levels";
  }
}

// Sensitivity: erase the most frequent saturated colour (a curve) of fig2b, or a 3-pixel band of
// the left axis of fig2a; each must fail the comparison against the untouched golden image.
TEST(GoldenImages, ComparisonCatchesAMissingCurveAndAMissingAxis) {
  const Image lag = load(kGolden + "/fig2b_frictional_lag.png");
  ASSERT_EQ(lag.w, kWidth);
  std::map<int, std::size_t> colours;
  for (int y = 0; y < lag.h; ++y)
    for (int x = 0; x < lag.w; ++x) {
      const int r = lag.at(x, y, 0), g = lag.at(x, y, 1), b = lag.at(x, y, 2);
      if (std::max({r, g, b}) - std::min({r, g, b}) > 80) ++colours[(r << 16) | (g << 8) | b];
    }
  ASSERT_FALSE(colours.empty());
  const int curve = std::max_element(colours.begin(), colours.end(), [](auto& a, auto& b) {
                      return a.second < b.second;
                    })->first;
  Image no_curve = lag;
  const int bg[3] = {lag.at(lag.w / 2, 2, 0), lag.at(lag.w / 2, 2, 1), lag.at(lag.w / 2, 2, 2)};
  for (int y = 0; y < lag.h; ++y)
    for (int x = 0; x < lag.w; ++x) {
      const int r = lag.at(x, y, 0), g = lag.at(x, y, 1), b = lag.at(x, y, 2);
      if (((r << 16) | (g << 8) | b) == curve)
        for (int c = 0; c < 3; ++c) no_curve.rgb[(static_cast<std::size_t>(y) * lag.w + x) * 3 + c] = bg[c];
    }
  EXPECT_FALSE(acceptable(compare(no_curve, lag), lag)) << "a missing curve went unnoticed";

  const Image pre = load(kGolden + "/fig2a_presliding.png");
  ASSERT_EQ(pre.w, kWidth);
  // The left axis: the column (left third) with the longest run of identical dark-grey pixels.
  int axis_x = -1;
  std::size_t best = 0;
  for (int x = 0; x < pre.w / 3; ++x) {
    std::size_t run = 0, longest = 0;
    for (int y = 1; y < pre.h; ++y) {
      const bool same = pre.at(x, y, 0) == pre.at(x, y - 1, 0) && pre.at(x, y, 0) < 200 &&
                        pre.at(x, y, 0) == pre.at(x, y, 2);
      run = same ? run + 1 : 0;
      longest = std::max(longest, run);
    }
    if (longest > best) best = longest, axis_x = x;
  }
  ASSERT_GT(best, 100u);
  Image no_axis = pre;
  for (int y = 0; y < pre.h; ++y)
    for (int x = std::max(0, axis_x - 1); x <= std::min(pre.w - 1, axis_x + 1); ++x)
      for (int c = 0; c < 3; ++c)
        no_axis.rgb[(static_cast<std::size_t>(y) * pre.w + x) * 3 + c] = pre.at(pre.w / 2, 2, c);
  EXPECT_FALSE(acceptable(compare(no_axis, pre), pre)) << "a missing axis went unnoticed";
}
#else
TEST(GoldenImages, EveryFigureMatchesItsGoldenImage) {
  GTEST_SKIP() << "built without the app (GMSLAB_BUILD_APP=OFF): no headless renderer";
}
#endif

}  // namespace
}  // namespace gmslab
