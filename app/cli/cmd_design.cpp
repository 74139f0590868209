// gmslab design: placeholder registration; the design issue replaces this file with the real command.
#include "app/cli/cli.hpp"
#include "core/error.hpp"

namespace gmslab::cli {

void register_design(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand("design", "(not available yet in this build)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] () -> int { throw InputError("'gmslab design' is not available in this build yet"); };
  });
}

}  // namespace gmslab::cli
