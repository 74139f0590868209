// The measured-velocity feedforward (LoopConfig::feedforward_source): the Fig. 4 friction loop with
// the GMS compensator driven by the plant's velocity (against BM_FrictionLoop1s, driven by the
// reference), and one design-view frame with it on (adds the compensated describing-function
// prediction on F - F_hat to BM_DesignViewFrame). Target for the view: < 16 ms.
#include <benchmark/benchmark.h>

#include "core/control/design_session.hpp"
#include "core/io/scenario_io.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
Scenario fig4() { return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"); }
}  // namespace

static void BM_FrictionLoopMeasuredFeedforward1s(benchmark::State& st) {
  const Scenario s = fig4();
  LoopConfig c;
  c.C = {4440.18, 8.47263, 94.05};
  c.reference = Signal::sine(0.0, 0.01, 1.0);
  c.comp = Compensation::Gms;
  c.feedforward_source = FeedforwardSource::Measured;
  c.duration = 1.0;
  for (auto _ : st) benchmark::DoNotOptimize(simulate_loop(s, c).x.back());
  st.counters["steps/s"] = benchmark::Counter(1e5, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FrictionLoopMeasuredFeedforward1s)->Unit(benchmark::kMillisecond);

static void BM_DesignViewFrameMeasuredFeedforward(benchmark::State& st) {
  DesignInputs in;
  in.scenario = fig4();
  in.regime = Regime::Sliding;
  in.root = {0.7, 60.0};
  in.K = 1000.0;
  in.reference = Signal::sine(0.0, 0.01, 2.0);
  in.feedforward_source = FeedforwardSource::Measured;
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty() || !out.limit_cycles_compensated) st.SkipWithError("no compensated prediction");
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFrameMeasuredFeedforward)->Unit(benchmark::kMillisecond);
