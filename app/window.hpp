// gmslab app: the desktop window (GLFW + ImGui OpenGL3 backend) running ui::draw_frame.
#pragma once

#include <string>

namespace gmslab::ui {
struct LaunchRequest;
}

namespace gmslab::app {

// Returned by run_window when no window can be opened (no display, glfwInit or window creation
// failed); the caller falls back to headless output.
inline constexpr int kNoWindow = -100;

// Opens the window and runs until it is closed. The session (scenario, overlay model, view) is
// restored from `session_path` when that file exists and is valid, and saved there on exit.
// `launch` (checked with ui::check_launch), when given, is opened on top of it (gmslab --open).
// With the environment variable GMSLAB_UI_STATUS=FILE the window appends one JSON line per wall
// second to FILE (ui::ui_status_json: frames drawn, active tab, the active run and its time).
// Frames follow ui::frame_wait (ui/frame_policy.hpp). Returns the process exit code, or kNoWindow.
int run_window(const std::string& session_path, const ui::LaunchRequest* launch = nullptr);

// $GMSLAB_SESSION, else $XDG_CONFIG_HOME/gmslab/session.json, else ~/.config/gmslab/session.json.
std::string default_session_path();

}  // namespace gmslab::app
