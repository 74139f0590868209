// Control benchmarks: root locus of a 10th-order plant, full lead designs (reachable, and with
// relocation along three paths), the friction loop, and one full recomputation of the design
// view (locus + design + Bode / Nyquist + describing-function prediction + linear step + both
// nonlinear loops); frequency responses of a 10th-order loop; the view-rate limit-cycle prediction; the loop and the frame with the
// measured-velocity feedforward (LoopConfig::feedforward_source). Target for the view: < 16 ms.
#include <benchmark/benchmark.h>

#include "core/control/design_session.hpp"
#include "core/control/limit_cycles.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
TransferFunction tenth_order() {
  return {Poly::from_roots({{-1.5, 0}, {-4, 2}, {-4, -2}}),
          Poly::from_roots({{0, 0}, {-1, 0}, {-2, 1}, {-2, -1}, {-3, 4}, {-3, -4}, {-5, 0},
                            {-6, 0}, {-0.5, 2}, {-0.5, -2}})};
}
Scenario fig4() {
  return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
}
// The Fig. 4 friction loop with the lead design and the GMS compensator, 1 s of a 1 Hz sine.
LoopConfig fig4_loop() {
  LoopConfig c;
  c.C = {4440.18, 8.47263, 94.05};
  c.reference = Signal::sine(0.0, 0.01, 1.0);
  c.comp = Compensation::Gms;
  c.duration = 1.0;
  return c;
}
// The Design view's default frame on Fig. 4: sliding regime, zeta 0.7 at 60 rad/s, K 1000, two
// periods of a 2 Hz sine (1 s).
DesignInputs fig4_frame() {
  DesignInputs in;
  in.scenario = fig4();
  in.regime = Regime::Sliding;
  in.root = {0.7, 60.0};
  in.K = 1000.0;
  in.reference = Signal::sine(0.0, 0.01, 2.0);
  return in;
}
}  // namespace

static void BM_RootLocus10thOrder(benchmark::State& st) {
  const TransferFunction L = tenth_order();
  std::size_t n = 0;
  for (auto _ : st) {
    const RootLocus rl = root_locus(L);
    n = rl.gains.size();
    benchmark::DoNotOptimize(rl.branches.data());
  }
  st.counters["gains"] = static_cast<double>(n);
}
BENCHMARK(BM_RootLocus10thOrder)->Unit(benchmark::kMillisecond);

static void BM_LeadDesignReachable(benchmark::State& st) {
  const TransferFunction g{Poly::descending({1}), Poly::descending({1, 6, 5, 0})};
  for (auto _ : st) benchmark::DoNotOptimize(lead_design(g, {0.5, 2.0}, 2.0));
}
BENCHMARK(BM_LeadDesignReachable)->Unit(benchmark::kMicrosecond);

static void BM_LeadDesignWithRelocation(benchmark::State& st) {
  const TransferFunction g{Poly::descending({1}), Poly::descending({1, 6, 5, 0})};
  for (auto _ : st) benchmark::DoNotOptimize(lead_design(g, {0.5, 2.0}, 8.0));
}
BENCHMARK(BM_LeadDesignWithRelocation)->Unit(benchmark::kMicrosecond);

static void BM_FrictionLoop1s(benchmark::State& st) {
  const Scenario s = fig4();
  const LoopConfig c = fig4_loop();
  for (auto _ : st) benchmark::DoNotOptimize(simulate_loop(s, c).x.back());
  st.counters["steps/s"] = benchmark::Counter(1e5, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FrictionLoop1s)->Unit(benchmark::kMillisecond);

// The same loop with a PID Kc (s + z)(s + zi)/((s + p) s): the two-section cascade (exact ZOH of
// its 2-state realisation each step) against the one-section update above.
static void BM_FrictionLoopPid1s(benchmark::State& st) {
  const Scenario s = fig4();
  LoopConfig c = fig4_loop();
  c.C = {4440.18, 8.47263, 94.05, Section{4.2, 0.0}};
  for (auto _ : st) benchmark::DoNotOptimize(simulate_loop(s, c).x.back());
  st.counters["steps/s"] = benchmark::Counter(1e5, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FrictionLoopPid1s)->Unit(benchmark::kMillisecond);

// The same loop with the GMS compensator driven by the plant's measured velocity
// (LoopConfig::feedforward_source) instead of the reference.
static void BM_FrictionLoopMeasuredFeedforward1s(benchmark::State& st) {
  const Scenario s = fig4();
  LoopConfig c = fig4_loop();
  c.feedforward_source = FeedforwardSource::Measured;
  for (auto _ : st) benchmark::DoNotOptimize(simulate_loop(s, c).x.back());
  st.counters["steps/s"] = benchmark::Counter(1e5, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FrictionLoopMeasuredFeedforward1s)->Unit(benchmark::kMillisecond);

static void BM_FrequencyResponse10thOrder(benchmark::State& st) {
  const TransferFunction L = tenth_order();
  const TransferFunction K{L.num * 5.0, L.den};
  for (auto _ : st) benchmark::DoNotOptimize(frequency_response(K).margins.phase_margin);
}
BENCHMARK(BM_FrequencyResponse10thOrder)->Unit(benchmark::kMicrosecond);

static void BM_LimitCyclesViewRate(benchmark::State& st) {  // as the design view runs it
  const Scenario s = fig4();
  const auto m = build_model(s.friction);
  const LeadCompensator C{4440.18, 8.47263, 94.05};
  for (auto _ : st)
    benchmark::DoNotOptimize(predict_limit_cycles(stepped(*m), s.plant, C, 1e-6, 10.0, {400, 2}).cycles.size());
}
BENCHMARK(BM_LimitCyclesViewRate)->Unit(benchmark::kMillisecond);

// The stick-slip hunting prediction (core/control/hunting.hpp) of a PI loop on the Fig. 4 mass with
// its GMS friction: at the view's rate (200 steps per period, 12 amplitudes) and at the default
// (400, 20) used by the CLI and the tests.
static void BM_HuntingDfViewRate(benchmark::State& st) {
  const Scenario s = fig4();
  const LeadCompensator C{1000.0, 5.0, 0.0};
  const HuntingOptions o = view_rate_hunting_options();
  int evals = 0;
  for (auto _ : st) {
    const HuntingReport r = predict_hunting(s.plant, s.friction, C, o);
    evals = r.evaluations;
    benchmark::DoNotOptimize(r.cycles.size());
  }
  st.counters["block_runs"] = evals;
}
BENCHMARK(BM_HuntingDfViewRate)->Unit(benchmark::kMillisecond);

// A case where the hunting is found (Coulomb Fs 1.5 N, Fc 1 N on 0.2 kg with 40 N s/m, the view's PI
// 8160.8 (s + 10.1)/s: predicted 0.037 mm, 1.62 s), at the view's rate.
static void BM_HuntingDfViewRateCoulomb(benchmark::State& st) {
  ModelParams fr = model_info("coulomb").defaults();
  fr.set_scalar("Fs", 1.5), fr.set_scalar("Fc", 1.0), fr.set_scalar("sigma2", 0.4);
  const Plant pl{0.2, 0.0, 40.0};
  const LeadCompensator C{8160.8, 10.1, 0.0};
  const HuntingOptions o = view_rate_hunting_options();
  int evals = 0;
  for (auto _ : st) {
    const HuntingReport r = predict_hunting(pl, fr, C, o);
    if (!r.hunting()) st.SkipWithError("no hunting predicted");
    evals = r.evaluations;
    benchmark::DoNotOptimize(r.cycles.size());
  }
  st.counters["block_runs"] = evals;
}
BENCHMARK(BM_HuntingDfViewRateCoulomb)->Unit(benchmark::kMillisecond);

static void BM_HuntingDfDefault(benchmark::State& st) {
  const Scenario s = fig4();
  const LeadCompensator C{1000.0, 5.0, 0.0};
  for (auto _ : st) benchmark::DoNotOptimize(predict_hunting(s.plant, s.friction, C).cycles.size());
}
BENCHMARK(BM_HuntingDfDefault)->Unit(benchmark::kMillisecond);

// One drag of the Design view with a PI compensator (the hunting prediction added to the frame).
static void BM_DesignViewFramePI(benchmark::State& st) {
  DesignInputs in = fig4_frame();
  in.type = CompensatorType::PI;
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty()) st.SkipWithError(out.error.c_str());
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFramePI)->Unit(benchmark::kMillisecond);

// The same with a hunting case (the plant of BM_HuntingDfViewRateCoulomb, a step reference): the
// prediction is found and the loops run 20 predicted periods (30 s).
static void BM_DesignViewFramePIHunting(benchmark::State& st) {
  DesignInputs in;
  in.scenario = fig4();
  in.scenario.friction = model_info("coulomb").defaults();
  in.scenario.friction.set_scalar("Fs", 1.5), in.scenario.friction.set_scalar("Fc", 1.0);
  in.scenario.friction.set_scalar("sigma2", 0.4);
  in.scenario.plant = {0.2, 0.0, 40.0};
  in.regime = Regime::Sliding;
  in.root = {0.5, 0.5};
  in.type = CompensatorType::PI;
  in.reference = Signal::constant(0.01);
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty() || !out.hunting || !out.hunting->hunting()) st.SkipWithError("no hunting predicted");
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFramePIHunting)->Unit(benchmark::kMillisecond);

static void BM_DesignViewFrame(benchmark::State& st) {
  const DesignInputs in = fig4_frame();
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty()) st.SkipWithError(out.error.c_str());
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFrame)->Unit(benchmark::kMillisecond);

// The same frame with a 2 ms controller sample time: adds the sampled loop's Bode / margins and
// its z-plane root locus (unit-circle crossings, stable gain intervals).
static void BM_DesignViewFrameSampled(benchmark::State& st) {
  DesignInputs in = fig4_frame();
  in.sample_time = 2e-3;
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty() || !out.z_locus) st.SkipWithError("no z-plane locus");
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFrameSampled)->Unit(benchmark::kMillisecond);

// The frame with the measured-velocity feedforward on: adds the compensated describing-function
// prediction on F - F_hat. Target for the view: < 16 ms.
static void BM_DesignViewFrameMeasuredFeedforward(benchmark::State& st) {
  DesignInputs in = fig4_frame();
  in.feedforward_source = FeedforwardSource::Measured;
  for (auto _ : st) {
    const DesignOutputs out = compute_design(in);
    if (!out.error.empty() || !out.compensated().limit_cycles) st.SkipWithError("no compensated prediction");
    benchmark::DoNotOptimize(out.locus.gains.data());
  }
}
BENCHMARK(BM_DesignViewFrameMeasuredFeedforward)->Unit(benchmark::kMillisecond);

// The z-plane locus of the view's sampled loop alone.
static void BM_ZRootLocusSampledLoop(benchmark::State& st) {
  const TransferFunction G{Poly({1.0}), Poly({0.0, 0.4, 1.0})};
  const TransferFunction Lz = sampled_loop(G, 40.6848, 813.697, 2e-3);
  std::size_t n = 0;
  for (auto _ : st) {
    const ZLocus z = z_root_locus(Lz, 2e-3);
    n = z.locus.gains.size();
    benchmark::DoNotOptimize(z.crossings.data());
  }
  st.counters["gains"] = static_cast<double>(n);
}
BENCHMARK(BM_ZRootLocusSampledLoop)->Unit(benchmark::kMillisecond);

#if __has_include(<imgui.h>)  // built with the app: time a whole drag frame of the Design panel
#include "app/headless.hpp"
#include "ui/app.hpp"
#include "ui/design/design_view.hpp"

// One drag frame: s_d moved (so locus, design, step and both friction loops are recomputed),
// then the full window drawn and rasterised by OSMesa (llvmpipe, CPU: an upper bound for the
// GPU window).
static void BM_DesignViewDragFrameRendered(benchmark::State& st) {
  gmslab::ui::AppState s;
  gmslab::ui::load_scenario_into(s, fig4(), "");
  s.view.tab = "Design";
  gmslab::app::Offscreen off(1600, 1000);
  off.render([&] { gmslab::ui::draw_frame(s); }, 3);
  auto& d = s.design;
  int i = 0;
  for (auto _ : st) {
    d.in.root.wn = 60.0 + (i++ % 2);
    d.dirty = true;
    benchmark::DoNotOptimize(off.render([&] { gmslab::ui::draw_frame(s); }, 1).data());
  }
  st.counters["compute_ms"] = d.compute_ms;
}
BENCHMARK(BM_DesignViewDragFrameRendered)->Unit(benchmark::kMillisecond);
#endif

// Periodic orbits (core/control/limit_cycles.hpp) of the loop: mass 1 kg, damper 3 N s/m,
// PI 1000 (s + 5)/s, GMS at its defaults, at the design job's step (5 % of the stability limit).
namespace {
ClosedLoop gms_pi_loop(double gain_scale = 1.0) {
  ClosedLoop L;
  L.scenario.plant = {1.0, 0.0, 3.0};
  L.scenario.friction = model_info("gms").defaults();
  L.config.C = LeadCompensator{1000.0 * gain_scale, 5.0, 0.0};
  L.config.reference = Signal::constant(0.01);
  L.config.dt = 0.05 * 2.0 / std::sqrt(stuck_stiffness(L.scenario.friction) + 1000.0);
  return L;
}
}  // namespace

// One orbit from a warm start, as on a drag: the orbit at gain 1 continued to gain 1.02
// (quasi-Newton from the neighbour's Jacobian, fresh finite-difference multipliers at the
// solution). Target < 16 ms.
static void BM_OrbitWarm(benchmark::State& st) {
  const ClosedLoop L = gms_pi_loop();
  const OrbitReport r = find_orbits(L);
  if (!r.stable()) {
    st.SkipWithError("no stable orbit to start from");
    return;
  }
  for (auto _ : st) {
    auto o = continue_orbit(L, *r.stable(), 1.02);
    benchmark::DoNotOptimize(o);
  }
}
BENCHMARK(BM_OrbitWarm)->Unit(benchmark::kMillisecond);

// The hunting map of that loop over gain scales 0.25-4 (9 points) from the orbit at gain 1.
// Target <= 300 ms.
static void BM_HuntingMap(benchmark::State& st) {
  const ClosedLoop L = gms_pi_loop();
  const OrbitReport r = find_orbits(L);
  if (!r.stable()) {
    st.SkipWithError("no stable orbit to start from");
    return;
  }
  for (auto _ : st) {
    auto m = hunting_map(L, *r.stable(), 0.25, 4.0, 9);
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_HuntingMap)->Unit(benchmark::kMillisecond);

// The cold search (short simulation from rest, fixed-point iterations, Newton, multipliers).
static void BM_OrbitCold(benchmark::State& st) {
  const ClosedLoop L = gms_pi_loop();
  for (auto _ : st) {
    auto r = find_orbits(L);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_OrbitCold)->Unit(benchmark::kMillisecond);
