// GMS friction step and the Fig. 4 simulation.
//   BM_GmsStep/N/mode: one friction step of N elements; reported as ns per element-step.
//   mode 0 = sliding (all elements slip at 1 mm/s), mode 1 = presliding (small oscillation, stick)
//   BM_Fig4Preset: the whole Fig. 4 stick-slip preset (25 s at dt = 1e-5 s, 2.5e6 steps).
//   BM_GmsAlongPath/N/runner: the identification's hot path, GMS driven along a prescribed motion
//     (40,000 steps at 1 kHz like the EMPS record: strokes, reversals, rests, delta 1.3);
//     runner 0 = GmsModel::step per step, 1 = GmsPathRunner (Stribeck level and relaxation of all
//     steps at once, then the elements; bit-identical); a new shape each iteration; ns per step.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numeric>

#include "core/friction/gms.hpp"
#include "core/friction/gms_path.hpp"
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

static void BM_GmsAlongPath(benchmark::State& st) {
  const auto n = static_cast<std::size_t>(st.range(0));
  const bool runner = st.range(1) == 1;
  GmsPath path;
  path.samples = 1;
  std::vector<double> v, h;
  for (int k = 0; k < 40000; ++k) {  // 8 s periods: stroke at 0.15 m/s, reversal, rest
    const double t = 1e-3 * k, ph = std::fmod(t, 8.0);
    const double vk = ph < 3 ? 0.15 * std::sin(M_PI * ph / 3) : ph < 7 ? -0.08 * std::sin(M_PI * (ph - 3) / 4) : 0.0;
    v.push_back(vk), h.push_back(1e-3);
    path.add_step(vk, 1e-3);
    path.end_sample();
  }
  GmsParams g;
  g.S = {3.0, 1.0, 0.002, 1.3};
  g.C = 5000.0;
  g.sigma2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    g.alpha.push_back(1.0 / static_cast<double>(n));
    g.k.push_back(g.alpha.back() / (1e-6 * std::pow(1.5, static_cast<double>(i))));
    g.sigma.push_back(0.0);
  }
  std::vector<double> out(path.samples), sk(n, 0.0);
  GmsPathRunner run;
  double acc = 0.0;
  int it = 0;
  for (auto _ : st) {
    g.S.Vs = 0.002 * (1.0 + 1e-3 * (it++ % 2));  // a new shape: nothing kept between iterations
    if (runner) {
      run.prepare(g.S, g.C, path);
      run.run(path, g.alpha, g.k, sk, 0.0, {}, 1.0, nullptr, out);
    } else {
      const GmsModel m(g.to_params());
      std::vector<double> s(m.state_size());
      m.reset(s);
      for (std::size_t k = 0; k < v.size(); ++k) out[k + 1] = m.step(s, {v[k], h[k], 0.0, 0.0});
    }
    acc += out.back();
  }
  benchmark::DoNotOptimize(acc);
  st.counters["ns_per_step"] = benchmark::Counter(static_cast<double>(st.iterations()) * 40000.0,
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_GmsAlongPath)
    ->ArgsProduct({{2, 31}, {0, 1}})
    ->ArgNames({"N", "runner"})
    ->Unit(benchmark::kMillisecond);

static void BM_Fig4Preset(benchmark::State& st) {
  const Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  for (auto _ : st) {
    Trace tr = simulate(sc);
    benchmark::DoNotOptimize(tr.x.back());
  }
  st.SetLabel("25 s of simulated time, dt = 1e-5 s");
}
BENCHMARK(BM_Fig4Preset)->Unit(benchmark::kMillisecond);
