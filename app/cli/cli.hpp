// gmslab command line: one CLI11 app, one file per command (app/cli/cmd_*.cpp).
//
// Commands that need GL (render, figures) run in gmslab-headless (OSMesa); `gmslab` forwards them
// there through Host, so both executables print the same help and accept the same options.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace gmslab::cli {

// The exit code when the program a command is handed to cannot be started: gmslab-headless
// (render, figures) or python3 (sweep), as a shell reports a command it cannot find (README).
inline constexpr int kExitCannotStart = 127;

struct RenderOptions {
  std::string preset;              // scenario JSON
  std::string out;                 // PNG path
  std::string size = "1600x1000";  // WIDTHxHEIGHT in pixels
  std::string view = "auto";       // which view to draw (auto: what the preset is for)
  double time = -1.0;              // simulated time to show [s]; < 0: the whole run
  // Identify view: run an identification first and show its outcome.
  std::string data, validate, mask_edges = "pulse_code:0.005:0.060";
  bool no_run = false;   // only load and show the records
  bool compare = false;  // also compare every model
  std::string format = "png";  // png, or svg: the Simulation view's plots as a vector figure
  // Design view: the plant source (core/control/design_plant.hpp). An assembled preset (schema 2)
  // designs from `drive` to `output` ("" = the first drive, its body); num / den: a typed plant.
  std::string drive, output, num, den;
  double zeta = 0.0, wn = 0.0;  // design view: desired dominant roots (0: the Design tab's defaults)
  std::string compensator;      // design view: lead | lag | lead_lag | pi | pid ("": the tab's own)
  double K = 0.0;               // design view: target error constant (0: none, the usable maximum)
  double sample_time = 0.0;    // Design view: controller sample time [s] (0: continuous)
  // Design view: loop reference (step | ramp | sine), compensation (coulomb | gms) and what drives it
  // (reference | measured velocity); "": the tab's own.
  std::string design_reference, compensation, feedforward;
  std::string manual;  // design view: a manual compensator "Kc z p [z2 p2]" (as if dragged); "": the design's
};

struct FiguresOptions {
  std::string out = "figures";  // folder for PNG + CSV
  std::string only;             // comma-separated figure ids; empty = all
  std::string size = "1400x900";
  std::string format = "png";  // png, svg or both (same figure data; CSV always)
};

void add_render_options(CLI::App& sub, RenderOptions& o);
void add_figures_options(CLI::App& sub, FiguresOptions& o);
// Parses "1600x1000"; throws InputError naming the option on bad input.
void parse_size(const std::string& text, int& w, int& h);

// The window's options (no command): gmslab [--open PRESET [--tab TAB] [--run]].
struct WindowOptions {
  std::string open;  // a preset to open ("": the restored session); a path or a shipped preset's name
  std::string tab;   // simulation | figures | design | identify | plant ("": the preset's own tab)
  bool run = false;  // start the run of that tab
};

struct Host {
  std::function<int(const RenderOptions&)> render;
  std::function<int(const FiguresOptions&)> figures;
  std::function<int(const WindowOptions&)> window;  // no command given
};

// The action a command registers; run() calls it after a successful parse. A command keeps its
// option values in storage its callbacks own and resets them in its preparse_callback.
using Action = std::function<int()>;

void register_simulate(CLI::App& app, Action& action);
void register_design(CLI::App& app, Action& action);
void register_cycles(CLI::App& app, Action& action);
void register_identify(CLI::App& app, Action& action);

// The command line, built once: every command and option registered on one CLI11 app. run() may
// be called many times (the fuzz harness reparses one Cli per input instead of rebuilding ~60
// options): CLI11 clears its parse results at each parse, and every command resets its option
// values to their defaults when it is parsed (preparse_callback), so no call sees another's
// values. Each command's options live in the app (held by its callbacks), so two Cli objects are
// independent.
class Cli {
 public:
  explicit Cli(Host host);
  Cli(const Cli&) = delete;  // the app's callbacks point into this object
  Cli& operator=(const Cli&) = delete;

  // Parses argv, runs the command; returns the process exit code. Bad input prints one clear
  // error (file, line or key, what is accepted) and returns 2; never throws.
  int run(int argc, char** argv);

  const CLI::App& app() const { return app_; }  // for tests

  // The words a mistyped `word` may have meant: the options of the command being parsed when
  // it starts with '-', else the command names.
  std::vector<std::string> known_words(const std::string& word) const;
  // The command names, comma-separated, in help order.
  std::string command_list() const;

 private:
  Host host_;
  CLI::App app_;
  Action action_;
  RenderOptions render_;
  FiguresOptions figures_;
  WindowOptions window_;
};

// The closest of `known` to `word` (edit distance at most max(2, |word| / 3)), or "".
std::string suggest(const std::string& word, const std::vector<std::string>& known);

// One-shot form of Cli::run (what the executables call).
int run(int argc, char** argv, const Host& host);

}  // namespace gmslab::cli
