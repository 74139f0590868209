// gmslab-headless: the commands that draw (render, figures) through OSMesa, with no display.
// `gmslab render ...` and `gmslab figures ...` forward here; every other command works too.
#include "app/cli/cli.hpp"
#include "app/headless.hpp"

int main(int argc, char** argv) {
  gmslab::cli::Host host;
  host.render = gmslab::app::render_command;
  host.figures = gmslab::app::figures_command;
  return gmslab::cli::run(argc, argv, host);
}
