// gmslab: the window, and every command line command.
//   gmslab                   opens the window (no display: renders the figure set to ./figures)
//   gmslab --open PRESET [--tab TAB] [--run]   opens the window on PRESET (a display is needed)
//   gmslab render|figures    run in the sibling executable gmslab-headless (OSMesa)
//   gmslab sweep SPEC.json   runs python3 -m gmslab.sweep (Dask; app/python/gmslab/sweep.py)
//   gmslab <other command>   app/cli (simulate, design, identify, ...)
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"
#include "app/window.hpp"
#include "core/error.hpp"
#include "ui/app.hpp"

namespace {

// gmslab-headless next to this executable (/proc/self/exe), else on PATH.
std::string headless_path() {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n > 0) {
    std::string self(buf, static_cast<std::size_t>(n));
    const auto slash = self.rfind('/');
    const std::string sibling = self.substr(0, slash + 1) + "gmslab-headless";
    if (access(sibling.c_str(), X_OK) == 0) return sibling;
  }
  return "gmslab-headless";
}

// Replaces this process with gmslab-headless ARGS; returns only on failure.
int exec_headless(std::vector<std::string> args) {
  const std::string exe = headless_path();
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(exe.c_str()));
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  if (exe.find('/') != std::string::npos)
    execv(exe.c_str(), argv.data());
  else
    execvp(exe.c_str(), argv.data());
  std::fprintf(stderr, "gmslab: cannot run %s: %s (build the gmslab-headless target)\n", exe.c_str(),
               std::strerror(errno));
  return gmslab::cli::kExitCannotStart;
}

#ifndef GMSLAB_PYTHON_FROM_BIN
#define GMSLAB_PYTHON_FROM_BIN "../lib/python3/dist-packages"
#endif

// Replaces this process with python3 -m gmslab.sweep ARGS, the package this executable belongs to
// put first on PYTHONPATH: build/python next to it in a build tree, else the installed package
// (GMSLAB_PYTHON_FROM_BIN: relative to the executable's folder, so any install prefix works).
// Returns only on failure.
int exec_sweep(int argc, char** argv) {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n > 0) {
    const std::string self(buf, static_cast<std::size_t>(n));
    const std::string bin = self.substr(0, self.rfind('/') + 1);
    const std::string rel = GMSLAB_PYTHON_FROM_BIN;
    for (const std::string& dir : {bin + "python", rel.starts_with('/') ? rel : bin + rel}) {
      if (access((dir + "/gmslab/sweep.py").c_str(), R_OK) != 0) continue;
      const char* old = std::getenv("PYTHONPATH");
      setenv("PYTHONPATH", (old && *old ? dir + ":" + old : dir).c_str(), 1);
      break;
    }
  }
  // The Debian interpreter (python3-distributed, python3-numpy) before any other python3 on PATH.
  const std::string py = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  std::vector<std::string> args = {py, "-m", "gmslab.sweep"};
  args.insert(args.end(), argv + 2, argv + argc);
  std::vector<char*> av;
  for (auto& a : args) av.push_back(a.data());
  av.push_back(nullptr);
  std::fflush(nullptr);
  execvp(py.c_str(), av.data());
  std::fprintf(stderr, "gmslab sweep: cannot run python3: %s (Debian: python3-distributed)\n", std::strerror(errno));
  return gmslab::cli::kExitCannotStart;
}

bool has_display() {
  const char* x = std::getenv("DISPLAY");
  const char* w = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (w && *w);
}

int figures_fallback() {
  std::fprintf(stderr,
               "gmslab: no display; rendering the figure set headlessly into ./figures instead "
               "(gmslab figures --out figures)\n");
  return exec_headless({"figures", "--out", "figures"});
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && (std::strcmp(argv[1], "render") == 0 || std::strcmp(argv[1], "figures") == 0))
    return exec_headless(std::vector<std::string>(argv + 1, argv + argc));
  if (argc >= 2 && std::strcmp(argv[1], "sweep") == 0) return exec_sweep(argc, argv);

  std::vector<std::string> forward(argv + 1, argv + argc);
  gmslab::cli::Host host;
  host.render = [&](const gmslab::cli::RenderOptions&) { return exec_headless(forward); };
  host.figures = [&](const gmslab::cli::FiguresOptions&) { return exec_headless(forward); };
  host.window = [](const gmslab::cli::WindowOptions& o) {
    if (o.open.empty()) {
      if (!has_display()) return figures_fallback();
      const int rc = gmslab::app::run_window(gmslab::app::default_session_path());
      return rc == gmslab::app::kNoWindow ? figures_fallback() : rc;
    }
    // --open: checked before any window (a bad preset or tab: exit 2 with the reason).
    const gmslab::ui::LaunchRequest launch = gmslab::ui::check_launch({o.open, o.tab, o.run});
    const char* no_window =
        "--open needs a display (DISPLAY or WAYLAND_DISPLAY) to open the window; for an image of the view use "
        "gmslab render PRESET --view TAB --out FILE.png";
    if (!has_display()) throw gmslab::IoError(no_window);
    const int rc = gmslab::app::run_window(gmslab::app::default_session_path(), &launch);
    if (rc == gmslab::app::kNoWindow) throw gmslab::IoError(no_window);
    return rc;
  };
  return gmslab::cli::run(argc, argv, host);
}
