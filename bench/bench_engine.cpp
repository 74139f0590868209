// The engine on the one-body presets, as the CLI, Python and the sweeps run them:
//   BM_Engine_Fig4: the Fig. 4 preset (25 s, 2.5e6 steps, a GMS contact of 4 elements pulled
//     through a spring) through simulate(Scenario), the one-body trace recorded every 10 steps.
//   BM_Engine_Fig2a: the prescribed-displacement preset (12,700 steps, every step recorded).
//   BM_Engine_Fig4Path/0: Fig. 4 as an assembled plant (the assembled trace layout), /1: as
//     one_body_simulation (the one-body layout), both through AssemblySimulation::run_to_end.
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

using namespace gmslab;

namespace {
Scenario preset(const char* name) { return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name); }

void run(benchmark::State& st, const Scenario& sc) {
  for (auto _ : st) {
    const Trace tr = simulate(sc);
    benchmark::DoNotOptimize(tr.x.back());
  }
  const double steps = std::round(sc.run.duration / sc.run.dt);
  st.counters["steps_per_s"] = benchmark::Counter(steps * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
}  // namespace

static void BM_Engine_Fig4(benchmark::State& st) { run(st, preset("fig4_stick_slip.json")); }
BENCHMARK(BM_Engine_Fig4)->Unit(benchmark::kMillisecond);

static void BM_Engine_Fig2a(benchmark::State& st) { run(st, preset("fig2a_presliding.json")); }
BENCHMARK(BM_Engine_Fig2a)->Unit(benchmark::kMicrosecond);

static void BM_Engine_Fig4Path(benchmark::State& st) {
  const Scenario sc = preset("fig4_stick_slip.json");
  for (auto _ : st) {
    if (st.range(0) == 0) {
      AssemblySimulation sim(assembly_from_scenario(sc));
      sim.run_to_end();
      benchmark::DoNotOptimize(sim.trace().values.back());
    } else {
      AssemblySimulation sim = one_body_simulation(sc);
      sim.run_to_end();
      benchmark::DoNotOptimize(sim.one_body_trace().x.back());
    }
  }
}
BENCHMARK(BM_Engine_Fig4Path)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
