// gmslab core: series derived from a trace, computed from the trace itself (never cached apart
// from it), so a changed setting applies to every recorded sample.
//
// Stick / slip phase of a sample: gross slip when the body moves (|v| > slip_velocity) or every
// recorded friction element slips; a single weak element slipping is still presliding (the body
// sticks).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/sim/simulation.hpp"

namespace gmslab {

enum class Phase : std::uint8_t { Stick = 0, Slip = 1 };

// The phase of sample k of `tr`.
Phase phase_at(const Trace& tr, std::size_t k, double slip_velocity);
// The phase of every sample of `tr` (0 = stick, 1 = slip), written into `out` (resized).
void classify_phases(const Trace& tr, double slip_velocity, std::vector<std::uint8_t>& out);

// The phases of a growing trace, one byte per sample. update() classifies only the new samples
// while the threshold and the trace's revision (bumped whenever recorded samples change: reset,
// compaction, a live edit that re-lays the element columns) stay the same, and reclassifies the
// whole trace otherwise - a new threshold applies to every sample already recorded.
class PhaseSeries {
 public:
  std::span<const std::uint8_t> update(const Trace& tr, double slip_velocity);
  std::span<const std::uint8_t> phases() const { return phase_; }

 private:
  std::vector<std::uint8_t> phase_;
  double threshold_ = -1.0;
  std::uint64_t revision_ = 0;
  const Trace* trace_ = nullptr;
};

}  // namespace gmslab
