#include "app/cli/cli.hpp"

#include <cstdio>
#include <iostream>

#include "core/error.hpp"

namespace gmslab::cli {

void add_render_options(CLI::App& sub, RenderOptions& o) {
  sub.add_option("preset", o.preset, "Scenario preset (JSON)")->required();
  sub.add_option("--out,-o", o.out, "PNG file to write")->required();
  sub.add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub.add_option("--view", o.view, "View to draw: auto, simulation, design, identify")
      ->capture_default_str();
  sub.add_option("--time", o.time, "Simulated time to show [s] (default: the whole run)");
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

int run(int argc, char** argv, const Host& host) {
  CLI::App app{
      "gmslab: friction simulation and compensation around the Generalized Maxwell-Slip model.\n"
      "With no command, opens the window (or, with no display, renders the figure set)."};
  app.set_version_flag("--version", "gmslab 0.1.0");
  app.require_subcommand(0, 1);
  Action action;

  register_simulate(app, action);

  RenderOptions render;
  auto* r = app.add_subcommand("render", "Render the app's view of a scenario to PNG (headless)");
  add_render_options(*r, render);
  r->callback([&] { action = [&] { return host.render(render); }; });

  FiguresOptions figures;
  auto* f = app.add_subcommand("figures", "Render the paper's figure set to PNG + CSV (headless)");
  add_figures_options(*f, figures);
  f->callback([&] { action = [&] { return host.figures(figures); }; });

  register_design(app, action);
  register_identify(app, action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (!action) {
      if (host.window) return host.window();
      std::cerr << app.help();
      return 2;
    }
    return action();
  } catch (const InputError& e) {
    std::cerr << "gmslab: error: " << e.what() << '\n';
    return 2;
  } catch (const SimulationError& e) {
    std::cerr << "gmslab: simulation stopped: " << e.what() << '\n';
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "gmslab: error: " << e.what() << '\n';
    return 1;
  }
}

}  // namespace gmslab::cli
