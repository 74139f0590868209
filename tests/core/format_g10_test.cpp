// format_g10 (core/text/format_g10.hpp) writes what printf's "%.10g" writes, byte for byte: checked
// against std::snprintf on random bit patterns (every exponent, subnormals, infinities and NaNs),
// random magnitudes from 1e-20 to 1e20, short decimals (many trailing zeros), values next to the
// powers of ten and to the 10-digit rounding boundaries (x.5 in the 10th digit), and exact ties;
// millions of values over the whole exponent range; and format_g10_cached (a column's previous text
// copied while a value lies in its interval) on columns that repeat, drift across rounding
// boundaries, and at the bounds of the interval.
#include "core/text/format_g10.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace gmslab {
namespace {

struct Check {
  long cases = 0, wrong = 0;
  void operator()(double x) {
    char want[64], got[kFormatG10MaxChars + 8];
    const int n = std::snprintf(want, sizeof want, "%.10g", x);
    const char* end = format_g10(x, got);
    ++cases;
    if (end - got != n || std::memcmp(want, got, static_cast<std::size_t>(n)) != 0) {
      if (++wrong <= 5)
        ADD_FAILURE() << "x = " << std::to_string(x) << ": printf '" << want << "', format_g10 '"
                      << std::string(static_cast<const char*>(got), end) << "'";
    }
  }
};

TEST(FormatG10, RandomBitPatternsAsPrintf) {
  std::mt19937_64 rng(91);
  Check check;
  for (int i = 0; i < 400000; ++i) {
    const std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    check(x);
  }
  EXPECT_EQ(check.cases, 400000);
  EXPECT_EQ(check.wrong, 0);
}

TEST(FormatG10, RandomMagnitudesAndShortDecimalsAsPrintf) {
  std::mt19937_64 rng(92);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Check check;
  for (int i = 0; i < 300000; ++i) {
    check(u(rng) * std::pow(10.0, static_cast<int>(rng() % 41) - 20));
    check(std::round(u(rng) * 1e12) /
          std::pow(10.0, static_cast<int>(rng() % 16)));  // trailing zeros
    check(static_cast<double>(rng() % 100000) * 1e-5);    // a time axis
  }
  EXPECT_EQ(check.cases, 900000);
  EXPECT_EQ(check.wrong, 0);
}

// Next to every power of ten, to the largest 10-digit values (which round up a decade) and to the
// half-way points of the 10th digit, one ulp either side; exact ties; zeros and the extremes.
TEST(FormatG10, DecadeAndRoundingBoundariesAsPrintf) {
  Check check;
  for (int k = -30; k <= 32; ++k) {
    for (double d :
         {1.0, 9.9999999995, 9.99999999949, 9.9999999996, 5.0, 1.00000000005, 2.50000000005}) {
      const double x = d * std::pow(10.0, k);
      for (double y : {x, std::nextafter(x, 0.0), std::nextafter(x, 1e308), -x}) check(y);
    }
  }
  for (double x :
       {0.0, -0.0, 0.5, 1234567890.5, 9999999999.5, 12345.678905, 1e-4, 1e-5, 9.99999999995e-5,
        1e10, 1e300, -1e-300, 5e-324, 1.7976931348623157e308,
        std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::quiet_NaN()})
    check(x);
  EXPECT_EQ(check.cases, 63 * 7 * 4 + 17);
  EXPECT_EQ(check.wrong, 0);
}

// 3.2 million values drawn over the whole range, with fixed seeds: random bit patterns of every
// binary exponent (subnormals included), integers, negative numbers, 10-digit rounding ties
// (d.ddddddddd5 * 10^k) and values that round up to the next power of ten, +-0.
TEST(FormatG10, MillionsOfValuesOverTheWholeRangeAsPrintf) {
  std::mt19937_64 rng(93);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Check check;
  for (int i = 0; i < 400000; ++i) {
    const double sign = rng() % 2 ? -1.0 : 1.0;
    // a mantissa with every binary exponent, subnormals (exponent field 0) included
    const std::uint64_t bits = (rng() & 0x000fffffffffffffULL) | ((rng() % 2047) << 52);
    double x;
    std::memcpy(&x, &bits, sizeof x);
    check(sign * x);
    check(sign * static_cast<double>(rng() % 100000000000ULL));  // integers up to 1e11
    const double tie = static_cast<double>(1000000000 + rng() % 9000000000ULL) + 0.5;
    const int k = static_cast<int>(rng() % 601) - 300;
    check(sign * tie * std::pow(10.0, k - 9));       // a 10th-digit tie, rounded to double
    check(sign * 9.9999999995 * std::pow(10.0, k));  // rounds up to the next decade, or not
    check(sign * (1.0 + u(rng)) * std::pow(10.0, static_cast<int>(rng() % 61) - 30));
    const double y = sign * u(rng) * std::pow(10.0, static_cast<int>(rng() % 31) - 15);
    check(y);
    check(std::nextafter(y, 0.0));
    check(sign * 0.0);
  }
  EXPECT_EQ(check.cases, 8 * 400000);
  EXPECT_EQ(check.wrong, 0);
}

// format_g10_cached as a CSV column uses it: each value written a row apart in one buffer, the
// previous row's text copied while the value lies in its interval.
struct CachedColumn {
  std::vector<char> buf = std::vector<char>(64 * 4);
  G10Last last;
  long rows = 0, cases = 0, wrong = 0, copied = 0;
  void operator()(double x) {
    char* at = buf.data() + 64 * (rows++ % 4);
    const G10Last before = last;
    const char* end = format_g10_cached(x, at, last);
    char want[64];
    const int n = std::snprintf(want, sizeof want, "%.10g", x);
    ++cases;
    copied += x > before.lo && x < before.hi;
    if (end - at != n || std::memcmp(want, at, static_cast<std::size_t>(n)) != 0) {
      if (++wrong <= 5)
        ADD_FAILURE() << "x = " << std::to_string(x) << ": printf '" << want << "', cached '"
                      << std::string(static_cast<const char*>(at), end) << "'";
    }
  }
};

// Random walks whose steps are small against the 10th digit (most rows repeat the text above, some
// cross a rounding boundary), over every decade from 1e-15 to 1e15, both signs, and through zero.
TEST(FormatG10, CachedColumnsRepeatingAndDriftingAsPrintf) {
  std::mt19937_64 rng(94);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  long cases = 0, copied = 0;
  for (int walk = 0; walk < 300; ++walk) {
    CachedColumn column;
    const double scale = std::pow(10.0, static_cast<int>(rng() % 31) - 15);
    double x = u(rng) * scale;
    const double step = scale * std::pow(10.0, -8.0 - static_cast<double>(rng() % 5));
    for (int i = 0; i < 5000; ++i) {
      column(x);
      if (rng() % 4 != 0) x += u(rng) * step;  // else the same value again
      if (rng() % 1000 == 0) x = -x;
    }
    EXPECT_EQ(column.wrong, 0) << "walk " << walk;
    cases += column.cases;
    copied += column.copied;
  }
  EXPECT_EQ(cases, 300 * 5000);
  // The interval is taken for most values (not a test of nothing): at least a quarter copied.
  EXPECT_GT(copied, cases / 4);
}

// The values at and next to both bounds of the interval, and at the true rounding boundaries
// (m -+ 0.5) * 10^-s a few ulps either side: copied or computed, always printf's text.
TEST(FormatG10, CachedAtTheBoundsOfTheIntervalAsPrintf) {
  std::mt19937_64 rng(95);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  long cases = 0, wrong = 0, copied = 0, with_interval = 0;
  for (int i = 0; i < 200000; ++i) {
    CachedColumn first;
    const double x = u(rng) * std::pow(10.0, static_cast<int>(rng() % 41) - 20);
    first(x);
    char text[64];
    std::snprintf(text, sizeof text, "%.9e", std::fabs(x));  // d.ddddddddde+XX: m and k
    const double m = std::stod(std::string(1, text[0]) + std::string(text + 2, 9));
    const int k = std::atoi(text + 12);
    with_interval += first.last.lo < first.last.hi;
    std::vector<double> ys = {first.last.lo, first.last.hi, std::nextafter(first.last.lo, 1e308),
                              std::nextafter(first.last.hi, -1e308)};
    for (double half : {-0.5, 0.5}) {
      const double b = std::copysign((m + half) * std::pow(10.0, k - 9), x);
      double y = b;
      for (int j = 0; j < 3; ++j) y = std::nextafter(y, 0.0);
      for (int j = 0; j < 7; ++j, y = std::nextafter(y, std::copysign(1e308, x))) ys.push_back(y);
    }
    for (double y : ys) {
      CachedColumn column = first;  // x's text in its buffer, its interval
      column.wrong = column.copied = column.cases = 0;
      column(y);
      cases += column.cases;
      wrong += column.wrong;
      copied += column.copied;
    }
  }
  EXPECT_EQ(cases, 200000L * 18);
  EXPECT_EQ(wrong, 0);
  // Every value from 1e-13 on has an interval, and the two values just inside its bounds are
  // copied.
  EXPECT_GT(with_interval, 150000);
  EXPECT_GE(copied, 2 * with_interval);
}

}  // namespace
}  // namespace gmslab
