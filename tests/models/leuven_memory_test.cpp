// How close the Leuven model comes to nonlocal memory and to non-drifting, and that what is left is
// the model's, not the stepping's. F_h(z) is a Maxwell-slip model, so its memory in z is exact;
// but z follows x only as dz/dx = 1 - sgn(u)|u|^n, u = F_h/s (|u| < 1 in presliding), so a loop
// closed in x is not closed in z. The miss therefore does not change when the time step shrinks,
// and it falls as n grows (dz/dx -> 1 for |u| < 1), as does the creep under a sub-break-away
// oscillating force (Fig. 2D protocol).
#include <gtest/gtest.h>

#include <cmath>

#include "tests/models/model_protocols.hpp"

namespace gmslab {
namespace {

using testing::at_time;
using testing::preset_with;

Scenario leuven_with_n(const char* preset, double n, double dt_divisor = 1.0) {
  Scenario s = preset_with(preset, "leuven");
  s.friction.set_scalar("n", n);
  s.run.dt /= dt_divisor;
  s.run.record_every = static_cast<int>(s.run.record_every * dt_divisor);
  return s;
}

// Fig. 2A: F at 8 um after the inner loop 8 -> -3 -> 8 um minus F at 8 um before it [N].
double inner_loop_miss(double n, double dt_divisor) {
  const Trace tr = simulate(leuven_with_n("fig2a_presliding.json", n, dt_divisor));
  return at_time(tr, tr.friction, 9.0) - at_time(tr, tr.friction, 6.8);
}

// Fig. 2D: x(12 s) - x(6 s) [m].
double creep(double n) {
  const Trace tr = simulate(leuven_with_n("fig2d_nondrifting.json", n));
  return tr.x.back() - at_time(tr, tr.x, 6.0);
}

TEST(LeuvenMemory, InnerLoopMissIsTheModelsAndShrinksAsNGrows) {
  double prev = 1e300;
  for (const double n : {2.0, 8.0, 16.0}) {
    const double miss = inner_loop_miss(n, 1.0);
    EXPECT_NEAR(inner_loop_miss(n, 10.0), miss, 1e-6) << "n = " << n << ": not a stepping error";
    EXPECT_LT(std::abs(miss), prev) << "n = " << n;
    prev = std::abs(miss);
  }
  // Measured: 0.139 N (n = 2), 0.016 N (n = 8, the default), 0.001 N (n = 16).
  EXPECT_LT(prev, 2e-3);
}

TEST(LeuvenMemory, CreepUnderSubBreakAwayForceShrinksAsNGrows) {
  const double c2 = std::abs(creep(2.0)), c8 = std::abs(creep(8.0)), c16 = std::abs(creep(16.0));
  EXPECT_GT(c2, 10 * c8);
  EXPECT_GT(c8, 10 * c16);
  EXPECT_LT(c16, 0.01e-6);  // measured 14 um, 0.23 um, 0.002 um
}

}  // namespace
}  // namespace gmslab
