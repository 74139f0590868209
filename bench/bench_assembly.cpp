// The assembled plant (core/sim/assembly.hpp) against the one-body simulation it generalises.
//   BM_Assembly_Fig4Preset: the Fig. 4 preset (25 s, 2.5e6 steps) mapped onto the general plant;
//     compare with BM_Fig4Preset (bench_gms.cpp), the one-body path, on the same machine.
//   BM_Assembly_Chain3Gms2_1e6: presets/three_body_chain.json (3 bodies, 2 springs, 2 dampers, 2
//     GMS contacts of 4 elements, pull drive) for 1e6 steps (10 s at dt = 1e-5 s).
//   BM_Assembly_Chain3Gms2_1e6_Bounded: the same, every step recorded into a trace bounded to
//     1 MiB (the Plant tab's compaction, compact_minmax).
#include <benchmark/benchmark.h>

#include "core/io/assembly_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

using namespace gmslab;

static void BM_Assembly_Fig4Preset(benchmark::State& st) {
  const AssemblyScenario sc =
      assembly_from_scenario(load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json"));
  for (auto _ : st) {
    auto tr = simulate(sc);
    benchmark::DoNotOptimize(tr.values.data());
  }
  st.counters["steps_per_s"] = benchmark::Counter(2.5e6 * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Assembly_Fig4Preset)->Unit(benchmark::kMillisecond);

static void BM_Assembly_Chain3Gms2_1e6(benchmark::State& st) {
  AssemblyScenario sc = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/three_body_chain.json");
  sc.run.duration = 10.0;  // 1e6 steps
  for (auto _ : st) {
    auto tr = simulate(sc);
    benchmark::DoNotOptimize(tr.values.data());
  }
  st.counters["steps_per_s"] = benchmark::Counter(1e6 * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Assembly_Chain3Gms2_1e6)->Unit(benchmark::kMillisecond);

static void BM_Assembly_Chain3Gms2_1e6_Bounded(benchmark::State& st) {
  AssemblyScenario sc = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/three_body_chain.json");
  sc.run.duration = 10.0;  // 1e6 steps
  sc.run.record_every = 1;
  for (auto _ : st) {
    AssemblySimulation sim(sc, TraceOptions{.max_bytes = std::size_t{1} << 20});
    sim.run_to_end();
    benchmark::DoNotOptimize(sim.trace().values.data());
  }
  st.counters["steps_per_s"] = benchmark::Counter(1e6 * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Assembly_Chain3Gms2_1e6_Bounded)->Unit(benchmark::kMillisecond);
