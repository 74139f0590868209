// Every shipped preset keeps its trace: the engine's trace of each preset against a committed
// reference (tests/data/engine_reference/NAME.csv), within 1e-12 of each column's largest magnitude
// (bit for bit is not portable across x86-64 libm variants). A reference holds every K-th sample of
// the trace with 17 significant digits (which give a double back exactly), the sample count, and
// per column the sum, the sum of magnitudes and the largest magnitude over every sample: a kept
// sample that moves by more than 1e-12 of its column's scale fails the test, and so does any
// sample that moves by more than (samples x 1e-12) of it (through the sums). One-body presets are
// compared in the one-body trace layout (t, x, v, F_f, F_applied, element forces and slip flags:
// what `gmslab simulate` writes), assembled ones in the assembled layout (t, every channel, per
// contact its element forces, element slip flags and gross-slip flag). Three further references
// hold a run edited live, the same run with its trace bounded to 64 KiB, and a run of each drive
// kind with a spring and damper.
//
// The references were written by the one-body engine that this engine replaced (one-body presets,
// the live edits, the drive kinds) and by this engine (assembled presets), each in one run.
// GMSLAB_WRITE_ENGINE_REFERENCE=1 rewrites them from the engine under test instead of comparing:
// only for an intended change of the traces, explained in its commit.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>

#include "core/error.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;

// A trace as named columns of doubles (slip flags as 0 / 1).
struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> cols;
  std::size_t rows() const { return cols.empty() ? 0 : cols[0].size(); }
  void add(std::string name, std::vector<double> col) {
    names.push_back(std::move(name));
    cols.push_back(std::move(col));
  }
};

template <class T>
std::vector<double> strided(const std::vector<T>& v, std::size_t n, std::size_t i,
                            std::size_t stride) {
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = static_cast<double>(v[k * stride + i]);
  return out;
}

Table table_of(const Trace& tr) {
  Table t;
  const std::size_t n = tr.size(), ne = tr.n_elements;
  t.add("t", tr.t);
  t.add("x", tr.x);
  t.add("v", tr.v);
  t.add("F_f", tr.friction);
  t.add("F_applied", tr.applied);
  for (std::size_t i = 0; i < ne; ++i)
    t.add("F" + std::to_string(i + 1), strided(tr.element_force, n, i, ne));
  for (std::size_t i = 0; i < ne; ++i)
    t.add("slip" + std::to_string(i + 1), strided(tr.element_slip, n, i, ne));
  return t;
}

Table table_of(const AssemblyTrace& tr) {
  Table t;
  const std::size_t n = tr.size(), nc = tr.channels.size();
  t.add("t", tr.t);
  for (std::size_t c = 0; c < nc; ++c) t.add(tr.channels[c].name, strided(tr.values, n, c, nc));
  for (std::size_t j = 0; j < tr.n_elements.size(); ++j) {
    const std::size_t ne = tr.n_elements[j];
    const std::string cj = "c" + std::to_string(j) + ".";
    for (std::size_t i = 0; i < ne; ++i)
      t.add(cj + "F" + std::to_string(i + 1), strided(tr.element_force[j], n, i, ne));
    for (std::size_t i = 0; i < ne; ++i)
      t.add(cj + "slip" + std::to_string(i + 1), strided(tr.element_slip[j], n, i, ne));
    t.add(cj + "gross_slip", strided(tr.contact_slip[j], n, 0, 1));
  }
  return t;
}

// Per column over every sample: sum, sum of magnitudes, largest magnitude.
struct Summary {
  std::vector<double> sum, abs_sum, max_abs;
};
Summary summarise(const Table& t) {
  Summary s;
  for (const auto& c : t.cols) {
    double a = 0.0, b = 0.0, m = 0.0;
    for (double x : c) a += x, b += std::abs(x), m = std::max(m, std::abs(x));
    s.sum.push_back(a);
    s.abs_sum.push_back(b);
    s.max_abs.push_back(m);
  }
  return s;
}

std::string g17(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

constexpr std::size_t kRowsKept = 100;

void write_reference(const fs::path& file, const Table& t) {
  const std::size_t n = t.rows(), every = std::max<std::size_t>(1, n / kRowsKept);
  const Summary s = summarise(t);
  std::ofstream out(file);
  auto line = [&](const char* key, const std::vector<double>& v) {
    out << "# " << key;
    for (double x : v) out << ',' << g17(x);
    out << '\n';
  };
  out << "# rows," << n << "\n# every," << every << '\n';
  line("sum", s.sum);
  line("abs_sum", s.abs_sum);
  line("max_abs", s.max_abs);
  for (std::size_t c = 0; c < t.names.size(); ++c) out << (c ? "," : "") << t.names[c];
  out << '\n';
  for (std::size_t k = 0; k < n; k += every) {
    for (std::size_t c = 0; c < t.cols.size(); ++c) out << (c ? "," : "") << g17(t.cols[c][k]);
    out << '\n';
  }
}

struct Reference {
  std::size_t rows = 0, every = 1;
  Summary summary;
  std::vector<std::string> names;
  std::vector<std::vector<double>> kept;  // [kept row][column]
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  return out;
}

std::vector<double> numbers(const std::vector<std::string>& f, std::size_t from) {
  std::vector<double> v;
  for (std::size_t i = from; i < f.size(); ++i) v.push_back(std::strtod(f[i].c_str(), nullptr));
  return v;
}

Reference read_reference(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot be read");
  Reference r;
  std::string line;
  while (std::getline(in, line)) {
    const auto f = split(line);
    if (f.empty()) continue;
    if (f[0] == "# rows")
      r.rows = std::stoull(f.at(1));
    else if (f[0] == "# every")
      r.every = std::stoull(f.at(1));
    else if (f[0] == "# sum")
      r.summary.sum = numbers(f, 1);
    else if (f[0] == "# abs_sum")
      r.summary.abs_sum = numbers(f, 1);
    else if (f[0] == "# max_abs")
      r.summary.max_abs = numbers(f, 1);
    else if (r.names.empty())
      r.names = f;
    else
      r.kept.push_back(numbers(f, 0));
  }
  return r;
}

// Compares the engine's table with a reference: the sample count, the column names, the kept
// rows within 1e-12 of the column's largest magnitude, each column's sums within 1e-12 of its sum
// of magnitudes and its largest magnitude within 1e-12 relative. Returns the largest relative
// difference seen and counts the values compared.
double compare(const Table& t, const Reference& r, std::size_t& compared) {
  const double tol = 1e-12;
  EXPECT_EQ(t.rows(), r.rows);
  EXPECT_EQ(t.names, r.names);
  if (t.rows() != r.rows || t.names != r.names) return INFINITY;
  const Summary s = summarise(t);
  double worst = 0.0;
  auto rel = [&](double a, double b, double scale) {
    const double d = a == b ? 0.0 : std::abs(a - b) / scale;
    worst = std::max(worst, d);
    ++compared;
    return d;
  };
  for (std::size_t c = 0; c < t.cols.size(); ++c) {
    const double scale = r.summary.max_abs.at(c);
    EXPECT_LE(rel(s.sum[c], r.summary.sum.at(c), r.summary.abs_sum.at(c)), tol)
        << t.names[c] << " sum";
    EXPECT_LE(rel(s.abs_sum[c], r.summary.abs_sum.at(c), r.summary.abs_sum.at(c)), tol)
        << t.names[c] << " abs sum";
    EXPECT_LE(rel(s.max_abs[c], scale, scale), tol) << t.names[c] << " max";
    for (std::size_t q = 0; q < r.kept.size(); ++q)
      EXPECT_LE(rel(t.cols[c].at(q * r.every), r.kept[q].at(c), scale), tol)
          << t.names[c] << " at sample " << q * r.every;
  }
  EXPECT_EQ(r.kept.size(), (r.rows + r.every - 1) / r.every);
  return worst;
}

fs::path reference_dir() {
  return fs::path(GMSLAB_SOURCE_DIR) / "tests" / "data" / "engine_reference";
}

bool writing() {
  const char* w = std::getenv("GMSLAB_WRITE_ENGINE_REFERENCE");
  return w && std::string(w) == "1";
}

// Writes or checks one reference; returns the values compared (0 when writing).
std::size_t check_reference(const std::string& name, const Table& t) {
  const fs::path file = reference_dir() / (name + ".csv");
  if (writing()) {
    fs::create_directories(reference_dir());
    write_reference(file, t);
    return 0;
  }
  std::size_t compared = 0;
  const double worst = compare(t, read_reference(file), compared);
  std::cout << "[ reference] " << name << ": " << t.rows() << " samples, " << compared
            << " values compared, largest relative difference " << worst << '\n';
  return compared;
}

std::vector<fs::path> shipped_presets() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(GMSLAB_SOURCE_DIR) / "presets"))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

Table one_body_table(const Scenario& s) { return table_of(simulate(s)); }

Scenario fig4() {
  return load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
}

TEST(EngineReference, EveryShippedPresetKeepsItsTrace) {
  int presets = 0, one_body = 0;
  for (const auto& path : shipped_presets()) {
    SCOPED_TRACE(path.string());
    const Preset p = load_preset(path.string());
    const Table t = p.assembled() ? table_of(simulate(p.scenario)) : one_body_table(p.one_body());
    ASSERT_GT(t.rows(), 100u);
    check_reference(path.stem().string(), t);
    ++presets;
    one_body += !p.assembled();
  }
  EXPECT_GE(presets, 14);
  EXPECT_GE(one_body, 10);
}

// Fig. 4 edited live, the state kept: at 8 s other element stiffnesses and Fc (same shape), at
// 12 s another plant, at 16 s three elements instead of four (the friction restarts virgin).
Table edited_fig4(const TraceOptions& opts) {
  const Scenario s = fig4();
  AssemblySimulation sim = one_body_simulation(s, opts);
  auto until = [&](double t) {
    sim.advance(
        static_cast<std::size_t>(std::llround(t / s.run.dt) - std::llround(sim.time() / s.run.dt)));
  };
  until(8.0);
  ModelParams p = s.friction;
  p.set_scalar("Fc", 0.8);
  for (auto& row : p.elements) row[1] *= 0.7;
  sim.set_friction(p);
  until(12.0);
  sim.set_plant(Plant{1.5, 3.0, 0.2});
  until(16.0);
  p.elements = {{0.2, 50000, 40}, {0.3, 40000, 30}, {0.5, 30000, 20}};
  sim.set_friction(p);
  sim.run_to_end();
  return table_of(sim.take_one_body_trace());
}

TEST(EngineReference, ARunEditedLiveKeepsItsTrace) {
  check_reference("live_edits_fig4", edited_fig4({}));
}

TEST(EngineReference, ABoundedTraceKeepsItsCompactedSamples) {
  const Table t = edited_fig4(TraceOptions{.max_bytes = std::size_t{64} << 10});
  EXPECT_LT(t.rows(), (std::size_t{64} << 10) / trace_sample_bytes(3));
  check_reference("live_edits_fig4_bounded_64k", t);
}

TEST(EngineReference, EveryDriveKindKeepsItsTrace) {
  // The prescribed-motion fast paths and the energy watch over many checks: every drive kind,
  // with a spring and damper to ground, one after the other in one table.
  Scenario s = fig4();
  s.plant = {1.3, 20.0, 0.7};
  s.run = {1e-5, 3.0, 7};
  for (const auto kind :
       {Drive::Kind::Displacement, Drive::Kind::Velocity, Drive::Kind::Force, Drive::Kind::Pull}) {
    s.drive.kind = kind;
    s.drive.signal = kind == Drive::Kind::Pull
                         ? Signal::ramp(0.0, 0.1)
                         : Signal::sine(0.0, kind == Drive::Kind::Force ? 3.0 : 1e-3, 2.0);
    check_reference(std::string("drive_") + to_string(kind), one_body_table(s));
  }
}

TEST(EngineReference, AChangedTraceFailsTheComparison) {
  // The comparison itself: a kept sample moved by 1e-10 of its column's scale fails it, a sample
  // between kept ones moved by rows x 1e-10 of it (seen by the column's sums) too, and so does a
  // trace one sample short; the unchanged table passes.
  const Preset p = load_preset(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2a_presliding.json");
  const Table t = table_of(simulate(p.one_body()));
  if (writing()) GTEST_SKIP() << "writing the references";
  const Reference r = read_reference(reference_dir() / "fig2a_presliding.csv");
  std::size_t n = 0;
  EXPECT_EQ(compare(t, r, n), 0.0);
  const double scale = r.summary.max_abs[3];
  const double rows = static_cast<double>(r.rows);
  std::vector<Table> changed(3, t);
  changed[0].cols[3][r.every * 3] += 1e-10 * scale;             // a kept sample
  changed[1].cols[3][r.every * 3 + 1] += rows * 1e-10 * scale;  // one between kept samples
  for (auto& c : changed[2].cols) c.pop_back();                 // one sample short
  int failures = 0;
  for (const Table& u : changed) {
    ::testing::TestPartResultArray results;
    {
      ::testing::ScopedFakeTestPartResultReporter rep(
          ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
      compare(u, r, n);
    }
    failures += results.size() > 0;
  }
  EXPECT_EQ(failures, 3);
}

}  // namespace
}  // namespace gmslab
