// Cost of one friction step of every registered model, on the same input (defaults, h = 1e-5 s):
//   BM_ModelStep/<tag>/sliding     v = 10 mm/s +- 10 % (gross sliding, Stribeck region passed)
//   BM_ModelStep/<tag>/presliding  v = 1 mm/s sin(2 pi k / 1000): +-1.6 um, all in presliding
//   BM_ModelFig2d/<tag>            the whole Fig. 2D protocol (6e5 steps with a mass)
// Reported as ns per step (the benchmark's time per iteration).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"

using namespace gmslab;

namespace {

std::vector<double> velocities(bool presliding) {
  std::vector<double> v(1000);
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double s = std::sin(2 * std::numbers::pi * static_cast<double>(k) / 1000.0);
    v[k] = presliding ? 1e-3 * s : 1e-2 * (1.0 + 0.1 * s);
  }
  return v;
}

void model_step(benchmark::State& st, const std::string& tag, bool presliding) {
  const auto model = build_model(model_info(tag).defaults());
  std::vector<double> s(model->state_size());
  model->reset(s);
  const auto v = velocities(presliding);
  const double h = 1e-5;
  for (int i = 0; i < 3; ++i)  // settle into the regime
    for (double vk : v) model->step(s, {vk, h});
  std::size_t k = 0;
  double acc = 0.0;
  for (auto _ : st) {
    acc += model->step(s, {v[k], h, 0.0, 0.0});
    k = (k + 1 == v.size()) ? 0 : k + 1;
  }
  benchmark::DoNotOptimize(acc);
  st.SetItemsProcessed(st.iterations());
}

void model_fig2d(benchmark::State& st, const std::string& tag) {
  Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2d_nondrifting.json");
  if (tag != "gms") sc.friction = model_info(tag).defaults();
  for (auto _ : st) {
    const Trace tr = simulate(sc);
    benchmark::DoNotOptimize(tr.x.back());
  }
  st.SetItemsProcessed(st.iterations() * 600000);
}

const bool registered = [] {
  for (const auto& m : model_registry()) {
    const std::string tag(m.tag);
    benchmark::RegisterBenchmark(("BM_ModelStep/" + tag + "/sliding").c_str(),
                                 [tag](benchmark::State& st) { model_step(st, tag, false); });
    benchmark::RegisterBenchmark(("BM_ModelStep/" + tag + "/presliding").c_str(),
                                 [tag](benchmark::State& st) { model_step(st, tag, true); });
    benchmark::RegisterBenchmark(("BM_ModelFig2d/" + tag).c_str(),
                                 [tag](benchmark::State& st) { model_fig2d(st, tag); })
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
