#include "app/window.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <csignal>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <thread>
#include <vector>

#include <climits>
#include <sys/wait.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/ident/figure_json.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/session_io.hpp"
#include "ui/app.hpp"
#include "ui/app_files.hpp"
#include "ui/frame_policy.hpp"
#include "ui/identify/identify_panel.hpp"
#include "ui/plot/plot.hpp"
#include "ui/style.hpp"

namespace gmslab::app {

namespace {
// The three GL calls the window makes itself, loaded through GLFW (the target links no libGL; the
// ImGui OpenGL3 backend loads its own functions).
struct Gl {
  void (*viewport)(int, int, int, int) = nullptr;
  void (*clear_color)(float, float, float, float) = nullptr;
  void (*clear)(unsigned) = nullptr;
  bool load() {
    viewport = reinterpret_cast<decltype(viewport)>(glfwGetProcAddress("glViewport"));
    clear_color = reinterpret_cast<decltype(clear_color)>(glfwGetProcAddress("glClearColor"));
    clear = reinterpret_cast<decltype(clear)>(glfwGetProcAddress("glClear"));
    return viewport && clear_color && clear;
  }
};
constexpr unsigned kColorBufferBit = 0x00004000;  // GL_COLOR_BUFFER_BIT

// SIGINT / SIGTERM close the window normally, so the session is still saved.
volatile std::sig_atomic_t g_quit = 0;
void on_signal(int) { g_quit = 1; }

// PNG export of a plot: the figure drawn by gmslab-headless plot-figure (the same drawing as
// `gmslab figures`), next to this executable, as a child process; the window keeps running.
void png_via_headless(const Figure& f, const std::string& path) {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  std::string exe = "gmslab-headless";
  if (n > 0) exe = std::filesystem::path(std::string(buf, static_cast<std::size_t>(n))).parent_path() / "gmslab-headless";
  const std::string json = path + ".figure.json";
  save_figure_json(f, json);
  const pid_t pid = fork();
  if (pid == 0) {
    execl(exe.c_str(), exe.c_str(), "plot-figure", json.c_str(), "--out", path.c_str(), "--size", "1600x1000",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (pid > 0) waitpid(pid, &status, 0);
  std::filesystem::remove(json);
  if (pid < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw IoError("PNG not written: " + exe + " plot-figure failed (build the gmslab-headless target)");
}

void glfw_error(int code, const char* text) { std::fprintf(stderr, "gmslab: GLFW error %d: %s\n", code, text); }

// Restores the last session, else opens the stick-slip preset.
void initial_state(ui::AppState& s, const std::string& session_path) {
  if (std::filesystem::exists(session_path)) {
    try {
      ui::restore_session(s, load_session(session_path));
      s.note("restored the session from " + session_path);
      return;
    } catch (const std::exception& e) {
      s.report(ui::Panel::Simulation, e, "session not restored");
      // Keep the user's file: the session saved on exit would otherwise overwrite it.
      try {
        s.status += "; the file was kept as " + set_aside(session_path);
      } catch (const std::exception& e2) {
        s.report(ui::Panel::Simulation, e2, "session file not set aside");
      }
    }
  }
  const std::string preset = ui::presets_dir() + "/fig4_stick_slip.json";
  try {
    ui::load_scenario_into(s, load_scenario(preset), preset);
    ui::mark_clean(s);
  } catch (const std::exception& e) {
    s.report(ui::Panel::Simulation, e, "default preset not loaded");
  }
}

// The Plant tab shows the session's plant, else the two-mass drive preset.
void initial_plant(ui::AppState& s) {
  if (s.plant.scenario) return;
  const std::string preset = ui::presets_dir() + "/two_mass_drive.json";
  try {
    ui::load_plant(s.plant, load_assembly_scenario(preset), preset);
  } catch (const std::exception& e) {
    s.plant.error = "default plant not loaded: " + std::string(e.what());
  }
}

void save(const ui::AppState& s, const std::string& path) {
  if (!s.main.sim) return;
  try {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    save_session(ui::make_session(s), path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gmslab: session not saved: %s\n", e.what());
  }
}

// Input events seen by the window (GLFW callbacks; ImGui's backend chains to those it also
// installs), counted so the frame policy knows when one was handled. Key presses are kept until
// the next frame: ImGui 1.86's GLFW backend only holds the keys' current state, so a key pressed
// and released between two frames (a quick Return, Ctrl+S from a script) would never be seen.
struct InputEvents {
  unsigned long long count = 0;
  struct Press {
    int key = 0, mods = 0;
  };
  std::vector<Press> presses;  // since the last frame
  static InputEvents* of(GLFWwindow* w) { return static_cast<InputEvents*>(glfwGetWindowUserPointer(w)); }
  static void bump(GLFWwindow* w) {
    if (auto* e = of(w)) ++e->count;
  }
  // Each key pressed since the last frame is down in this one (with its modifiers); its release,
  // already in io, shows in the next frame, which the frame policy draws (kSettleFrames).
  void hold_presses(ImGuiIO& io) {
    for (const Press& p : presses) {
      if (p.key >= 0 && p.key < IM_ARRAYSIZE(io.KeysDown)) io.KeysDown[p.key] = true;
      io.KeyCtrl |= (p.mods & GLFW_MOD_CONTROL) || p.key == GLFW_KEY_LEFT_CONTROL || p.key == GLFW_KEY_RIGHT_CONTROL;
      io.KeyShift |= (p.mods & GLFW_MOD_SHIFT) || p.key == GLFW_KEY_LEFT_SHIFT || p.key == GLFW_KEY_RIGHT_SHIFT;
      io.KeyAlt |= (p.mods & GLFW_MOD_ALT) || p.key == GLFW_KEY_LEFT_ALT || p.key == GLFW_KEY_RIGHT_ALT;
    }
    presses.clear();
  }
  void install(GLFWwindow* w) {
    glfwSetWindowUserPointer(w, this);
    glfwSetMouseButtonCallback(w, [](GLFWwindow* w, int, int, int) { bump(w); });
    glfwSetScrollCallback(w, [](GLFWwindow* w, double, double) { bump(w); });
    glfwSetKeyCallback(w, [](GLFWwindow* w, int key, int, int action, int mods) {
      bump(w);
      if (auto* e = of(w); e && action == GLFW_PRESS) e->presses.push_back({key, mods});
    });
    glfwSetCharCallback(w, [](GLFWwindow* w, unsigned) { bump(w); });
    glfwSetCursorPosCallback(w, [](GLFWwindow* w, double, double) { bump(w); });
    glfwSetCursorEnterCallback(w, [](GLFWwindow* w, int) { bump(w); });
    glfwSetWindowFocusCallback(w, [](GLFWwindow* w, int) { bump(w); });
    glfwSetFramebufferSizeCallback(w, [](GLFWwindow* w, int, int) { bump(w); });
    glfwSetWindowRefreshCallback(w, [](GLFWwindow* w) { bump(w); });
  }
};

// GMSLAB_UI_STATUS=FILE: one line of ui::ui_status_json appended per wall second.
struct StatusReport {
  using clock = std::chrono::steady_clock;
  std::string path;
  clock::time_point next = clock::now() + std::chrono::seconds(1);
  double seconds_left() const {
    if (path.empty()) return std::numeric_limits<double>::infinity();
    return std::chrono::duration<double>(next - clock::now()).count();
  }
  void maybe_write(const ui::AppState& s, long long frames) {
    if (path.empty() || clock::now() < next) return;
    next += std::chrono::seconds(1);
    if (next < clock::now()) next = clock::now() + std::chrono::seconds(1);  // after a stall: no burst
    if (std::FILE* f = std::fopen(path.c_str(), "a")) {
      std::fprintf(f, "%s\n", ui::ui_status_json(s, frames).c_str());
      std::fclose(f);
    } else {
      std::fprintf(stderr, "gmslab: GMSLAB_UI_STATUS: cannot append to %s: %s (status reports stop)\n", path.c_str(),
                   std::strerror(errno));
      path.clear();
    }
  }
};

void loop(GLFWwindow* win, ui::AppState& s, const Gl& gl, InputEvents& events) {
  using clock = std::chrono::steady_clock;
  auto next = clock::now();
  s.keys = {GLFW_KEY_S, GLFW_KEY_F5};
  std::string title;
  unsigned long long seen = 0;
  int frames_since_input = 0;  // the first frames settle like after an event
  long long frames = 0;
  long long fps_frames = 0;
  auto fps_until = clock::now() + std::chrono::seconds(1);
  StatusReport report;
  if (const char* p = std::getenv("GMSLAB_UI_STATUS"); p && *p) report.path = p;
  while (!glfwWindowShouldClose(win) && !g_quit) {
    if (std::string t = ui::window_title(s); t != title) glfwSetWindowTitle(win, (title = t).c_str());
    // The one frame policy (ui/frame_policy.hpp): poll while anything runs or after input, else wait.
    const ui::FrameWait w = ui::frame_wait(ui::frame_activity(s), frames_since_input, report.seconds_left());
    switch (w.kind) {
      case ui::FrameWaitKind::Poll: glfwPollEvents(); break;
      case ui::FrameWaitKind::Timeout: glfwWaitEventsTimeout(w.timeout_s); break;
      case ui::FrameWaitKind::Wait:
        // Until input; woken twice a second only to see SIGINT / SIGTERM (a signal does not end
        // GLFW's wait), drawing nothing then.
        do glfwWaitEventsTimeout(0.5);
        while (events.count == seen && !g_quit && !glfwWindowShouldClose(win));
        break;
    }
    if (events.count != seen) {
      seen = events.count;
      frames_since_input = 0;
    } else if (frames_since_input < ui::kSettleFrames) {
      ++frames_since_input;
    }
    const auto frame_start = clock::now();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    events.hold_presses(ImGui::GetIO());
    ImGui::NewFrame();
    // Runs keep wall-clock pace down to 4 frames per second (a slow projector laptop, a loaded
    // machine); a longer stall (a suspended process) advances them 0.25 s. The first frame after
    // a wait (nothing was running: e.g. the click on Run) advances one 60 Hz frame.
    s.frame_dt = w.kind == ui::FrameWaitKind::Poll
                     ? std::clamp(static_cast<double>(ImGui::GetIO().DeltaTime), 1e-4, 0.25)
                     : 1.0 / 60.0;
    ui::draw_frame(s);
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(win, &fw, &fh);
    gl.viewport(0, 0, fw, fh);
    gl.clear_color(0.95f, 0.95f, 0.96f, 1.0f);
    gl.clear(kColorBufferBit);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    const auto frame_end = clock::now();
    glfwSwapBuffers(win);
    ++frames;
    s.perf.frame_ms = std::max(1e-3, std::chrono::duration<double, std::milli>(frame_end - frame_start).count());
    if (frame_end >= fps_until) {  // frames drawn in the last wall second
      s.perf.fps = static_cast<int>(frames - fps_frames);
      fps_frames = frames;
      fps_until = frame_end + std::chrono::seconds(1);
    }
    report.maybe_write(s, frames);
    if (w.kind != ui::FrameWaitKind::Poll) {
      next = clock::now();  // a frame after a wait is drawn at once
      continue;
    }
    next += std::chrono::microseconds(16667);  // cap at 60 fps where vsync is absent (Xvfb)
    const auto now = clock::now();
    if (next > now)
      std::this_thread::sleep_until(next);
    else
      next = now;
  }
}
}  // namespace

std::string default_session_path() {
  if (const char* p = std::getenv("GMSLAB_SESSION"); p && *p) return p;
  if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x) return std::string(x) + "/gmslab/session.json";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : ".") + "/.config/gmslab/session.json";
}

int run_window(const std::string& session_path, const ui::LaunchRequest* launch) {
  glfwSetErrorCallback(glfw_error);
  if (!glfwInit()) return kNoWindow;
  // GL 3.2 core: the ImGui OpenGL3 backend then draws draw lists beyond 65536 vertices
  // (ImGuiBackendFlags_RendererHasVtxOffset), which long plotted traces need. GL 3.0 as fallback.
  const char* glsl = "#version 150";
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 2);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  const char* title = "gmslab - friction simulation (GMS)";
  GLFWwindow* win = glfwCreateWindow(1600, 1000, title, nullptr, nullptr);
  if (!win) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 0);
    glsl = "#version 130";
    win = glfwCreateWindow(1600, 1000, title, nullptr, nullptr);
  }
  if (!win) {
    glfwTerminate();
    return kNoWindow;
  }
  glfwMakeContextCurrent(win);
  glfwSwapInterval(1);
  Gl gl;
  if (!gl.load()) {
    glfwDestroyWindow(win);
    glfwTerminate();
    return kNoWindow;
  }
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  const ui::ScopedPlotContext plots;  // the window's plot view state
  ui::SetPlotPngWriter(png_via_headless);
  float sx = 1.0f, sy = 1.0f;
  glfwGetWindowContentScale(win, &sx, &sy);
  ui::setup_style(17.0f * std::max(1.0f, sy));
  // Installed before ImGui's, which chain to them.
  InputEvents events;
  events.install(win);
  ImGui_ImplGlfw_InitForOpenGL(win, true);
  ImGui_ImplOpenGL3_Init(glsl);
  if (!(ImGui::GetIO().BackendFlags & ImGuiBackendFlags_RendererHasVtxOffset))
    std::fprintf(stderr, "gmslab: OpenGL < 3.2: very long traces may not draw completely\n");

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  ui::AppState s;
  initial_state(s, session_path);
  initial_plant(s);
  if (launch) {
    try {
      ui::apply_launch(s, *launch);
    } catch (const std::exception& e) {
      s.report(ui::Panel::Simulation, e, "--open failed");
    }
  }
  loop(win, s, gl, events);
  save(s, session_path);

  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(win);
  glfwTerminate();
  return 0;
}

}  // namespace gmslab::app
