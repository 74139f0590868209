// GMS friction step and the Fig. 4 simulation.
//   BM_GmsStep/N/mode: one friction step of N elements; reported as ns per element-step.
//   mode 0 = sliding (all elements slip at 1 mm/s), mode 1 = presliding (small oscillation, stick)
//   BM_Fig4Preset: the whole Fig. 4 stick-slip preset (25 s at dt = 1e-5 s, 2.5e6 steps).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numeric>

#include "core/friction/gms.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"

using namespace gmslab;

namespace {
ModelParams gms_with(std::size_t n) {
  GmsParams g = GmsParams::reference(true);
  g.alpha.assign(n, 1.0 / static_cast<double>(n));
  g.k.resize(n);
  g.sigma.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    g.k[i] = 30000.0 + 45000.0 * static_cast<double>(i) / static_cast<double>(n);
    g.sigma[i] = 8.7e-4 * g.k[i];
  }
  return g.to_params();
}
}  // namespace

static void BM_GmsStep(benchmark::State& st) {
  const auto n = static_cast<std::size_t>(st.range(0));
  const bool presliding = st.range(1) == 1;
  const auto model = build_model(gms_with(n));
  std::vector<double> s(model->state_size());
  model->reset(s);
  const double h = 1e-5;
  // Bring the elements into the regime of interest.
  for (int i = 0; i < 2000; ++i) model->step(s, {presliding ? 0.0 : 1e-3, h});
  std::uint64_t k = 0;
  double acc = 0.0;
  for (auto _ : st) {
    // presliding: +-1 um/s oscillation around the loaded state (elements stay stuck);
    // sliding: steady 1 mm/s.
    const double v = presliding ? ((k++ & 1024) ? 1e-6 : -1e-6) : 1e-3;
    acc += model->step(s, {v, h});
  }
  benchmark::DoNotOptimize(acc);
  st.counters["ns_per_element_step"] = benchmark::Counter(
      static_cast<double>(st.iterations()) * static_cast<double>(n),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["ns_per_element_step"] =
      benchmark::Counter(static_cast<double>(st.iterations() * n),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_GmsStep)
    ->ArgsProduct({{4, 64, 1024}, {0, 1}})
    ->ArgNames({"N", "presliding"});

static void BM_Fig4Preset(benchmark::State& st) {
  const Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  for (auto _ : st) {
    Trace tr = simulate(sc);
    benchmark::DoNotOptimize(tr.x.back());
  }
  st.SetLabel("25 s of simulated time, dt = 1e-5 s");
}
BENCHMARK(BM_Fig4Preset)->Unit(benchmark::kMillisecond);
