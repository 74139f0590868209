// gmslab identify: placeholder registration; the identify issue replaces this file with the real command.
#include "app/cli/cli.hpp"
#include "core/error.hpp"

namespace gmslab::cli {

void register_identify(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand("identify", "(not available yet in this build)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] () -> int { throw InputError("'gmslab identify' is not available in this build yet"); };
  });
}

}  // namespace gmslab::cli
