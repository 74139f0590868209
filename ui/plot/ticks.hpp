// gmslab ui: "nice" axis ticks (pure; no ImGui).
//
// nice_ticks(lo, hi, target) returns tick values k * step inside [lo, hi], where
// step = m * 10^e with m in {1, 2, 2.5, 5} chosen so that about `target` ticks fit.
// format_tick prints a tick with just enough decimals for its step ("0.25", "1e-05", "-3").
#pragma once

#include <string>
#include <vector>

namespace gmslab::ui {

struct Ticks {
  double step = 0.0;           // spacing between ticks (same unit as the axis), > 0
  std::vector<double> values;  // increasing, all in [lo, hi]
};

// lo < hi expected; a degenerate or non-finite range gives no ticks. target >= 2.
Ticks nice_ticks(double lo, double hi, int target = 6);
// Shortest text for `value` that still tells ticks `step` apart; exact zero prints "0".
// `magnitude` (the largest |tick| of the axis; 0: |value|) picks fixed or scientific notation
// for the whole axis: scientific when it is >= 1e5 or < 1e-3.
std::string format_tick(double value, double step, double magnitude = 0.0);

}  // namespace gmslab::ui
