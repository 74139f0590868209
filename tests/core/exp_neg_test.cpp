// exp_neg, the exp(-x) on every friction step's latency chain: its polynomial and underflow fast
// paths must agree with libm's exp(-x) to the last bit or so, over the whole range and at the
// seams between the paths.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/friction/stribeck.hpp"

namespace gmslab {
namespace {

double ulps_apart(double a, double b) {
  if (a == b) return 0.0;
  const double ulp = std::nextafter(b, INFINITY) - b;
  return std::abs(a - b) / ulp;
}

TEST(ExpNeg, PolynomialPathIsWithinOneUlpOfLibmExp) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 1000000; ++i) {
    // Uniform on [0, 1/64) and log-uniform down to 1e-18: both ends of the polynomial's range.
    const double x = (i % 2 ? u(rng) : std::pow(10.0, -18.0 * u(rng))) / 64.0;
    worst = std::max(worst, ulps_apart(exp_neg(x), std::exp(-x)));
  }
  EXPECT_LE(worst, 1.0);
  EXPECT_EQ(exp_neg(0.0), 1.0);
}

TEST(ExpNeg, SeamsAndLargeArgumentsMatchLibm) {
  const double seam = 1.0 / 64;
  for (double x : {std::nextafter(seam, 0.0), seam, std::nextafter(seam, 1.0), 2e-3, 0.5, 1.0,
                   30.0, 700.0, 744.9})
    EXPECT_LE(ulps_apart(exp_neg(x), std::exp(-x)), 1.0) << "x = " << x;
  // Beyond 745, exp(-x) is below the smallest subnormal (4.9e-324) and rounds to 0.
  EXPECT_EQ(exp_neg(745.2), 0.0);
  EXPECT_EQ(std::exp(-745.2), 0.0);
  EXPECT_EQ(exp_neg(1e300), 0.0);
}

}  // namespace
}  // namespace gmslab
