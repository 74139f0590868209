// One gmslab::cli::Cli run many times (as the fuzz harness does) must behave exactly as a fresh
// command line per call: same exit code, same output, options of one call never seen by the next.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"
#include "hardening_util.hpp"

namespace gmslab::hardening {
namespace {

struct Outcome {
  int rc = 0;
  std::string out, err;
  bool operator==(const Outcome&) const = default;
};

std::vector<char*> argv_of(std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  return argv;
}

Outcome run_on(cli::Cli& c, std::vector<std::string> args) {
  args.insert(args.begin(), "gmslab");
  auto argv = argv_of(args);
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  Outcome o;
  o.rc = c.run(static_cast<int>(args.size()), argv.data());
  o.out = ::testing::internal::GetCapturedStdout();
  o.err = ::testing::internal::GetCapturedStderr();
  return o;
}

// The reference: a fresh Cli (the commands keep their options in the app, no statics).
Outcome run_fresh(std::vector<std::string> args, const cli::Host& host = {}) {
  cli::Cli c(host);
  return run_on(c, std::move(args));
}

// Plant G = 4 / (s (s + 2)) of the design worked example; `extra` adds options.
std::vector<std::string> design_args(std::vector<std::string> extra) {
  std::vector<std::string> a = {"design", "--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4",
                                "--json", "-"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

TEST(CliReparse, DesignOptionsOfOneCallDoNotLeakIntoTheNext) {
  cli::Cli c({});
  const Outcome with_k = run_on(c, design_args({"--K", "5", "--max-ratio", "10", "--margin", "0.3"}));
  ASSERT_EQ(with_k.rc, 0) << with_k.err;
  const Outcome reused = run_on(c, design_args({}));
  const Outcome fresh = run_fresh(design_args({}));
  ASSERT_EQ(fresh.rc, 0) << fresh.err;
  EXPECT_EQ(reused, fresh);
  // The options change the design, so a leak would show.
  const auto a = nlohmann::json::parse(with_k.out), b = nlohmann::json::parse(fresh.out);
  EXPECT_EQ(a["max_ratio"], 10.0);
  EXPECT_EQ(b["max_ratio"], 20.0);
  EXPECT_NE(a["K"], b["K"]);
}

TEST(CliReparse, RenderAndFiguresOptionsReturnToTheirDefaults) {
  std::optional<cli::RenderOptions> render;
  std::optional<cli::FiguresOptions> figures;
  cli::Host host;
  host.render = [&](const cli::RenderOptions& o) { return render = o, 0; };
  host.figures = [&](const cli::FiguresOptions& o) { return figures = o, 0; };
  cli::Cli c(host);
  ASSERT_EQ(run_on(c, {"render", "p.json", "-o", "a.png", "--size", "800x600", "--view", "design",
                       "--time", "2"}).rc, 0);
  EXPECT_EQ(render->size, "800x600");
  EXPECT_EQ(render->time, 2.0);
  ASSERT_EQ(run_on(c, {"render", "q.json", "-o", "b.png"}).rc, 0);
  const cli::RenderOptions def;
  EXPECT_EQ(render->preset, "q.json");
  EXPECT_EQ(render->out, "b.png");
  EXPECT_EQ(render->size, def.size);
  EXPECT_EQ(render->view, def.view);
  EXPECT_EQ(render->time, def.time);

  ASSERT_EQ(run_on(c, {"figures", "--out", "f", "--only", "fig4", "--size", "640x480"}).rc, 0);
  EXPECT_EQ(figures->only, "fig4");
  ASSERT_EQ(run_on(c, {"figures"}).rc, 0);
  const cli::FiguresOptions fdef;
  EXPECT_EQ(figures->out, fdef.out);
  EXPECT_EQ(figures->only, fdef.only);
  EXPECT_EQ(figures->size, fdef.size);
}

// CLI11 2.1.2 keeps parse_order() across parses (CLIUtils/CLI11#1216): a reused Cli grew by
// 8 bytes per parsed option and call (cli_fuzz's memory climbed past 300 MB in 3.5e6 inputs).
TEST(CliReparse, MemoryOfOneCallIsNotKeptByTheNext) {
  cli::Cli c({});
  const auto args = design_args({"--K", "5"});
  std::size_t after_one = 0;
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(run_on(c, args).rc, 0);
    const auto& order = c.app().get_subcommand("design")->parse_order();
    if (i == 0) after_one = order.size();
    ASSERT_EQ(order.size(), after_one) << "after call " << i + 1;
  }
  EXPECT_EQ(after_one, 6u);  // --num --den --zeta --wn --json --K
}

// A mixed sequence on one Cli (errors, help, version, each command, parse failures half-way)
// gives every call the outcome a fresh Cli gives it.
TEST(CliReparse, EveryCallInAMixedSequenceMatchesAFreshCommandLine) {
  const std::string csv = temp_file("reparse_bad.csv");
  write_file_atomic(csv, "t_s,x_m,F_N\n0,0,1\n0.1,0,abc\n");
  const std::string missing = temp_file("missing.json");
  const std::string report = temp_file("reparse_report.json");
  const std::vector<std::vector<std::string>> calls = {
      design_args({"--K", "5"}),
      {"--version"},
      {"design", "--zeta"},  // missing value: parse error after the subcommand was entered
      design_args({}),
      {"simulate", missing, "--out", "-"},
      {"--help"},
      {"identify", "--data", csv, "--report", report, "--method", "sbplx", "--holdout", "0.4"},
      {"identify", "--data", csv, "--report", report},
      {"identify", "--data", csv, "--report", report, "--elements", "99"},
      {"design", "--help"},
      {"frobnicate", "--zz"},
      {"render", "p.json", "-o", "a.png", "--size", "10x99999"},
      {"simulate"},
      {},
      design_args({"--simulate"}),
      {"design", "--num", "4 x", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4"},
      design_args({"--max-ratio", "0.5"}),
      design_args({}),
  };
  cli::Host host;
  host.render = [](const cli::RenderOptions& o) {
    int w = 0, h = 0;
    cli::parse_size(o.size, w, h);
    return 0;
  };
  cli::Cli reused(host);
  for (const auto& call : calls) {
    std::string line;
    for (const auto& a : call) line += a + ' ';
    const Outcome fresh = run_fresh(call, host);
    const Outcome again = run_on(reused, call);
    EXPECT_EQ(again.rc, fresh.rc) << line;
    EXPECT_EQ(again.out, fresh.out) << line;
    EXPECT_EQ(again.err, fresh.err) << line;
  }
}

}  // namespace
}  // namespace gmslab::hardening
