// Bounded memory: `simulate` streams its trace (the same bytes as writing the whole trace at the
// end, atomically), and a bounded trace (the window's and render's live runs) keeps every extreme
// of the full trace per time bucket while never exceeding its limit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "core/friction/gms.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/trace_csv.hpp"
#include "core/sim/assembly.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;

std::string tmp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("gmslab_" + std::to_string(::getpid()) + "_" + name)).string();
}

// The CSV text written independently of trace_csv.cpp: printf's %.10g, as the README says.
std::string printf_csv(const Trace& tr) {
  std::string out = "t_s,x_m,v_mps,F_friction_N,F_applied_N";
  const std::size_t ne = tr.n_elements;
  for (std::size_t i = 0; i < ne; ++i) out += ",F" + std::to_string(i + 1) + "_N";
  for (std::size_t i = 0; i < ne; ++i) out += ",slip" + std::to_string(i + 1);
  out += '\n';
  char b[256];
  for (std::size_t k = 0; k < tr.size(); ++k) {
    std::snprintf(b, sizeof b, "%.10g,%.10g,%.10g,%.10g,%.10g", tr.t[k], tr.x[k], tr.v[k], tr.friction[k], tr.applied[k]);
    out += b;
    for (std::size_t i = 0; i < ne; ++i) {
      std::snprintf(b, sizeof b, ",%.10g", tr.element_force[k * ne + i]);
      out += b;
    }
    for (std::size_t i = 0; i < ne; ++i) out += tr.element_slip[k * ne + i] ? ",1" : ",0";
    out += '\n';
  }
  return out;
}

// Equal texts; else the first differing line (a diff of megabytes would not help).
::testing::AssertionResult same_text(const std::string& a, const std::string& b) {
  if (a == b) return ::testing::AssertionSuccess();
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ga = static_cast<bool>(std::getline(sa, la)), gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga || !gb || la != lb)
      return ::testing::AssertionFailure() << "line " << line << ": '" << (ga ? la : "<end>") << "' vs '"
                                           << (gb ? lb : "<end>") << "'";
  }
}

TEST(TraceStream, StreamedCsvHasTheSameBytesAsTheWholeTraceInPrintfFormat) {
  for (const char* preset : {"fig2a_presliding.json", "fig4_stick_slip.json", "fig2b_lag_x16.json"}) {
    const Scenario sc = load_scenario(test_util::preset_path(preset));
    const std::string expected = printf_csv(simulate(sc));
    std::string streamed;
    std::size_t pieces = 0;
    const std::size_t n = stream_trace_csv(sc, [&](std::string_view s) {
      streamed += s;
      ++pieces;
    });
    EXPECT_TRUE(same_text(streamed, expected)) << preset;
    EXPECT_EQ(n, simulate(sc).size()) << preset;
    std::ostringstream whole;
    write_trace_csv(simulate(sc), whole);
    EXPECT_TRUE(same_text(whole.str(), expected)) << preset;
    if (std::string(preset) == "fig4_stick_slip.json") {
      EXPECT_GT(pieces, 10u);  // 250001 samples: streamed in chunks
    }
  }
}

// hand_over_one_body_trace: the chunks a streaming consumer takes, put together, are the samples
// of the whole run, and the run records on into the memory the consumer handed back.
TEST(TraceStream, HandedOverChunksMakeTheWholeTrace) {
  const Scenario sc = load_scenario(test_util::preset_path("fig4_stick_slip.json"));
  const Trace whole = simulate(sc);
  AssemblySimulation sim =
      one_body_simulation(sc, TraceOptions{.max_bytes = 0, .reserve_samples = 1002});
  Trace joined, chunk;
  std::size_t chunks = 0;
  while (!sim.finished()) {
    sim.advance(1000 * static_cast<std::size_t>(sc.run.record_every));
    sim.hand_over_one_body_trace(chunk);
    EXPECT_EQ(sim.one_body_trace().size(), 0u);
    EXPECT_EQ(chunk.n_elements, whole.n_elements);
    ++chunks;
    auto add = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    add(joined.t, chunk.t), add(joined.x, chunk.x), add(joined.v, chunk.v);
    add(joined.friction, chunk.friction), add(joined.applied, chunk.applied);
    add(joined.element_force, chunk.element_force), add(joined.element_slip, chunk.element_slip);
  }
  EXPECT_GT(chunks, 100u);  // 250001 samples in chunks of 1000
  test_util::expect_same_samples(joined, whole);
}

// A sink slower than the simulation: the calling thread then formats rows of the chunks waiting
// for the writer (the split between the threads differs from chunk to chunk), and the text is still
// printf's, every row once and in order.
TEST(TraceStream, ASlowSinkGivesTheSameBytes) {
  for (const char* preset : {"fig4_stick_slip.json", "fig2b_lag_x16.json"}) {
    const Scenario sc = load_scenario(test_util::preset_path(preset));
    const std::string expected = printf_csv(simulate(sc));
    std::string streamed;
    std::size_t pieces = 0;
    stream_trace_csv(sc, [&](std::string_view s) {
      std::this_thread::sleep_for(std::chrono::milliseconds(4));
      streamed += s;
      ++pieces;
    });
    EXPECT_TRUE(same_text(streamed, expected)) << preset;
    std::cout << preset << ": " << pieces << " pieces through a sink of 4 ms a piece\n";
  }
}

TEST(TraceStream, SavedFileIsAtomicAndADivergingRunLeavesTheOldFileAndNoTemporary) {
  const std::string out = tmp_path("stream.csv");
  const Scenario ok = load_scenario(test_util::preset_path("fig2a_presliding.json"));
  ASSERT_EQ(save_trace_csv_streamed(ok, out), simulate(ok).size());
  const std::string good = read_file(out);
  EXPECT_TRUE(same_text(good, printf_csv(simulate(ok))));
  // A run that diverges after some chunks have streamed: the target keeps the previous content.
  Scenario bad;
  bad.name = "diverges";
  bad.friction = GmsParams::reference(false).to_params();
  bad.plant = {1.0, 0.0, 2040.0};
  bad.drive.kind = Drive::Kind::Force;
  bad.drive.signal = Signal::sine(0.0, 10.0, 2.0);
  bad.run = {1e-3, 10.0, 1};
  EXPECT_THROW(save_trace_csv_streamed(bad, out), SimulationError);
  EXPECT_TRUE(read_file(out) == good);
  for (const auto& e : fs::directory_iterator(fs::temp_directory_path()))
    EXPECT_EQ(e.path().filename().string().rfind("." + fs::path(out).filename().string() + ".tmp-", 0), std::string::npos)
        << e.path();
  fs::remove(out);
}

// Channels of a trace, by index: x, v, F_f, F_applied.
const std::vector<double>& channel(const Trace& tr, int c) {
  return c == 0 ? tr.x : c == 1 ? tr.v : c == 2 ? tr.friction : tr.applied;
}

TEST(BoundedTrace, NeverExceedsItsLimitAndKeepsEveryExtremePerBucket) {
  const Scenario sc = load_scenario(test_util::preset_path("fig4_stick_slip.json"));  // 250001 samples
  const Trace full = simulate(sc);
  const std::size_t limit_bytes = 3000 * trace_sample_bytes(4);
  AssemblySimulation sim = one_body_simulation(sc, TraceOptions{.max_bytes = limit_bytes});
  EXPECT_EQ(sim.trace_max_samples(), 3000u);
  std::size_t most = 0;
  while (!sim.finished()) {
    sim.advance(7919);
    most = std::max(most, sim.one_body_trace().size());
    ASSERT_LE(sim.one_body_trace().t.capacity() * 5 * sizeof(double) +
                  sim.one_body_trace().element_force.capacity() * 9,
              limit_bytes + 64);
  }
  EXPECT_LE(most, 3000u);
  const Trace& b = sim.one_body_trace();
  const std::uint64_t w = sim.trace_bucket_steps();
  ASSERT_GT(w, 0u);
  EXPECT_GT(b.size(), 300u);  // still well resolved: more samples than a plot has pixel columns
  // Every kept sample is a sample of the full run, bit for bit, in order; the last one is kept.
  std::size_t j = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    while (j < full.size() && full.t[j] != b.t[k]) ++j;
    ASSERT_LT(j, full.size()) << "sample at t = " << b.t[k] << " is not in the full trace";
    for (int c = 0; c < 4; ++c) ASSERT_EQ(channel(b, c)[k], channel(full, c)[j]);
    for (std::size_t e = 0; e < 4; ++e) ASSERT_EQ(b.element_force[k * 4 + e], full.element_force[j * 4 + e]);
  }
  EXPECT_EQ(b.t.back(), full.t.back());
  // Per bucket of w steps: the smallest and largest value of every channel is that of the full run.
  const double dt = sc.run.dt;
  auto bucket = [&](double t) { return static_cast<std::uint64_t>(std::llround(t / dt)) / w; };
  std::size_t kb = 0, checked = 0;
  for (std::size_t i = 0; i < full.size();) {
    const std::uint64_t id = bucket(full.t[i]);
    std::size_t e = i;
    while (e < full.size() && bucket(full.t[e]) == id) ++e;
    std::size_t ke = kb;
    while (ke < b.size() && bucket(b.t[ke]) == id) ++ke;
    ASSERT_GT(ke, kb) << "bucket " << id << " lost";
    for (int c = 0; c < 4; ++c) {
      const auto& f = channel(full, c);
      const auto& g = channel(b, c);
      ASSERT_EQ(*std::min_element(f.begin() + i, f.begin() + e), *std::min_element(g.begin() + kb, g.begin() + ke));
      ASSERT_EQ(*std::max_element(f.begin() + i, f.begin() + e), *std::max_element(g.begin() + kb, g.begin() + ke));
    }
    ++checked;
    i = e;
    kb = ke;
  }
  EXPECT_EQ(kb, b.size());
  EXPECT_GT(checked, 100u);
}

TEST(BoundedTrace, UnderTheLimitEveryStepIsKept) {
  const Scenario sc = load_scenario(test_util::preset_path("fig4_stick_slip.json"));
  AssemblySimulation sim =
      one_body_simulation(sc, TraceOptions{.max_bytes = std::size_t{64} << 20});
  sim.run_to_end();
  const Trace full = simulate(sc);
  EXPECT_EQ(sim.trace_bucket_steps(), 0u);
  EXPECT_EQ(sim.one_body_trace().t, full.t);
  EXPECT_EQ(sim.one_body_trace().friction, full.friction);
}

}  // namespace
}  // namespace gmslab
