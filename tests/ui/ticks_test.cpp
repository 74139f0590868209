// Nice axis ticks: steps of 1, 2, 2.5 or 5 times a power of ten, inside the range, evenly spaced.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ui/plot/ticks.hpp"

using gmslab::ui::format_tick;
using gmslab::ui::nice_ticks;

namespace {
bool nice_mantissa(double step) {
  const double m = step / std::pow(10.0, std::floor(std::log10(step)));
  for (const double k : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (std::fabs(m - k) < 1e-9 * k) return true;
  return false;
}
}  // namespace

TEST(NiceTicks, CoverEveryRandomRangeWithEvenNiceSteps) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> e(-9, 9), u(-1, 1);
  for (int n = 0; n < 2000; ++n) {
    const double scale = std::pow(10.0, e(rng));
    double lo = u(rng) * scale, hi = u(rng) * scale;
    if (lo > hi) std::swap(lo, hi);
    if (!(hi > lo)) continue;
    const int target = 2 + n % 9;
    const auto t = nice_ticks(lo, hi, target);
    ASSERT_GT(t.step, 0.0);
    EXPECT_TRUE(nice_mantissa(t.step)) << t.step;
    ASSERT_FALSE(t.values.empty()) << lo << " " << hi;
    // Inside the range, no tick missing at either end, evenly spaced.
    EXPECT_GE(t.values.front(), lo - 1e-9 * t.step);
    EXPECT_LE(t.values.back(), hi + 1e-9 * t.step);
    EXPECT_LT(t.values.front() - lo, t.step * (1 + 1e-9));
    EXPECT_LT(hi - t.values.back(), t.step * (1 + 1e-9));
    for (std::size_t i = 1; i < t.values.size(); ++i)
      EXPECT_NEAR(t.values[i] - t.values[i - 1], t.step, 1e-9 * t.step);
    // About the number asked for: the chosen step is the smallest nice one >= range / target,
    // unless that leaves a single tick; then the first target' > target that gives two.
    EXPECT_GE(t.values.size(), 2u) << lo << " " << hi;
    int used = target;
    while (t.step < (hi - lo) / used * (1 - 1e-12)) ++used;
    EXPECT_LE(t.values.size(), static_cast<std::size_t>(used) + 1);
    EXPECT_LE(used, 12);
  }
}

TEST(NiceTicks, ARangeJustShortOfTwoStepsStillGetsTwoTicks) {
  // Rounded up, 1.75 / 2 gives step 1 and a single tick (0) inside [-0.8, 0.95]: no scale.
  const auto t = nice_ticks(-0.8, 0.95, 2);
  ASSERT_GE(t.values.size(), 2u);
  EXPECT_DOUBLE_EQ(t.step, 0.5);
  EXPECT_DOUBLE_EQ(t.values.front(), -0.5);
  EXPECT_DOUBLE_EQ(t.values.back(), 0.5);
}

TEST(NiceTicks, ZeroIsAnExactTickAndDegenerateRangesGiveNone) {
  const auto t = nice_ticks(-1.5, 1.5, 6);
  bool zero = false;
  for (const double v : t.values) zero = zero || v == 0.0;
  EXPECT_TRUE(zero);
  EXPECT_DOUBLE_EQ(t.step, 0.5);
  EXPECT_TRUE(nice_ticks(1.0, 1.0).values.empty());
  EXPECT_TRUE(nice_ticks(2.0, 1.0).values.empty());
  EXPECT_TRUE(nice_ticks(0.0, INFINITY).values.empty());
  EXPECT_TRUE(nice_ticks(NAN, 1.0).values.empty());
}

TEST(FormatTick, UsesJustEnoughDecimalsForTheStep) {
  EXPECT_EQ(format_tick(0.25, 0.25), "0.25");
  EXPECT_EQ(format_tick(0.5, 0.25), "0.50");
  EXPECT_EQ(format_tick(0.1 + 0.2, 0.1), "0.3");
  EXPECT_EQ(format_tick(20.0, 10.0), "20");
  EXPECT_EQ(format_tick(-3.0, 1.0), "-3");
  EXPECT_EQ(format_tick(0.0, 1e-6), "0");
  EXPECT_EQ(format_tick(1.5e-5, 5e-6), "1.5e-05");
  EXPECT_EQ(format_tick(2e5, 1e5), "2e+05");
  // One notation for the whole axis: 50000 on an axis reaching 2e5 is scientific too.
  EXPECT_EQ(format_tick(5e4, 5e4, 2e5), "5e+04");
}
