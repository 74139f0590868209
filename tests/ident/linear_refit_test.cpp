// LinearRefit (fit.hpp) is refit_linear with the record's fixed columns built once: at every
// shape, its RMS and its fit are refit_linear's bit for bit, in any order of shapes (the object's
// caches hold nothing that depends on the previous shape). Checked on records of the synthetic
// GMS rig with each catalog effect (the scalars of the ripple, time shift, sensor filter and
// backlash columns set), at random shapes of the unit box, in random order and revisited. The rig
// records no normal force: normal_load there is an InputError.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/ident/fit.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

TEST(LinearRefit, EqualsRefitLinearBitForBitAtEveryShape) {
  std::mt19937 rng(9402);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int cases = 0;
  for (const Effect e : effect_catalog()) {
    synth::SynthOptions so;
    so.seed = 9402 + static_cast<unsigned>(cases);
    so.moves = 6;
    so.level = std::pow(10.0, 2.0 * U(rng) - 1.0);
    const Dataset d = prepare_dataset(synth::synthesize(so));
    EffectContext c = make_context(d);
    c.backlash = 2e-6 * (1.0 + U(rng));
    c.filter_T = 1e-3 * (1.0 + U(rng));
    c.time_shift = 1e-3 * (1.0 + U(rng));
    c.wavelengths = {1e-3 * (1.0 + U(rng))};
    FitSpec spec;
    spec.elements = 1 + rng() % 4;
    spec.effects = {e};
    if (e == Effect::NormalLoad) {
      // The rig records no normal force: an error that says so, not a crash.
      EXPECT_FALSE(effect_applicable(e, d, c));
      EXPECT_THROW(
          refit_linear(spec, d, c,
                       std::vector<double>(
                           Parameterization(model_info(spec.model), spec.elements, c).size(), 0.5)),
          InputError);
      ++cases;
      continue;
    }
    const std::size_t dim = Parameterization(model_info(spec.model), spec.elements, c).size();
    std::vector<std::vector<double>> shapes(6, std::vector<double>(dim));
    for (auto& u : shapes)
      for (auto& x : u) x = U(rng);
    LinearRefit on(spec, d, c);
    // Each shape twice, in an order that revisits: 0 1 2 3 4 5 2 0 5 1 4 3.
    const std::size_t order[] = {0, 1, 2, 3, 4, 5, 2, 0, 5, 1, 4, 3};
    for (const std::size_t i : order) {
      const FitResult ref = refit_linear(spec, d, c, shapes[i]);
      const double r = on.rms(shapes[i]);
      EXPECT_EQ(r, ref.rms_train) << effect_name(e) << ", shape " << i;
      const FitResult f = on.fit(shapes[i]);
      EXPECT_EQ(f.rms_train, ref.rms_train) << effect_name(e) << ", shape " << i;
      EXPECT_EQ(f.theta, ref.theta) << effect_name(e) << ", shape " << i;
      EXPECT_EQ(f.u, ref.u);
    }
    ++cases;
  }
  EXPECT_EQ(cases, static_cast<int>(effect_catalog().size()));
  EXPECT_GE(cases, 10);
}
