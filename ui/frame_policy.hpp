// gmslab ui: when the window draws its next frame - the one frame policy of every tab.
//
// The window asks frame_wait() before each frame and then polls (draws at once: display rate),
// waits with a timeout, or waits for the next input event. Pure: no GLFW, no ImGui.
//   - something changes by itself (a run of the Simulation or Plant tab, an identification on its
//     worker thread, any other animation): poll;
//   - an input event was handled fewer than kSettleFrames frames ago: poll, so what the event
//     started (a popup opened on release, a click's press and release seen in two frames, a layout
//     that moves after an edit) is drawn without waiting for the next event;
//   - otherwise wait: until the next scheduled thing (the status report, `until_deadline_s`) or
//     the text caret's next blink (kCaretBlinkS) when a text field has the keyboard, else for input.
#pragma once

#include <limits>

namespace gmslab::ui {

struct FrameActivity {
  bool sim_running = false;    // the Simulation tab's run
  bool plant_running = false;  // the Plant tab's run (it advances while that tab is shown)
  bool identifying = false;    // an identification (or another background job) is working
  bool animating = false;      // anything else that changes in the next frame without input
  bool text_input = false;     // a text field has the keyboard (its caret blinks)
  bool any_active() const { return sim_running || plant_running || identifying || animating; }
};

enum class FrameWaitKind { Poll, Timeout, Wait };
struct FrameWait {
  FrameWaitKind kind = FrameWaitKind::Wait;
  double timeout_s = 0.0;  // Timeout: the longest wait [s]
  bool operator==(const FrameWait&) const = default;
};

// Frames drawn after each input event before the window may wait again (ImGui needs two to
// settle: a popup is sized in the frame after it opens; a press and its release land in two).
inline constexpr int kSettleFrames = 3;
// The longest wait while a text field has the keyboard (ImGui's caret blinks at 0.4 / 0.8 s).
inline constexpr double kCaretBlinkS = 0.2;

// frames_since_input: frames drawn since the last input event was handled (0: the frame just drawn
// handled one). until_deadline_s: seconds to the next scheduled frame (infinity: none).
FrameWait frame_wait(const FrameActivity& a, int frames_since_input,
                     double until_deadline_s = std::numeric_limits<double>::infinity());

}  // namespace gmslab::ui
