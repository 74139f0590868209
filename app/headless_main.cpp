// gmslab-headless: the commands that draw (render, figures) through OSMesa, with no display.
// `gmslab render ...` and `gmslab figures ...` forward here; every other command works too.
// Hidden: `gmslab-headless plot-figure FIGURE.json --out PNG [--size WxH]` draws any Figure saved
// as JSON (core/ident/figure_json.hpp); `gmslab identify --plot` uses it.
#include <cstring>
#include <iostream>
#include <string>

#include "app/cli/cli.hpp"
#include "app/headless.hpp"
#include "core/error.hpp"
#include "core/ident/figure_json.hpp"

namespace {

// plot-figure FIGURE.json --out PNG [--size WxH]; exit code 0, else 2 (bad input) or 1 (cannot
// write, no OSMesa) with one error line.
int plot_figure(int argc, char** argv) {
  std::string json, out, size = "1600x1000";
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--out" || a == "--size") && i + 1 < argc) (a == "--out" ? out : size) = argv[++i];
    else if (json.empty()) json = a;
  }
  try {
    if (json.empty() || out.empty())
      throw gmslab::InputError("usage: gmslab-headless plot-figure FIGURE.json --out PNG [--size WxH]");
    int w = 0, h = 0;
    gmslab::cli::parse_size(size, w, h);
    const gmslab::Figure f = gmslab::load_figure_json(json);
    gmslab::app::Offscreen off(w, h);
    const auto& rgba = off.render([&] { gmslab::app::draw_figure_window(f); });
    gmslab::app::write_png(out, w, h, rgba);
    return 0;
  } catch (const gmslab::Error& e) {  // the README's exit codes: 2 bad input, 1 cannot write
    std::cerr << "gmslab-headless: " << gmslab::error_label(e.kind()) << ": " << e.what() << '\n';
    return gmslab::exit_code(e.kind());
  } catch (const std::exception& e) {  // OSMesa unavailable, a bug
    std::cerr << "gmslab-headless: error: " << e.what() << '\n';
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "plot-figure") == 0) return plot_figure(argc, argv);
  gmslab::cli::Host host;
  host.render = gmslab::app::render_command;
  host.figures = gmslab::app::figures_command;
  return gmslab::cli::run(argc, argv, host);
}
