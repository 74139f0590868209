// The command line's commands as a user meets them: `render` with the default view draws the Plant
// view of an assembled preset and its title names the preset loaded (whatever the preset); an
// unknown command says so and lists the commands (exit 2); `sweep` is listed in the help.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"
#include "core/io/atomic_file.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {

struct Captured {
  int rc = 0;
  std::string out, err;
};

// The command line in this process (as gmslab-headless runs it), stdout and stderr captured.
Captured run_in_process(std::vector<std::string> args) {
  cli::Host host;
  host.render = [](const cli::RenderOptions&) { return 0; };
  host.figures = [](const cli::FiguresOptions&) { return 0; };
  cli::Cli c(host);
  args.insert(args.begin(), "gmslab");
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

fs::path tmp(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("gmslab_cli_commands_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d / name;
}

#ifdef GMSLAB_EXE
// Runs a shell command; stdout and stderr into files, returned with the exit code.
Captured run_exe(const std::string& cmd) {
  const auto o = tmp("out.txt"), e = tmp("err.txt");
  const int rc = std::system((cmd + " >" + o.string() + " 2>" + e.string()).c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, read_file(o.string()), read_file(e.string())};
}
#endif

std::string preset(const std::string& name) { return std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name; }

std::string preset_name(const std::string& file) {
  return nlohmann::json::parse(read_file(preset(file)))["name"].get<std::string>();
}

}  // namespace

TEST(CliCommands, UnknownCommandSaysSoAndListsTheCommands) {
  const Captured r = run_in_process({"foo", "x", "--bar", "-"});
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("gmslab: unknown command 'foo'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("commands: simulate, render, figures, design, cycles, identify, sweep"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("did you mean '-h'"), std::string::npos) << r.err;
  // A near miss still gets its suggestion, in the same one message.
  const Captured near = run_in_process({"simulat", "x.json"});
  EXPECT_EQ(near.rc, 2);
  EXPECT_NE(near.err.find("unknown command 'simulat'; did you mean 'simulate'?"), std::string::npos) << near.err;
#ifdef GMSLAB_EXE
  const Captured exe = run_exe(std::string(GMSLAB_EXE) + " foo x --bar -");
  EXPECT_EQ(exe.rc, 2);
  EXPECT_NE(exe.err.find("unknown command 'foo'"), std::string::npos) << exe.err;
#endif
}

TEST(CliCommands, HelpListsSweep) {
  const Captured r = run_in_process({"--help"});
  EXPECT_EQ(r.rc, 0);
  const std::string all = r.out + r.err;
  for (const char* cmd : {"simulate", "render", "figures", "design", "identify", "sweep"})
    EXPECT_NE(all.find(std::string("  ") + cmd), std::string::npos) << cmd << ":\n" << all;
  // Outside the gmslab executable (which hands sweep to Python) sweep says where it runs.
  const Captured s = run_in_process({"sweep", "spec.json"});
  EXPECT_EQ(s.rc, 2);
  EXPECT_NE(s.err.find("python3 -m gmslab.sweep"), std::string::npos) << s.err;
#ifdef GMSLAB_EXE
  const Captured exe = run_exe(std::string(GMSLAB_EXE) + " --help");
  EXPECT_EQ(exe.rc, 0);
  EXPECT_NE((exe.out + exe.err).find("  sweep"), std::string::npos) << exe.out;
#endif
}

#ifdef GMSLAB_EXE
// The default view of an assembled preset is its Plant view (exit 0, not 2), and the title of any
// rendered view names the preset loaded, not the window's default preset.
TEST(CliCommands, RenderAutoViewOfAssembledPresetIsPlantTitledWithIt) {
  const auto png = tmp("plant.png");
  const Captured r = run_exe(std::string(GMSLAB_EXE) + " render " + preset("two_mass_drive.json") + " --out " +
                             png.string() + " --size 640x400 --time 0.5");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("Plant view"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("title \"gmslab - " + preset_name("two_mass_drive.json") + "  (" + preset("two_mass_drive.json") + ")\""),
            std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(preset_name("fig4_stick_slip.json")), std::string::npos) << r.out;
  EXPECT_GT(fs::file_size(png), 1000u);
  for (const char* p : {"three_body_chain.json", "fig2a_presliding.json"}) {
    const Captured q = run_exe(std::string(GMSLAB_EXE) + " render " + preset(p) + " --out " + png.string() +
                               " --size 640x400 --time 0.2");
    ASSERT_EQ(q.rc, 0) << p << ": " << q.err;
    EXPECT_NE(q.out.find("title \"gmslab - " + preset_name(p)), std::string::npos) << p << ": " << q.out;
    EXPECT_EQ(q.out.find(preset_name("fig4_stick_slip.json")), std::string::npos) << p << ": " << q.out;
  }
  // The Design view of an assembled preset designs on that plant: its title names it too.
  const Captured design = run_exe(std::string(GMSLAB_EXE) + " render " + preset("two_mass_drive.json") + " --out " +
                                  png.string() + " --size 640x400 --view design --output x.load --wn 10");
  ASSERT_EQ(design.rc, 0) << design.err;
  EXPECT_NE(design.out.find("title \"gmslab - " + preset_name("two_mass_drive.json")), std::string::npos) << design.out;
  // SVG is the Simulation view's plots: not of an assembled preset (an error naming why, not fig4's plots).
  const Captured svg = run_exe(std::string(GMSLAB_EXE) + " render " + preset("two_mass_drive.json") + " --out " +
                               tmp("p.svg").string() + " --format svg");
  EXPECT_EQ(svg.rc, 2);
  EXPECT_NE(svg.err.find("--format svg draws the Simulation view's plots"), std::string::npos) << svg.err;
  EXPECT_FALSE(fs::exists(tmp("p.svg")));
  // An explicit view still decides: the Simulation view of an assembled preset is an error.
  EXPECT_EQ(run_exe(std::string(GMSLAB_EXE) + " render " + preset("two_mass_drive.json") + " --out " +
                    png.string() + " --view simulation")
                .rc,
            2);
  fs::remove_all(png.parent_path());
}
#endif
