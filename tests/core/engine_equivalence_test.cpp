// One engine for every preset: a one-body scenario runs on the assembled plant's engine
// (simulate(Scenario), one_body_simulation) and keeps, sample for sample, the trace of the one-body
// Simulation; the CSV of `gmslab simulate` is the same text. Every shipped preset (one-body and
// assembled) also keeps the trace saved in GMSLAB_BINARY_DIR/reference_traces, when that folder
// exists (written by an earlier build of the engine; the test is skipped without it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/error.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_csv.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> shipped_presets() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets"))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Largest difference of two series relative to the largest magnitude of the first; counts the
// samples that are equal bit for bit.
struct Diff {
  double rel = 0.0;
  std::size_t equal = 0, n = 0;
  void add(const std::vector<double>& a, const std::vector<double>& b) {
    ASSERT_EQ(a.size(), b.size());
    double scale = 1e-300;
    for (double x : a) scale = std::max(scale, std::abs(x));
    for (std::size_t k = 0; k < a.size(); ++k) {
      rel = std::max(rel, std::abs(a[k] - b[k]) / scale);
      equal += a[k] == b[k] || (std::isnan(a[k]) && std::isnan(b[k]));
    }
    n += a.size();
  }
};

Trace old_engine(const Scenario& s) {
  Simulation sim(s);
  sim.run_to_end();
  return sim.take_trace();
}

TEST(Engine, EveryOneBodyPresetKeepsItsTraceOnTheAssembledEngine) {
  int presets = 0;
  for (const auto& path : shipped_presets()) {
    const Preset p = load_preset(path.string());
    if (p.assembled()) continue;
    SCOPED_TRACE(path.string());
    ++presets;
    const Scenario s = p.one_body();
    const Trace a = old_engine(s);
    const Trace b = simulate(s);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.n_elements, b.n_elements);
    EXPECT_EQ(a.t, b.t);
    Diff d;
    d.add(a.x, b.x);
    d.add(a.v, b.v);
    d.add(a.friction, b.friction);
    d.add(a.applied, b.applied);
    d.add(a.element_force, b.element_force);
    EXPECT_EQ(a.element_slip, b.element_slip);
    EXPECT_LE(d.rel, 1e-12);
    std::cout << "[ engine   ] " << path.filename().string() << ": " << a.size() << " samples, " << d.equal << " of "
              << d.n << " values bit for bit, max relative difference " << d.rel << '\n';
    // The CLI's CSV (stream_trace_csv) is the text the old trace gives.
    std::ostringstream want;
    write_trace_csv(a, want);
    std::string got;
    stream_trace_csv(s, [&](std::string_view t) { got += t; });
    EXPECT_TRUE(got == want.str()) << "the CSV of " << path.filename().string() << " changed";
  }
  EXPECT_GE(presets, 10);
}

TEST(Engine, LongerRunsOfEveryDriveKindKeepTheirTrace) {
  // The prescribed-motion fast paths and the energy watch over many checks: every drive kind,
  // with a spring and damper to ground.
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  s.plant = {1.3, 20.0, 0.7};
  s.run = {1e-5, 3.0, 7};
  for (const auto kind : {Drive::Kind::Displacement, Drive::Kind::Velocity, Drive::Kind::Force, Drive::Kind::Pull}) {
    SCOPED_TRACE(to_string(kind));
    s.drive.kind = kind;
    s.drive.signal = kind == Drive::Kind::Pull ? Signal::ramp(0.0, 0.1) : Signal::sine(0.0, kind == Drive::Kind::Force ? 3.0 : 1e-3, 2.0);
    const Trace a = old_engine(s);
    const Trace b = simulate(s);
    ASSERT_EQ(a.size(), b.size());
    Diff d;
    d.add(a.x, b.x);
    d.add(a.v, b.v);
    d.add(a.friction, b.friction);
    d.add(a.applied, b.applied);
    d.add(a.element_force, b.element_force);
    EXPECT_EQ(a.element_slip, b.element_slip);
    EXPECT_LE(d.rel, 1e-12);
  }
}

TEST(Engine, ABoundedTraceIsCompactedAsTheOneBodyTrace) {
  // The one-body trace of one_body_simulation, bounded to 64 KiB and taken in steps, keeps the
  // samples Simulation keeps.
  const Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  const TraceOptions opts{.max_bytes = std::size_t{64} << 10};
  Simulation a(s, opts);
  AssemblySimulation b = one_body_simulation(s, opts);
  for (int chunk = 0; chunk < 40; ++chunk) {
    a.advance(25'000);
    b.advance(25'000);
    ASSERT_EQ(a.trace_bucket_steps(), b.trace_bucket_steps()) << chunk;
    const Trace& ta = a.trace();
    const Trace& tb = b.one_body_trace();
    ASSERT_EQ(ta.size(), tb.size()) << chunk;
    EXPECT_EQ(ta.t, tb.t);
    EXPECT_EQ(ta.x, tb.x);
    EXPECT_EQ(ta.v, tb.v);
    EXPECT_EQ(ta.friction, tb.friction);
    EXPECT_EQ(ta.applied, tb.applied);
    EXPECT_EQ(ta.element_force, tb.element_force);
    EXPECT_EQ(ta.element_slip, tb.element_slip);
  }
  EXPECT_GT(a.trace_bucket_steps(), 0u);  // it was compacted
  EXPECT_TRUE(b.trace().t.empty());       // the assembled trace takes no samples
}

TEST(Engine, DivergenceSaysWhatTheOneBodyEngineSays) {
  // A step too large for the damping: the energy watch stops both engines at the same check, with
  // the same message.
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  s.plant.damper = 2040.0;
  s.run.dt = 1e-3;
  std::string a, b;
  try {
    old_engine(s);
  } catch (const SimulationError& e) {
    a = e.what();
  }
  try {
    simulate(s);
  } catch (const SimulationError& e) {
    b = e.what();
  }
  EXPECT_NE(a.find("the energy of the mass and springs grew"), std::string::npos) << a;
  EXPECT_EQ(a.substr(0, a.find(" grew to")), b.substr(0, b.find(" grew to")));
  EXPECT_EQ(a.substr(a.find("Likely cause")), b.substr(b.find("Likely cause")));
}

// The reference traces: per preset NAME.trace, the assembled plant's trace (samples, channels,
// contacts, each contact's element count; t; values; per contact its element forces, element slip
// flags and gross-slip flags).
struct RefTrace {
  std::uint64_t n = 0, nc = 0;
  std::vector<std::uint64_t> ne;
  std::vector<double> t, values;
  std::vector<std::vector<double>> element_force;
  std::vector<std::vector<std::uint8_t>> element_slip, contact_slip;
};

bool read_reference(const fs::path& file, RefTrace& r) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  auto u64 = [&] {
    std::uint64_t v = 0;
    in.read(reinterpret_cast<char*>(&v), 8);
    return v;
  };
  auto doubles = [&](std::size_t n) {
    std::vector<double> v(n);
    in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * 8));
    return v;
  };
  auto bytes = [&](std::size_t n) {
    std::vector<std::uint8_t> v(n);
    in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n));
    return v;
  };
  r.n = u64();
  r.nc = u64();
  r.ne.resize(u64());
  for (auto& x : r.ne) x = u64();
  r.t = doubles(r.n);
  r.values = doubles(r.n * r.nc);
  for (auto ne : r.ne) {
    r.element_force.push_back(doubles(r.n * ne));
    r.element_slip.push_back(bytes(r.n * ne));
    r.contact_slip.push_back(bytes(r.n));
  }
  return static_cast<bool>(in);
}

TEST(Engine, EveryShippedPresetKeepsItsReferenceTrace) {
  const fs::path dir = fs::path(GMSLAB_BINARY_DIR) / "reference_traces";
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir.string() << ": no reference traces";
  int presets = 0;
  for (const auto& path : shipped_presets()) {
    SCOPED_TRACE(path.string());
    RefTrace ref;
    ASSERT_TRUE(read_reference(dir / (path.stem().string() + ".trace"), ref));
    ++presets;
    const AssemblyTrace tr = simulate(load_preset(path.string()).scenario);
    ASSERT_EQ(tr.size(), ref.n);
    ASSERT_EQ(tr.channels.size(), ref.nc);
    ASSERT_EQ(tr.n_elements.size(), ref.ne.size());
    EXPECT_EQ(tr.t, ref.t);
    Diff d;
    for (std::size_t c = 0; c < ref.nc; ++c) {
      std::vector<double> a(ref.n), b(ref.n);
      for (std::size_t k = 0; k < ref.n; ++k) a[k] = ref.values[k * ref.nc + c], b[k] = tr.values[k * ref.nc + c];
      d.add(a, b);
    }
    for (std::size_t j = 0; j < ref.ne.size(); ++j) {
      d.add(ref.element_force[j], tr.element_force[j]);
      EXPECT_EQ(ref.element_slip[j], tr.element_slip[j]);
      EXPECT_EQ(ref.contact_slip[j], tr.contact_slip[j]);
    }
    EXPECT_LE(d.rel, 1e-12);
    std::cout << "[ reference] " << path.filename().string() << ": " << ref.n << " samples, " << d.equal << " of " << d.n
              << " values bit for bit, max relative difference " << d.rel << '\n';
  }
  EXPECT_GE(presets, 14);
}

}  // namespace
}  // namespace gmslab
