// format_g10 (core/text/format_g10.hpp) writes what printf's "%.10g" writes, byte for byte: checked
// against std::snprintf on random bit patterns (every exponent, subnormals, infinities and NaNs),
// random magnitudes from 1e-20 to 1e20, short decimals (many trailing zeros), values next to the
// powers of ten and to the 10-digit rounding boundaries (x.5 in the 10th digit), and exact ties.
#include "core/text/format_g10.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

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

}  // namespace
}  // namespace gmslab
