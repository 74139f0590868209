// Tests of the variable-projection fit on records generated with gmslab's own GMS model.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "core/ident/fit.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

TEST(IdentFit, GmsFitOfCleanGmsRecordReachesNoiseLevel) {
  synth::SynthOptions so;
  const auto rec = synth::synthesize(so);
  const auto d = prepare_dataset(rec);
  const auto c = make_context(d);
  FitOptions o;
  o.starts = 2;
  FitSpec spec;
  auto t0 = std::chrono::steady_clock::now();
  const auto r = fit_model(spec, d, c, o);
  auto dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("n=%zu evals=%d rms=%.4f time=%.2fs x_ba=%.3g f_level=%.3g vref=%.3g\n", d.size(), r.evaluations, r.rms_train, dt, c.x_ba, c.f_level, c.v_ref);
  for (const auto& t : r.terms) std::printf("  %s %s = %g %s\n", t.effect.c_str(), t.name.c_str(), t.value, t.unit.c_str());
  for (std::size_t i = 0; i < r.friction.scalars.size(); ++i) std::printf("  scalar %zu = %g\n", i, r.friction.scalars[i]);
  for (auto& row : r.friction.elements) std::printf("  el alpha=%g k=%g\n", row[0], row[1]);
  EXPECT_LT(r.rms_train, 1.3 * so.noise);
}

