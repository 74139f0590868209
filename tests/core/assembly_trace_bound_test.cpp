// The assembled plant's trace memory: a bounded run (TraceOptions::max_bytes) stays within its
// room and keeps, in every bucket of the final width, the first and last sample and the smallest
// and largest value of every output of the unbounded run, sample for sample; the streamed CSV is
// the whole run's CSV byte for byte (the CLI's constant-memory writer).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "core/io/assembly_io.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab {
namespace {

AssemblyScenario preset(const char* name) {
  return load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name);
}

TEST(AssemblyTraceBound, BoundedRunsKeepEveryBucketsExtremesWithinTheirRoom) {
  std::mt19937 rng(1105);
  for (const char* name : {"two_mass_drive.json", "slider_on_table.json", "three_body_chain.json", "fig4_stick_slip.json"}) {
    for (int trial = 0; trial < 2; ++trial) {
      AssemblyScenario s = preset(name);
      s.run.duration = std::min(s.run.duration, std::uniform_real_distribution<double>(0.5, 3.0)(rng));
      s.run.record_every = 1 + static_cast<int>(rng() % 4);
      const std::size_t max_bytes = std::size_t{1} << (15 + rng() % 3);  // 32 to 128 KiB
      SCOPED_TRACE(std::string(name) + " max_bytes " + std::to_string(max_bytes));
      AssemblySimulation full(s), bounded(s, TraceOptions{.max_bytes = max_bytes});
      full.run_to_end();
      bounded.run_to_end();
      const AssemblyTrace& F = full.trace();
      const AssemblyTrace& B = bounded.trace();
      ASSERT_GT(bounded.trace_bucket_steps(), 0u) << "the run was long enough to be compacted";
      EXPECT_LE(B.size(), bounded.trace_max_samples());
      EXPECT_LE(B.size() * B.sample_bytes(), max_bytes);
      EXPECT_LT(B.size(), F.size() / 2) << "the bound made a difference";
      const std::size_t nc = F.channels.size();
      ASSERT_EQ(B.channels.size(), nc);
      // Every kept sample is one of the full run's, with all its columns.
      std::map<long long, std::size_t> index;  // step -> full sample
      for (std::size_t k = 0; k < F.size(); ++k) index[std::llround(F.t[k] / s.run.dt)] = k;
      for (std::size_t k = 0; k < B.size(); ++k) {
        const auto it = index.find(std::llround(B.t[k] / s.run.dt));
        ASSERT_NE(it, index.end()) << "sample at t = " << B.t[k] << " s is not a recorded sample";
        for (std::size_t c = 0; c < nc; ++c) ASSERT_EQ(B.at(k, c), F.at(it->second, c));
        for (std::size_t j = 0; j < F.contact_slip.size(); ++j) {
          ASSERT_EQ(B.contact_slip[j][k], F.contact_slip[j][it->second]);
          const std::size_t ne = F.n_elements[j];
          for (std::size_t i = 0; i < ne; ++i) ASSERT_EQ(B.element_force[j][k * ne + i], F.element_force[j][it->second * ne + i]);
        }
        if (k > 0) {
          ASSERT_GT(B.t[k], B.t[k - 1]);
        }
      }
      EXPECT_EQ(B.t.front(), F.t.front());
      EXPECT_EQ(B.t.back(), F.t.back());
      // Per bucket of the final width: each output's extremes of the full run are in the bounded one.
      const std::uint64_t w = bounded.trace_bucket_steps();
      auto bucket = [&](double t) { return static_cast<std::uint64_t>(std::llround(t / s.run.dt)) / w; };
      std::map<std::uint64_t, std::vector<std::pair<double, double>>> full_ext, kept_ext;
      auto add = [&](auto& m, const AssemblyTrace& tr, std::size_t k) {
        auto& e = m[bucket(tr.t[k])];
        if (e.empty()) e.assign(nc, {INFINITY, -INFINITY});
        for (std::size_t c = 0; c < nc; ++c) e[c] = {std::min(e[c].first, tr.at(k, c)), std::max(e[c].second, tr.at(k, c))};
      };
      for (std::size_t k = 0; k < F.size(); ++k) add(full_ext, F, k);
      for (std::size_t k = 0; k < B.size(); ++k) add(kept_ext, B, k);
      EXPECT_EQ(kept_ext, full_ext);
    }
  }
}

TEST(AssemblyTraceBound, StreamedCsvIsTheWholeRunsCsv) {
  for (const char* name : {"two_mass_drive.json", "slider_on_table.json"}) {
    AssemblyScenario s = preset(name);
    s.run.record_every = 1;
    s.run.duration = std::min(s.run.duration, 0.4);  // > 16384 samples: several chunks
    std::ostringstream whole;
    write_assembly_trace_csv(simulate(s), whole);
    std::string streamed;
    int pieces = 0;
    const std::size_t n = stream_assembly_trace_csv(s, [&](std::string_view t) { streamed += t, ++pieces; });
    EXPECT_EQ(n, simulate(s).size());
    EXPECT_GE(pieces, 2) << name;
    EXPECT_TRUE(streamed == whole.str()) << name;
  }
}

}  // namespace
}  // namespace gmslab

namespace gmslab {
namespace {
// One body with its spring, damper and drive force each split in two parts to ground (the one-body
// loop for several parts, advance_one_body, which no v1 preset takes) follows the one-body
// run of the merged plant (the one-body fast path) to rounding, for random parameters.
TEST(AssemblyTraceBound, OneBodyWithSplitPartsFollowsTheMergedOneBodyPlant) {
  std::mt19937 rng(1106);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 8; ++trial) {
    Scenario s;
    s.name = "split " + std::to_string(trial);
    s.friction = model_info("gms").defaults();
    s.plant.mass = 0.2 + 3.0 * u(rng);
    const double k1 = 40.0 * u(rng), k2 = 40.0 * u(rng), c1 = u(rng), c2 = u(rng);
    const double a1 = 1.0 + 2.0 * u(rng), f = 0.5 + u(rng);
    s.plant.spring = k1 + k2;
    s.plant.damper = c1 + c2;
    s.drive.kind = Drive::Kind::Force;
    s.drive.signal = Signal::sine(0.0, 2.0 * a1, f);
    s.run = {1e-5, 1.5, 1 + trial % 3};
    AssemblyScenario as = assembly_from_scenario(s);
    Assembly& a = as.plant;
    ASSERT_EQ(a.springs.size(), 1u);
    a.springs[0].stiffness = k1;
    a.springs.push_back({"spring_b", 0, kGround, k2});
    a.dampers[0].damping = c1;
    a.dampers.push_back({"damper_b", 0, kGround, c2});
    a.drives[0].signal = Signal::sine(0.0, a1, f);
    a.drives.push_back({"drive_b", DrivePart::Kind::Force, 0, Signal::sine(0.0, a1, f)});
    SCOPED_TRACE(s.name);
    const Trace ref = simulate(s);
    const AssemblyTrace tr = simulate(as);
    ASSERT_EQ(tr.size(), ref.size());
    const auto x = tr.series("x.mass"), ff = tr.series("F.friction");
    double xmax = 0.0, fmax = 0.0, dx = 0.0, df = 0.0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
      xmax = std::max(xmax, std::abs(ref.x[k]));
      fmax = std::max(fmax, std::abs(ref.friction[k]));
      dx = std::max(dx, std::abs(x[k] - ref.x[k]));
      df = std::max(df, std::abs(ff[k] - ref.friction[k]));
    }
    ASSERT_GT(xmax, 0.0);
    EXPECT_LE(dx, 1e-8 * xmax);
    EXPECT_LE(df, 1e-6 * fmax);
  }
}
}  // namespace
}  // namespace gmslab
