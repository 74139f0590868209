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


// Any registered model can be fitted through its ModelInfo: the identified parameters are valid
// for the model, and every model with a state (presliding memory) explains most of the force of a
// GMS record. Static models (state-free) return zero force at rest while the GMS record holds
// its presliding force through every dwell, so they only have to beat the zero model.
TEST(IdentFit, EveryRegisteredModelFitsThroughItsModelInfo) {
  synth::SynthOptions so;
  so.moves = 4;
  so.rate = 250.0;
  const auto d = prepare_dataset(synth::synthesize(so));
  const auto c = make_context(d);
  double f2 = 0;
  for (std::size_t k = 0; k < d.size(); ++k) f2 += d.F[k] * d.F[k];
  const double null_rms = std::sqrt(f2 / static_cast<double>(d.size()));
  for (const auto& info : model_registry()) {
    FitSpec spec;
    spec.model = std::string(info.tag);
    spec.elements = 2;
    FitOptions o;
    o.starts = 1;
    o.max_evaluations = 60;
    const auto r = fit_model(spec, d, c, o);
    EXPECT_TRUE(validate(r.friction).empty()) << info.tag;
    const bool dynamic = build_model(info.defaults())->state_size() > 0;
    EXPECT_LT(r.rms_train, (dynamic ? 0.2 : 0.9) * null_rms) << info.tag;
    std::printf("  %-14s rms %.3f N\n", std::string(info.tag).c_str(), r.rms_train);
  }
}
