// libFuzzer target: the command-line parser, gmslab::cli::Cli::run, with argv built from the input
// (one argument per line, at most 24).
//
// One Cli is built at start-up and reparses every input, as it supports (cli.hpp): building the
// CLI11 app with its ~60 options cost ~0.3 ms per input, most of the time of the old harness.
// A reused Cli must behave as a fresh one, which CliReparse.* tests (tests/hardening/).
//
// Harmless by construction: run() works in a private temporary folder that is emptied after
// every input, arguments containing '/' are dropped (no paths outside that folder), the window,
// render and figures commands are stubs (render/figures only check --size), so the only files a
// command can open are ones it wrote itself in the same call (GMSLAB_PRESETS is that folder too, so
// a bare preset name finds no shipped preset). run() must return an exit code and never throw or
// crash.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"

namespace {
std::filesystem::path g_dir;
std::filesystem::path g_home;  // libFuzzer's own working folder (corpus paths are relative to it)
std::ostringstream g_sink;

int size_only(const std::string& size) {
  int w = 0, h = 0;
  gmslab::cli::parse_size(size, w, h);
  return 0;
}

gmslab::cli::Cli& cli() {
  static gmslab::cli::Cli c{gmslab::cli::Host{
      [](const gmslab::cli::RenderOptions& o) { return size_only(o.size); },
      [](const gmslab::cli::FiguresOptions& o) { return size_only(o.size); },
      [](const gmslab::cli::WindowOptions&) { return 0; }}};
  return c;
}

void remove_dir() {
  std::error_code ec;
  std::filesystem::remove_all(g_dir, ec);
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char tmpl[] = "/tmp/gmslab-cli-fuzz-XXXXXX";
  if (!::mkdtemp(tmpl)) std::abort();
  g_dir = tmpl;
  ::setenv("GMSLAB_PRESETS", tmpl, 1);  // bare preset names: looked up in the private folder only
  g_home = std::filesystem::current_path();
  std::atexit(remove_dir);
  std::cout.rdbuf(g_sink.rdbuf());  // help and error texts: not interesting here
  std::cerr.rdbuf(g_sink.rdbuf());
  cli();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"gmslab"};
  std::string cur;
  for (std::size_t i = 0; i <= size; ++i) {
    if (i == size || data[i] == '\n') {
      args.push_back(cur);
      cur.clear();
      if (args.size() > 25) break;
    } else {
      cur.push_back(static_cast<char>(data[i]));
    }
  }
  for (const auto& a : args)
    if (a.find('/') != std::string::npos) return 0;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  std::filesystem::current_path(g_dir);
  const int rc = cli().run(static_cast<int>(args.size()), argv.data());
  if (rc < 0 || rc > 255) __builtin_trap();
  g_sink.str("");
  for (const auto& e : std::filesystem::directory_iterator(g_dir))
    std::filesystem::remove_all(e.path());
  std::filesystem::current_path(g_home);
  return 0;
}
