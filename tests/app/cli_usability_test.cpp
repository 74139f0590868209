// The command line as a user meets it: every mistyped option of every command (one random edit,
// fixed seed) exits 2 and suggests the option meant; help names the program "gmslab" whichever
// executable runs it; `gmslab design --json -` has the same keys with and without --K.
#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli/cli.hpp"

using namespace gmslab;

namespace {
struct Captured {
  int rc = 0;
  std::string out, err;
};

Captured run(std::vector<std::string> args) {
  cli::Host host;
  host.render = [](const cli::RenderOptions&) { return 0; };
  host.figures = [](const cli::FiguresOptions&) { return 0; };
  host.window = [](const cli::WindowOptions&) { return 0; };
  cli::Cli c(host);
  args.insert(args.begin(), "gmslab-headless");  // as the sibling executable is called
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  std::ostringstream out, err;
  auto* o = std::cout.rdbuf(out.rdbuf());
  auto* e = std::cerr.rdbuf(err.rdbuf());
  const int rc = c.run(static_cast<int>(argv.size()), argv.data());
  std::cout.rdbuf(o);
  std::cerr.rdbuf(e);
  return {rc, out.str(), err.str()};
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j)
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
  return d[a.size()][b.size()];
}

std::string mutate(const std::string& w, std::mt19937& rng) {
  std::string m = w;
  const std::size_t pos = 2 + rng() % (w.size() - 2);  // keep the leading "--"
  switch (rng() % 3) {
    case 0: m.insert(pos, 1, static_cast<char>('a' + rng() % 26)); break;
    case 1: m.erase(pos, 1); break;
    default: m[pos] = static_cast<char>('a' + rng() % 26); break;
  }
  return m;
}
}  // namespace

TEST(CliUsability, MistypedOptionsExit2AndSuggestTheOptionMeant) {
  cli::Host host;
  cli::Cli c(host);
  std::mt19937 rng(1515);
  int checked = 0;
  for (const CLI::App* sub : c.app().get_subcommands([](const CLI::App*) { return true; })) {
    std::vector<std::string> names;
    for (const CLI::Option* o : sub->get_options())
      for (const auto& l : o->get_lnames()) names.push_back("--" + l);
    for (const auto& name : names) {
      if (name.size() < 5 || name == "--help") continue;
      const std::string typo = mutate(name, rng);
      // Only unambiguous typos: the option meant is strictly the closest.
      bool unique = typo != name;
      for (const auto& other : names)
        if (other != name && edit_distance(typo, other) <= edit_distance(typo, name)) unique = false;
      if (!unique) continue;
      const Captured r = run({sub->get_name(), typo});
      EXPECT_EQ(r.rc, 2) << sub->get_name() << ' ' << typo;
      EXPECT_NE(r.err.find("did you mean '" + name + "'"), std::string::npos)
          << sub->get_name() << ' ' << typo << ":\n" << r.err;
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
  // A mistyped command, and a missing required option.
  const Captured cmd = run({"figurs"});
  EXPECT_EQ(cmd.rc, 2);
  EXPECT_NE(cmd.err.find("did you mean 'figures'"), std::string::npos) << cmd.err;
  EXPECT_EQ(run({"render", "x.json"}).rc, 2);  // --out missing
}

TEST(CliUsability, HelpNamesTheProgramGmslab) {
  for (const char* sub : {"render", "figures", "design", "identify", "simulate"}) {
    const Captured r = run({sub, "--help"});
    EXPECT_EQ(r.rc, 0);
    const std::string all = r.out + r.err;
    EXPECT_NE(all.find(std::string("Usage: gmslab ") + sub), std::string::npos) << all.substr(0, 200);
    EXPECT_EQ(all.find("Usage: gmslab-headless"), std::string::npos) << all.substr(0, 200);
  }
}

TEST(CliUsability, DesignJsonHasOneShape) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 4; ++trial) {
    const double wn = std::uniform_real_distribution<double>(2.0, 20.0)(rng);
    const std::vector<std::string> base = {"design", "--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn",
                                           std::to_string(wn), "--json", "-"};
    const Captured a = run(base);
    ASSERT_EQ(a.rc, 0) << a.err;
    // A reachable K: half the largest one the first run reports.
    const double kmax = nlohmann::json::parse(a.out.substr(a.out.find('{')))["K_max"].get<double>();
    std::vector<std::string> with_k = base;
    with_k.insert(with_k.end(), {"--K", std::to_string(0.5 * kmax)});
    const Captured b = run(with_k);
    ASSERT_EQ(b.rc, 0) << b.err;
    const auto ja = nlohmann::json::parse(a.out.substr(a.out.find('{'))), jb = nlohmann::json::parse(b.out.substr(b.out.find('{')));
    std::set<std::string> ka, kb;
    for (auto it = ja.begin(); it != ja.end(); ++it) ka.insert(it.key());
    for (auto it = jb.begin(); it != jb.end(); ++it) kb.insert(it.key());
    kb.erase("K_requested");
    EXPECT_EQ(ka, kb);
    for (const char* k : {"dominant", "notes", "ratio"}) {
      ASSERT_TRUE(ja.contains(k)) << k;
      EXPECT_TRUE(ja[k].is_null()) << k;
      EXPECT_FALSE(jb[k].is_null()) << k;
    }
  }
}
