// One engine for every preset, side by side with the one-body Simulation it replaces in
// simulate(Scenario), the CLI, Python and the sweeps (run them in one invocation to compare):
//   BM_Engine_Fig4/one_body: the Fig. 4 preset (25 s, 2.5e6 steps) on Simulation.
//   BM_Engine_Fig4/assembled: the same through simulate(Scenario) (the assembled plant's engine,
//     its trace laid out as the one-body trace).
//   BM_Engine_Fig2a/one_body, /assembled: the prescribed-displacement preset (12,700 steps), the
//     same two ways.
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"

using namespace gmslab;

namespace {
Scenario preset(const char* name) { return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name); }

void run(benchmark::State& st, const Scenario& sc, bool assembled) {
  for (auto _ : st) {
    Trace tr;
    if (assembled) {
      tr = simulate(sc);
    } else {
      Simulation sim(sc);
      sim.run_to_end();
      tr = sim.take_trace();
    }
    benchmark::DoNotOptimize(tr.x.back());
  }
  const double steps = std::round(sc.run.duration / sc.run.dt);
  st.counters["steps_per_s"] = benchmark::Counter(steps * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
}  // namespace

static void BM_Engine_Fig4(benchmark::State& st) { run(st, preset("fig4_stick_slip.json"), st.range(0) == 1); }
BENCHMARK(BM_Engine_Fig4)->ArgName("assembled")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

static void BM_Engine_Fig2a(benchmark::State& st) { run(st, preset("fig2a_presliding.json"), st.range(0) == 1); }
BENCHMARK(BM_Engine_Fig2a)->ArgName("assembled")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

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
      benchmark::DoNotOptimize(sim.trace().values.back());
    }
  }
}
BENCHMARK(BM_Engine_Fig4Path)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
