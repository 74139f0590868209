// The CLI as a test calls it: gmslab::cli::run on "gmslab" followed by args (exit code).
#pragma once

#include <string>
#include <vector>

#include "app/cli/cli.hpp"

namespace gmslab::test_util {

inline int run_cli(std::vector<std::string> args) {
  args.insert(args.begin(), "gmslab");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  return gmslab::cli::run(static_cast<int>(argv.size()), argv.data(), {});
}

}  // namespace gmslab::test_util
