// Plant-source benchmarks (core/control/design_plant.hpp): the loop on the assembled two-mass
// train (1 s of the view's step), and one full recomputation of the design view on it (collocated:
// plant from the drive to the motor's position, locus, design, Bode / Nyquist, linear step and both
// loops on the assembled nonlinear plant). Target for the view: < 16 ms.
#include <benchmark/benchmark.h>

#include "core/control/design_session.hpp"
#include "core/control/design_settings.hpp"
#include "core/io/assembly_io.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
AssemblyScenario two_mass() {
  return load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json");
}
}  // namespace

static void BM_AssembledLoop1s(benchmark::State& st) {
  const AssemblyScenario s = two_mass();
  const AssemblyPort port = assembly_port(s.plant, "motor_force", "x.motor");
  LoopConfig c;
  c.C = {4105.21, 6.41952, 128.39};  // the usable-maximum lead at zeta 0.7, wn 10 rad/s (sliding)
  c.reference = Signal::sine(0.0, 0.01, 2.0);
  c.comp = Compensation::Gms;
  c.dt = 1e-5;
  c.duration = 1.0;
  for (auto _ : st) benchmark::DoNotOptimize(simulate_loop(s, port, c).x.back());
  st.counters["steps/s"] = benchmark::Counter(1e5, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AssembledLoop1s)->Unit(benchmark::kMillisecond);

static void BM_DesignViewFrameAssembled(benchmark::State& st) {
  DesignSettings ds;
  ds.plant.source = PlantSource::Assembly;
  ds.wn = 10.0;
  DesignInputs in;
  in.assembly = two_mass();
  set_design_inputs(ds, in);
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty()) st.SkipWithError(out.error.c_str());
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFrameAssembled)->Unit(benchmark::kMillisecond);
