#include "app/cli/cli.hpp"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <utility>

#include "core/error.hpp"

namespace gmslab::cli {

void add_render_options(CLI::App& sub, RenderOptions& o) {
  sub.add_option("preset", o.preset, "Scenario preset (JSON)")->required();
  sub.add_option("--out,-o", o.out, "PNG file to write")->required();
  sub.add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub.add_option("--view", o.view, "View to draw: auto, simulation, design, identify, plant")
      ->capture_default_str();
  sub.add_option("--time", o.time, "Simulated time to show [s] (default: the whole run)");
  sub.add_option("--data", o.data,
                 "Identify view: training CSV to identify before drawing (the panel's 'Identify')");
  sub.add_option("--validate", o.validate, "Identify view: validation CSV (default: a hold-out part)");
  sub.add_option("--mask-edges", o.mask_edges, "Identify view: COLUMN:BEFORE:AFTER [s] windows to ignore")
      ->capture_default_str();
  sub.add_flag("--compare", o.compare, "Identify view: also fit and compare every model (slower)");
  sub.add_flag("--no-run", o.no_run, "Identify view: load and show the records of --data without identifying");
}

void add_figures_options(CLI::App& sub, FiguresOptions& o) {
  sub.add_option("--out,-o", o.out, "Folder for the PNG figures and their CSV series")
      ->capture_default_str();
  sub.add_option("--only", o.only, "Comma-separated figure ids (default: all)");
  sub.add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
}

void parse_size(const std::string& text, int& w, int& h) {
  char x = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w < 64 || h < 64 || w > 8192 || h > 8192)
    throw InputError("--size '" + text +
                     "': expected WIDTHxHEIGHT with each side from 64 to 8192 pixels, e.g. 1600x1000");
}

Cli::Cli(Host host)
    : host_(std::move(host)),
      app_("gmslab: friction simulation and compensation around the Generalized Maxwell-Slip model.\n"
           "With no command, opens the window (or, with no display, renders the figure set).") {
  app_.set_version_flag("--version", "gmslab 0.1.0");
  app_.require_subcommand(0, 1);

  register_simulate(app_, action_);

  auto* r = app_.add_subcommand("render", "Render the app's view of a scenario to PNG (headless)");
  add_render_options(*r, render_);
  r->preparse_callback([this](std::size_t) { render_ = RenderOptions{}; });
  r->callback([this] { action_ = [this] { return host_.render(render_); }; });

  auto* f = app_.add_subcommand("figures", "Render the paper's figure set to PNG + CSV (headless)");
  add_figures_options(*f, figures_);
  f->preparse_callback([this](std::size_t) { figures_ = FiguresOptions{}; });
  f->callback([this] { action_ = [this] { return host_.figures(figures_); }; });

  register_design(app_, action_);
  register_identify(app_, action_);
}

namespace {
// CLI11 2.1.2's App::clear() (called by every parse after the first) keeps parse_order(), so each
// parse of a reused app appends to it for ever: 8 bytes per parsed option and call, ~1 GB over
// the 10^7 inputs of a fuzz run (CLIUtils/CLI11#1216, fixed upstream by #1218 in clear()). This
// does what that fix does, for the app and every subcommand. parse_order_ is protected: a member
// pointer named through a derived class reaches it on any App.
struct ParseOrder : CLI::App {
  static void clear(CLI::App& app) {
    (app.*(&ParseOrder::parse_order_)).clear();
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) clear(*sub);
  }
};
}  // namespace

int Cli::run(int argc, char** argv) {
  action_ = nullptr;
  ParseOrder::clear(app_);
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help / version, exit 0); any other parse failure is bad
    // input: exit 2, as the README says (CLI11's own codes, e.g. 109 for an unknown option, are not).
    return app_.exit(e) == 0 ? 0 : exit_code(ErrorKind::Input);
  }
  try {
    if (!action_) {
      if (host_.window) return host_.window();
      std::cerr << app_.help();
      return 2;
    }
    return action_();
  } catch (const Error& e) {  // typed: the kind decides the exit code (README)
    std::cerr << "gmslab: " << error_label(e.kind()) << ": " << e.what() << '\n';
    return exit_code(e.kind());
  } catch (const std::filesystem::filesystem_error& e) {  // a folder that cannot be created
    std::cerr << "gmslab: " << error_label(ErrorKind::Io) << ": " << e.what() << '\n';
    return exit_code(ErrorKind::Io);
  } catch (const std::exception& e) {  // not a typed error: a bug
    std::cerr << "gmslab: " << error_label(ErrorKind::Internal) << ": " << e.what() << '\n';
    return exit_code(ErrorKind::Internal);
  }
}

int run(int argc, char** argv, const Host& host) {
  Cli cli(host);
  return cli.run(argc, argv);
}

}  // namespace gmslab::cli
