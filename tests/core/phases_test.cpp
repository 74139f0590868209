// Stick / slip phases are derived from the trace in core: a changed threshold reclassifies every
// sample already recorded, and a growing trace is classified as it grows.
#include "core/sim/phases.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/assembly.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

// The definition, written out independently: slip when |v| > threshold or every element slips.
std::vector<std::uint8_t> expected_phases(const Trace& tr, double thr) {
  std::vector<std::uint8_t> out;
  const std::size_t ne = tr.n_elements;
  for (std::size_t k = 0; k < tr.size(); ++k) {
    bool all = ne > 0;
    for (std::size_t i = 0; i < ne; ++i) all = all && tr.element_slip[k * ne + i] == 1;
    out.push_back(std::abs(tr.v[k]) > thr || all ? 1 : 0);
  }
  return out;
}

std::size_t count_slip(std::span<const std::uint8_t> p) {
  std::size_t n = 0;
  for (auto c : p) n += c;
  return n;
}

TEST(Phases, ChangedThresholdAfterARunReclassifiesTheWholeTrace) {
  AssemblySimulation sim =
      one_body_simulation(load_scenario(test_util::preset_path("fig4_stick_slip.json")));
  sim.run_to_end();
  const Trace& tr = sim.one_body_trace();
  PhaseSeries ps;
  const std::vector<std::uint8_t> low(ps.update(tr, 1e-4).begin(), ps.update(tr, 1e-4).end());
  ASSERT_EQ(low, expected_phases(tr, 1e-4));
  // Now a threshold ten times higher, after the run: every sample, the first ones included.
  const auto high = ps.update(tr, 1e-3);
  ASSERT_EQ(high.size(), tr.size());
  EXPECT_EQ(std::vector<std::uint8_t>(high.begin(), high.end()), expected_phases(tr, 1e-3));
  EXPECT_LT(count_slip(high), count_slip(low));
  // Samples classified slip at 1e-4 and stick at 1e-3 exist in the first half of the run too.
  std::size_t flipped_early = 0;
  for (std::size_t k = 0; k < tr.size() / 2; ++k) flipped_early += low[k] == 1 && high[k] == 0;
  EXPECT_GT(flipped_early, 10u);
  // And back: the same as classifying from scratch.
  std::vector<std::uint8_t> fresh;
  classify_phases(tr, 1e-4, fresh);
  const auto again = ps.update(tr, 1e-4);
  EXPECT_EQ(std::vector<std::uint8_t>(again.begin(), again.end()), fresh);
}

TEST(Phases, GrowingTraceIsClassifiedAsItGrowsAndAResetStartsOver) {
  AssemblySimulation sim =
      one_body_simulation(load_scenario(test_util::preset_path("fig4_stick_slip.json")));
  PhaseSeries ps;
  for (int i = 0; i < 20; ++i) {
    sim.advance(100000);
    const auto p = ps.update(sim.one_body_trace(), 2e-4);
    ASSERT_EQ(std::vector<std::uint8_t>(p.begin(), p.end()),
              expected_phases(sim.one_body_trace(), 2e-4))
        << i;
  }
  sim.reset();
  EXPECT_EQ(ps.update(sim.one_body_trace(), 2e-4).size(), 1u);
}

}  // namespace
}  // namespace gmslab
