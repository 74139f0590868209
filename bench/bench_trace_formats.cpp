// The trace writers of `gmslab simulate --out` (core/io/trace_csv.hpp, core/io/trace_file.hpp):
// - BM_FormatG10 / BM_ToCharsG10: one number as %.10g, format_g10 / std::to_chars (general, 10
//   digits), over the values of a recorded Fig. 4 trace (ns per number).
// - BM_TraceCsvRows: CSV text of a recorded Fig. 4 trace (13 columns), formatting only (ns per
//   row). BM_TraceCsvRows_10s: the same for the 10 s of BM_SimulateCsv_Streamed (10^6 rows, with
//   its stick phases: a velocity and element forces whose text repeats row after row).
// - BM_Simulate1e8_NoOutput: the Fig. 4 preset run for 1000 s at dt = 1e-5 s (10^8 steps) with
//   the preset's record_every (10: 10^7 samples), the samples taken in chunks as the writers take
//   them and dropped: the simulation's share of the runs below.
// - BM_SimulateHdf5_1e8: the same run to an HDF5 file (save_trace_file), 10^8 steps to HDF5;
//   counters: file size, the CPU time of both threads and the process's peak RSS (meaningful when
//   run alone: --benchmark_filter=BM_SimulateHdf5_1e8).
// One iteration each for the 10^8-step runs (about 5 to 15 s); wall time.
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <charconv>
#include <filesystem>

#include "core/io/scenario_io.hpp"
#include "core/io/trace_csv.hpp"
#include "core/io/trace_file.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"
#include "core/text/format_g10.hpp"

using namespace gmslab;

namespace {
Scenario fig4() {
  return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
}

// 10^5 samples of Fig. 4 with every step recorded (its stick-slip phase: all columns moving).
const Trace& recorded() {
  static const Trace tr = [] {
    Scenario s = fig4();
    s.run.duration = 1.0;
    s.run.record_every = 1;
    return simulate(s);
  }();
  return tr;
}

// 10^6 samples: the 10 s run of BM_SimulateCsv_Streamed, every step recorded.
const Trace& recorded_10s() {
  static const Trace tr = [] {
    Scenario s = fig4();
    s.run.duration = 10.0;
    s.run.record_every = 1;
    return simulate(s);
  }();
  return tr;
}

std::vector<double> trace_values() {
  const Trace& tr = recorded();
  std::vector<double> v;
  for (const auto* c : {&tr.t, &tr.x, &tr.v, &tr.friction, &tr.applied, &tr.element_force})
    v.insert(v.end(), c->begin(), c->end());
  return v;
}

Scenario run_1e8() {
  Scenario s = fig4();
  s.run.duration = 1000.0;  // 10^8 steps of 1e-5 s; record_every as the preset has it (10)
  return s;
}

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}
}  // namespace

static void BM_FormatG10(benchmark::State& st) {
  const std::vector<double> v = trace_values();
  char buf[kFormatG10MaxChars];
  for (auto _ : st)
    for (double x : v) benchmark::DoNotOptimize(format_g10(x, buf));
  st.counters["ns_per_number"] =
      benchmark::Counter(static_cast<double>(v.size()) * static_cast<double>(st.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FormatG10)->Unit(benchmark::kMillisecond);

static void BM_ToCharsG10(benchmark::State& st) {
  const std::vector<double> v = trace_values();
  char buf[32];
  for (auto _ : st)
    for (double x : v)
      benchmark::DoNotOptimize(
          std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 10).ptr);
  st.counters["ns_per_number"] =
      benchmark::Counter(static_cast<double>(v.size()) * static_cast<double>(st.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ToCharsG10)->Unit(benchmark::kMillisecond);

static void trace_csv_rows(benchmark::State& st, const Trace& tr) {
  const std::size_t ne = trace_csv_elements(tr);
  std::string text;
  for (auto _ : st) {
    text.clear();
    append_trace_csv_rows(tr, ne, text);
    benchmark::DoNotOptimize(text.data());
  }
  st.counters["ns_per_row"] =
      benchmark::Counter(static_cast<double>(tr.size()) * static_cast<double>(st.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["bytes_per_row"] = static_cast<double>(text.size()) / static_cast<double>(tr.size());
}

static void BM_TraceCsvRows(benchmark::State& st) { trace_csv_rows(st, recorded()); }
BENCHMARK(BM_TraceCsvRows)->Unit(benchmark::kMillisecond);

static void BM_TraceCsvRows_10s(benchmark::State& st) { trace_csv_rows(st, recorded_10s()); }
BENCHMARK(BM_TraceCsvRows_10s)->Unit(benchmark::kMillisecond);

static void BM_Simulate1e8_NoOutput(benchmark::State& st) {
  const Scenario s = run_1e8();
  std::size_t samples = 0;
  const double cpu0 = process_cpu_s();
  for (auto _ : st) {
    AssemblySimulation sim =
        one_body_simulation(s, TraceOptions{.max_bytes = 0, .reserve_samples = (1u << 14) + 2});
    samples = 0;
    while (!sim.finished()) {
      sim.advance((1u << 14) * static_cast<std::size_t>(s.run.record_every));
      samples += sim.one_body_trace().size();
      sim.clear_trace();
    }
  }
  st.counters["samples"] = static_cast<double>(samples);
  st.counters["process_cpu_s"] = process_cpu_s() - cpu0;
}
BENCHMARK(BM_Simulate1e8_NoOutput)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

static void BM_SimulateHdf5_1e8(benchmark::State& st) {
  const Scenario s = run_1e8();
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("gmslab_bench_" + std::to_string(::getpid()) + ".h5"))
                               .string();
  std::size_t samples = 0;
  const double cpu0 = process_cpu_s();
  for (auto _ : st) samples = save_trace_file(s, path);
  st.counters["process_cpu_s"] = process_cpu_s() - cpu0;  // both threads (simulation, HDF5 writer)
  st.counters["samples"] = static_cast<double>(samples);
  st.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  st.counters["peak_RSS_MB"] = peak_rss_mb();
  std::filesystem::remove(path);
}
BENCHMARK(BM_SimulateHdf5_1e8)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
