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
  std::printf("n=%zu evaluations=%d rms=%.4f N (%.2f s)\n", d.size(), r.evaluations, r.rms_train, dt);
  EXPECT_LT(r.rms_train, 1.3 * so.noise);
  // The shared Stribeck curve and viscous term of the generating model are recovered.
  const auto g = synth::synth_gms();
  EXPECT_NEAR(r.friction.scalar("Fs"), g.S.Fs, 0.02 * g.S.Fs);
  EXPECT_NEAR(r.friction.scalar("Fc"), g.S.Fc, 0.02 * g.S.Fc);
  EXPECT_NEAR(r.friction.scalar("Vs"), g.S.Vs, 0.1 * g.S.Vs);
  EXPECT_NEAR(r.friction.scalar("sigma2"), g.sigma2, 0.05 * g.sigma2);
  double sum = 0;
  for (double a : r.friction.column("alpha")) sum += a;
  EXPECT_NEAR(sum, 1.0, 1e-9);
}

