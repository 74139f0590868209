// `gmslab simulate`: the whole path from scenario to CSV file on disk (atomic save included).
//   BM_SimulateCsv_InMemoryBefore: the path before streaming - run the whole scenario keeping
//     every sample, format the whole text (snprintf %.10g into an ostringstream), then one atomic
//     write. Memory grows with the run (76 B per sample of the trace + ~130 B of text).
//   BM_SimulateCsv_InMemory: the same with today's formatter (save_trace_csv).
//   BM_SimulateCsv_Streamed: what `gmslab simulate` does (save_trace_csv_streamed): chunks of
//     16384 samples formatted (format_g10) and written to the temporary file on a second thread
//     while the next chunk is simulated; constant memory. process_cpu_ns_per_step: both threads.
// Scenario: the Fig. 4 preset (GMS, 4 elements, pull drive), 1e6 steps of 1e-5 s, every step
// recorded (1e6 rows, ~120 MB of CSV).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_csv.hpp"
#include "core/sim/assembly.hpp"

using namespace gmslab;

namespace {
Scenario csv_scenario() {
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  s.run.duration = 10.0;  // 1e6 steps
  s.run.record_every = 1;
  return s;
}

std::string out_path() {
  return (std::filesystem::temp_directory_path() / ("gmslab_bench_" + std::to_string(::getpid()) + ".csv")).string();
}

// The formatter as it was before streaming (snprintf into an ostream).
void write_trace_csv_before(const Trace& tr, std::ostream& out) {
  const std::size_t ne = tr.element_force.size() == tr.size() * tr.n_elements ? tr.n_elements : 0;
  out << "t_s,x_m,v_mps,F_friction_N,F_applied_N";
  for (std::size_t i = 0; i < ne; ++i) out << ",F" << i + 1 << "_N";
  for (std::size_t i = 0; i < ne; ++i) out << ",slip" << i + 1;
  out << '\n';
  char buf[64];
  auto put = [&](double x) { out.write(buf, std::snprintf(buf, sizeof buf, "%.10g", x)); };
  for (std::size_t k = 0; k < tr.size(); ++k) {
    put(tr.t[k]);
    for (double x : {tr.x[k], tr.v[k], tr.friction[k], tr.applied[k]}) {
      out << ',';
      put(x);
    }
    for (std::size_t i = 0; i < ne; ++i) {
      out << ',';
      put(tr.element_force[k * ne + i]);
    }
    for (std::size_t i = 0; i < ne; ++i) out << ',' << int(tr.element_slip[k * ne + i]);
    out << '\n';
  }
}

// User + system CPU time of the whole process [s].
double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void report(benchmark::State& st, const std::string& path) {
  const double bytes = static_cast<double>(std::filesystem::file_size(path));
  st.counters["csv_MB"] = bytes / 1e6;
  st.counters["ns_per_step"] =
      benchmark::Counter(1e6 * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  std::filesystem::remove(path);
}
}  // namespace

static void BM_SimulateCsv_InMemoryBefore(benchmark::State& st) {
  const Scenario s = csv_scenario();
  const std::string path = out_path();
  for (auto _ : st) {
    const Trace tr = simulate(s);
    std::ostringstream ss;
    write_trace_csv_before(tr, ss);
    write_file_atomic(path, ss.str());
  }
  report(st, path);
}
BENCHMARK(BM_SimulateCsv_InMemoryBefore)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_SimulateCsv_InMemory(benchmark::State& st) {
  const Scenario s = csv_scenario();
  const std::string path = out_path();
  for (auto _ : st) save_trace_csv(simulate(s), path);
  report(st, path);
}
BENCHMARK(BM_SimulateCsv_InMemory)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_SimulateCsv_Streamed(benchmark::State& st) {
  const Scenario s = csv_scenario();
  const std::string path = out_path();
  const double cpu0 = process_cpu_s();
  for (auto _ : st) save_trace_csv_streamed(s, path);
  // Both threads' CPU time (the benchmark's CPU column counts the calling thread only).
  st.counters["process_cpu_ns_per_step"] =
      (process_cpu_s() - cpu0) * 1e9 / (1e6 * static_cast<double>(st.iterations()));
  report(st, path);
}
BENCHMARK(BM_SimulateCsv_Streamed)->Unit(benchmark::kMillisecond)->UseRealTime();

// The window's / render's live run: the Fig. 4 preset run for 250 s (2.5e7 steps, 2.5e6 samples
// recorded = 190 MB of trace) with every sample kept, and within the 64 MiB bound
// (TraceOptions::max_bytes, compacted to min/max per time bucket).
static void BM_LiveRun_Fig4_250s(benchmark::State& st) {
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  s.run.duration = 250.0;
  const std::size_t limit = st.range(0) ? std::size_t{64} << 20 : 0;
  std::size_t kept = 0;
  for (auto _ : st) {
    AssemblySimulation sim = one_body_simulation(s, TraceOptions{.max_bytes = limit});
    sim.run_to_end();
    kept = sim.one_body_trace().size();
  }
  st.counters["samples_kept"] = static_cast<double>(kept);
  st.counters["trace_MB"] = static_cast<double>(kept * trace_sample_bytes(4)) / 1e6;
}
BENCHMARK(BM_LiveRun_Fig4_250s)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(2);
