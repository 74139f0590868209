// Uses gmslab::core from an installed package: loads an installed preset, simulates it, and
// steps a registry GMS model at constant velocity until its force reaches the model's own
// steady-state curve. Exit 0 when both behave, 1 otherwise.
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/friction/model.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

int main(int argc, char** argv) {
  using namespace gmslab;
  if (argc < 2) {
    std::fprintf(stderr, "usage: core_consumer PRESET.json\n");
    return 2;
  }
  AssemblySimulation sim = one_body_simulation(load_scenario(argv[1]));
  sim.run_to_end();
  const Trace& tr = sim.one_body_trace();
  std::printf("simulated %zu samples of %s, last friction %.6g N\n", tr.size(), argv[1], tr.friction.back());

  auto model = build_model(model_info("gms").defaults());
  std::vector<double> state(model->state_size());
  model->reset(state);
  const double v = 0.01;  // [m/s]
  double f = 0.0;
  for (int i = 0; i < 100000; ++i) f = model->step(state, {v, 1e-5, 0.0, 0.0});
  const double ss = model->steady_state(v);
  std::printf("GMS at %.3g m/s: %.6g N after 1 s, steady state %.6g N\n", v, f, ss);
  return tr.size() > 1 && std::isfinite(tr.friction.back()) && std::abs(f - ss) < 1e-3 * std::abs(ss) ? 0 : 1;
}
