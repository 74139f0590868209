// GMS has two element loops (GmsModel::kScalarElements): a scalar loop with branches for few
// elements and a branch-free vectorised loop beyond. Both must be the same model. Splitting every
// element into three equal thirds (alpha/3, k/3, sigma/3) leaves each third with the element's
// own displacement dynamics, so the 12-element model (vectorised loop) must give exactly a third of
// each element force of the 4-element model (scalar loop), the same stick/slip states, and the
// same total force: checked on the Fig. 4 stick-slip run and on a presliding hysteresis drive.
#include <gtest/gtest.h>

#include "core/friction/gms.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

ModelParams split_in_thirds(const GmsParams& g) {
  GmsParams t = g;
  t.alpha.clear();
  t.k.clear();
  t.sigma.clear();
  for (int copy = 0; copy < 3; ++copy)
    for (std::size_t i = 0; i < g.alpha.size(); ++i) {
      t.alpha.push_back(g.alpha[i] / 3);
      t.k.push_back(g.k[i] / 3);
      t.sigma.push_back(g.sigma[i] / 3);
    }
  return t.to_params();
}

void expect_same_model(const Scenario& four) {
  ASSERT_LE(GmsParams::from(four.friction).alpha.size(), GmsModel::kScalarElements);
  Scenario twelve = four;
  twelve.friction = split_in_thirds(GmsParams::from(four.friction));
  ASSERT_GT(twelve.friction.elements.size(), GmsModel::kScalarElements);
  const Trace a = simulate(four), b = simulate(twelve);
  ASSERT_EQ(a.size(), b.size());
  std::size_t slipping = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_NEAR(a.friction[k], b.friction[k], 1e-9) << "t = " << a.t[k] << " s";
    ASSERT_NEAR(a.x[k], b.x[k], 1e-9) << "t = " << a.t[k] << " s";
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        ASSERT_NEAR(a.element_force[k * 4 + i] / 3, b.element_force[k * 12 + c * 4 + i], 1e-9);
        ASSERT_EQ(a.element_slip[k * 4 + i], b.element_slip[k * 12 + c * 4 + i])
            << "element " << i << " at t = " << a.t[k] << " s";
      }
    for (std::size_t i = 0; i < 4; ++i) slipping += a.element_slip[k * 4 + i];
  }
  // Both regimes were visited, so both branches of the scalar loop were compared.
  EXPECT_GT(slipping, 0u);
  EXPECT_LT(slipping, 4 * a.size());
}

TEST(GmsPaths, ScalarAndVectorisedLoopsAgreeOnStickSlip) {
  Scenario s = load_scenario(test_util::preset_path("fig4_stick_slip.json"));
  s.run.duration = 16.0;  // two slip events
  expect_same_model(s);
}

TEST(GmsPaths, ScalarAndVectorisedLoopsAgreeOnPreslidingHysteresis) {
  const Signal x = Signal::turning_points(0.0, 1e-4, {1.5e-5, -1.5e-5, 5e-6, -2e-6, 1.5e-5});
  expect_same_model(test_util::gms_displacement_scenario(x, x.natural_end(), 1e-3));
}

}  // namespace
}  // namespace gmslab
