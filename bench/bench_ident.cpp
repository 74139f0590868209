// Identification hot paths on the EMPS estimation record (../shared/data/emps; skipped with a
// message when absent):
//   BM_CsvParse: parse DATA_EMPS.csv from memory (24,841 rows x 7 columns).
//   BM_FitCost: one cost evaluation of the variable-projection fit (GMS 4 elements simulated along
//     the record + least squares of the linear terms); reported per sample.
//   BM_GridFitEmps: the GMS base fit alone (element grid by variable projection, grouping to 4
//     elements, free-knot polish; element_fit.hpp), with inertia as a linear term.
//   BM_IdentifyEmps: the CLI's identification job (job.hpp), loading included: GMS 4 grid base fit
//     and residual loop on the training record screened on every 12th sample (LoopOptions::
//     screen_samples), final polish on all samples, validation on the PULSES record with its
//     pulse windows masked.
//     Target: under 2 s on the 2-core development machine.
//   BM_IdentifyTrace40k: the same job on gmslab's own trace of presets/fig2c_periodic_1hz.json
//     (GMS, 40,000 samples, no noise; `gmslab simulate` CSV read as it is, the friction force as
//     F), identified with the generating model. Target: under 5 s, like EMPS. Counters: validation
//     RMS before / after [N] and the number of effects added (0 expected: an exact model).
// The fits run independent searches on two threads (core/ident/parallel.hpp): CPU time is the
// process's (both threads), next to the wall time.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "core/ident/job.hpp"
#include "core/ident/loop.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/csv.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/trace_file.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {
std::string emps(const std::string& file) {
  const char* env = std::getenv("GMSLAB_SHARED");
  return (env ? std::string(env) : std::string(GMSLAB_SOURCE_DIR) + "/../shared") + "/data/emps/" + file;
}
bool have_emps() {
  return std::filesystem::exists(emps("DATA_EMPS.csv")) && std::filesystem::exists(emps("DATA_EMPS_PULSES.csv"));
}
}  // namespace

static void BM_CsvParse(benchmark::State& st) {
  if (!have_emps()) return st.SkipWithError("EMPS data not found (../shared/data/emps)");
  const std::string text = read_file(emps("DATA_EMPS.csv"));
  std::size_t rows = 0;
  for (auto _ : st) {
    const auto r = parse_measured_csv(text, "DATA_EMPS.csv");
    rows = r.size();
    benchmark::DoNotOptimize(r.F.data());
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * rows));
  st.SetBytesProcessed(static_cast<std::int64_t>(st.iterations() * text.size()));
}
BENCHMARK(BM_CsvParse)->Unit(benchmark::kMillisecond);

static void BM_FitCost(benchmark::State& st) {
  if (!have_emps()) return st.SkipWithError("EMPS data not found (../shared/data/emps)");
  const auto d = prepare_dataset(load_measured_csv(emps("DATA_EMPS.csv")), {}, 50);
  const auto c = make_context(d);
  FitSpec spec;
  spec.effects = {Effect::Inertia, Effect::Offset};
  FitOptions o;
  o.starts = 1;
  o.max_evaluations = 20;
  const auto r = fit_model(spec, d, c, o);
  for (auto _ : st) benchmark::DoNotOptimize(refit_linear(spec, d, c, r.u).rms_train);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * d.size()));
}
BENCHMARK(BM_FitCost)->Unit(benchmark::kMillisecond);

static void BM_GridFitEmps(benchmark::State& st) {
  if (!have_emps()) return st.SkipWithError("EMPS data not found (../shared/data/emps)");
  const auto d = prepare_dataset(load_measured_csv(emps("DATA_EMPS.csv")), {}, 50);
  const auto c = make_context(d);
  FitSpec spec;
  spec.effects = {Effect::Inertia};
  FitResult r;
  for (auto _ : st) {
    r = fit_model(spec, d, c, FitOptions{});
    double rms = r.rms_train;
    benchmark::DoNotOptimize(rms);
  }
  st.counters["rms_train_N"] = r.rms_train;
  st.counters["evaluations"] = r.evaluations;
}
BENCHMARK(BM_GridFitEmps)->Unit(benchmark::kMillisecond)->Iterations(2)->MeasureProcessCPUTime()->UseRealTime();

static void BM_IdentifyEmps(benchmark::State& st) {
  if (!have_emps()) return st.SkipWithError("EMPS data not found (../shared/data/emps)");
  // The job `gmslab identify --data DATA_EMPS.csv --validate DATA_EMPS_PULSES.csv --mask-edges
  // pulse_code:0.005:0.060` runs (job.hpp: the CLI's, the panel's and Python's), loading included.
  IdentifyJob job;
  job.train.path = emps("DATA_EMPS.csv");
  job.train.mask_edges = "pulse_code:0.005:0.060";
  job.validation.path = emps("DATA_EMPS_PULSES.csv");
  job.validation.mask_edges = "pulse_code:0.005:0.060";
  IdentReport rep;
  for (auto _ : st) {
    rep = run_identification(job).report;
    double after = rep.rms_after_validation;  // a copy: GCC mis-handles "+m,r" on a member
    benchmark::DoNotOptimize(after);
  }
  st.counters["rms_val_before_N"] = rep.rms_before_validation;
  st.counters["rms_val_after_N"] = rep.rms_after_validation;
  st.counters["effects_added"] = static_cast<double>(rep.effects_added.size());
  st.counters["rounds"] = static_cast<double>(rep.rounds.size());
  st.counters["screened_every"] = static_cast<double>(rep.screen_every);
}
BENCHMARK(BM_IdentifyEmps)->Unit(benchmark::kSecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

static void BM_IdentifyTrace40k(benchmark::State& st) {
  // `gmslab simulate presets/fig2c_periodic_1hz.json --out rec.csv`, then `gmslab identify --data
  // rec.csv`: the trace written once, outside the timing.
  const auto dir = std::filesystem::temp_directory_path() / "gmslab_bench_trace40k";
  std::filesystem::create_directories(dir);
  const std::string rec = (dir / "fig2c_periodic_1hz.csv").string();
  const auto preset =
      load_preset(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2c_periodic_1hz.json");
  const std::size_t rows = save_trace_file(preset.one_body(), rec);
  IdentifyJob job;
  job.train.path = rec;
  IdentReport rep;
  for (auto _ : st) {
    rep = run_identification(job).report;
    double after = rep.rms_after_validation;
    benchmark::DoNotOptimize(after);
  }
  std::filesystem::remove_all(dir);
  st.counters["samples"] = static_cast<double>(rows);
  st.counters["rms_val_before_N"] = rep.rms_before_validation;
  st.counters["rms_val_after_N"] = rep.rms_after_validation;
  st.counters["effects_added"] = static_cast<double>(rep.effects_added.size());
}
BENCHMARK(BM_IdentifyTrace40k)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
