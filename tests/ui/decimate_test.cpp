// Per-pixel-column min/max decimation keeps the drawn envelope of a trace exactly and bounds
// the number of points by the plot width.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "ui/plot/decimate.hpp"

using namespace gmslab::ui;

namespace {
struct Walk {
  std::vector<double> x, y;
};
Walk random_walk(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Walk w;
  double y = 0;
  for (std::size_t i = 0; i < n; ++i) {
    w.x.push_back(static_cast<double>(i) / static_cast<double>(n - 1));
    y += g(rng);
    w.y.push_back(y);
  }
  return w;
}

long column_of(double x, double x0, double x1, int cols) { return decimate_column(x, x0, x1, cols); }
}  // namespace

TEST(DecimateMinMax, EveryColumnKeepsItsMinimumAndMaximum) {
  const Walk w = random_walk(200000, 3);
  for (const int cols : {1, 7, 317, 1600}) {
    std::vector<std::size_t> out;
    decimate_minmax(w.x.data(), w.y.data(), w.x.size(), 0.0, 1.0, cols, out);
    EXPECT_LE(out.size(), 4u * cols + 2);
    EXPECT_TRUE(std::is_sorted(out.begin(), out.end()));
    EXPECT_EQ(std::adjacent_find(out.begin(), out.end()), out.end());
    // Independent envelope of the full trace per column.
    std::vector<double> lo(cols, INFINITY), hi(cols, -INFINITY), klo(cols, INFINITY), khi(cols, -INFINITY);
    for (std::size_t i = 0; i < w.x.size(); ++i) {
      const long c = column_of(w.x[i], 0.0, 1.0, cols);
      lo[c] = std::min(lo[c], w.y[i]);
      hi[c] = std::max(hi[c], w.y[i]);
    }
    for (const std::size_t i : out) {
      const long c = column_of(w.x[i], 0.0, 1.0, cols);
      klo[c] = std::min(klo[c], w.y[i]);
      khi[c] = std::max(khi[c], w.y[i]);
    }
    for (int c = 0; c < cols; ++c) {
      EXPECT_EQ(klo[c], lo[c]) << "column " << c << " of " << cols;
      EXPECT_EQ(khi[c], hi[c]) << "column " << c << " of " << cols;
    }
    // First and last samples are kept, so the line starts and ends where the trace does.
    EXPECT_EQ(out.front(), 0u);
    EXPECT_EQ(out.back(), w.x.size() - 1);
  }
}

TEST(DecimateMinMax, ZoomedViewKeepsOneNeighbourOutsideOnEachSide) {
  const Walk w = random_walk(10000, 5);
  std::vector<std::size_t> out;
  decimate_minmax(w.x.data(), w.y.data(), w.x.size(), 0.25, 0.5, 100, out);
  ASSERT_GE(out.size(), 3u);
  EXPECT_LT(w.x[out.front()], 0.25);
  EXPECT_GE(w.x[out[1]], 0.25);
  EXPECT_GT(w.x[out.back()], 0.5);
  EXPECT_LE(w.x[out[out.size() - 2]], 0.5);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < w.x.size(); ++i) inside += w.x[i] >= 0.25 && w.x[i] <= 0.5;
  EXPECT_GT(inside, out.size());  // it did decimate
  EXPECT_LE(out.size(), 4u * 100 + 2);
}

TEST(DecimateMinMax, ShortTraceIsKeptWhole) {
  const std::vector<double> x = {0, 1, 2, 3}, y = {1, -1, 2, 0};
  std::vector<std::size_t> out;
  decimate_minmax(x.data(), y.data(), 4, 0, 3, 1000, out);
  EXPECT_EQ(out, (std::vector<std::size_t>{0, 1, 2, 3}));
  decimate_minmax(x.data(), y.data(), 0, 0, 3, 1000, out);
  EXPECT_TRUE(out.empty());
}

TEST(DecimatePath, HysteresisLoopIsBoundedByItsLengthInPixels) {
  // 10^5 samples around a circle of radius 100 px, 3 times: the kept points cannot exceed the
  // path length in pixels divided by the minimum spacing (+ the two ends).
  PlotTransform t{-1, 1, -1, 1, 0, 0, 200, 200};
  std::vector<double> x, y;
  const std::size_t n = 100000;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 6 * M_PI * static_cast<double>(i) / (n - 1);
    x.push_back(std::cos(a));
    y.push_back(std::sin(a));
  }
  std::vector<std::size_t> out;
  decimate_path(x.data(), y.data(), n, t, 1.0, out);
  const double length_px = 3 * 2 * M_PI * 100;
  EXPECT_LE(out.size(), static_cast<std::size_t>(length_px) + 2);
  EXPECT_GE(out.size(), static_cast<std::size_t>(length_px / std::sqrt(2.0) / 2));
  EXPECT_EQ(out.front(), 0u);
  EXPECT_EQ(out.back(), n - 1);
  // No dropped sample lies more than ~1 px (in x and y) from the kept polyline's vertices.
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (k + 1 < out.size() && out[k + 1] <= i) ++k;
    EXPECT_LT(std::fabs(t.to_px_x(x[i]) - t.to_px_x(x[out[k]])), 1.0 + 1e-9);
    EXPECT_LT(std::fabs(t.to_px_y(y[i]) - t.to_px_y(y[out[k]])), 1.0 + 1e-9);
  }
}

TEST(ValueRange, MatchesAFullScanAndSkipsNaN) {
  const Walk w = random_walk(10007, 11);
  double lo = 0, hi = 0;
  value_range(w.y.data(), w.y.size(), lo, hi);
  const auto [mn, mx] = std::minmax_element(w.y.begin(), w.y.end());
  EXPECT_EQ(lo, *mn);
  EXPECT_EQ(hi, *mx);
  const std::vector<double> v = {NAN, 2.0, NAN, -1.0, 5.0};
  value_range(v.data(), v.size(), lo, hi);
  EXPECT_EQ(lo, -1.0);
  EXPECT_EQ(hi, 5.0);
  value_range(v.data(), 1, lo, hi);
  EXPECT_TRUE(lo > hi);  // nothing but NaN: empty range
}
