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
#include <filesystem>
#include <thread>

#include <climits>
#include <sys/wait.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/ident/figure_json.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/session_io.hpp"
#include "ui/app.hpp"
#include "ui/app_files.hpp"
#include "ui/identify_panel.hpp"
#include "ui/plot.hpp"
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

void save(const ui::AppState& s, const std::string& path) {
  if (!s.main.sim) return;
  try {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    save_session(ui::make_session(s), path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gmslab: session not saved: %s\n", e.what());
  }
}

void loop(GLFWwindow* win, ui::AppState& s, const Gl& gl) {
  using clock = std::chrono::steady_clock;
  auto next = clock::now();
  s.keys = {GLFW_KEY_S, GLFW_KEY_F5};
  std::string title;
  while (!glfwWindowShouldClose(win) && !g_quit) {
    if (std::string t = ui::window_title(s); t != title) glfwSetWindowTitle(win, (title = t).c_str());
    // Idle: wait for input instead of spinning; running: one frame per 1/60 s.
    // Idle: sleep until input (a blinking text cursor or a background identification wakes it
    // 4 times a second, nothing else does); running: one frame per 1/60 s.
    if (s.running)
      glfwPollEvents();
    else
      glfwWaitEventsTimeout(ImGui::GetIO().WantTextInput || ui::identify_busy(s.identify) ? 0.25 : 5.0);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    s.frame_dt = std::clamp(static_cast<double>(ImGui::GetIO().DeltaTime), 1e-4, 0.1);
    ui::draw_frame(s);
    ImGui::Render();
    int w = 0, h = 0;
    glfwGetFramebufferSize(win, &w, &h);
    gl.viewport(0, 0, w, h);
    gl.clear_color(0.95f, 0.95f, 0.96f, 1.0f);
    gl.clear(kColorBufferBit);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(win);
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

int run_window(const std::string& session_path) {
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
  ImGui_ImplGlfw_InitForOpenGL(win, true);
  ImGui_ImplOpenGL3_Init(glsl);
  if (!(ImGui::GetIO().BackendFlags & ImGuiBackendFlags_RendererHasVtxOffset))
    std::fprintf(stderr, "gmslab: OpenGL < 3.2: very long traces may not draw completely\n");

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  ui::AppState s;
  initial_state(s, session_path);
  loop(win, s, gl);
  save(s, session_path);

  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(win);
  glfwTerminate();
  return 0;
}

}  // namespace gmslab::app
