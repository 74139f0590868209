#include "ui/frame_policy.hpp"

#include <algorithm>
#include <cmath>

namespace gmslab::ui {

FrameWait frame_wait(const FrameActivity& a, int frames_since_input, double until_deadline_s) {
  if (a.any_active() || frames_since_input < kSettleFrames) return {FrameWaitKind::Poll, 0.0};
  double t = std::isnan(until_deadline_s) ? 0.0 : std::max(0.0, until_deadline_s);
  if (a.text_input) t = std::min(t, kCaretBlinkS);
  if (std::isinf(t)) return {FrameWaitKind::Wait, 0.0};
  if (t <= 0.0) return {FrameWaitKind::Poll, 0.0};
  return {FrameWaitKind::Timeout, t};
}

}  // namespace gmslab::ui
