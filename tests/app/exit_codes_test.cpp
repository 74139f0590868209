// One error path: every command maps a typed failure to the README's exit code - 0 success,
// 2 bad input (InputError), 3 the simulation diverged (SimulationError), 130 cancelled (Cancelled),
// 127 a hand-over that cannot start, 1 any other failure (IoError: an output that cannot be written;
// internal errors). Run as a user runs them: the
// executables, with their exit status.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "app/cli/cli.hpp"
#include "core/error.hpp"
#include "core/friction/gms.hpp"
#include "core/ident/figure_json.hpp"
#include "core/ident/fit.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/ident/synthetic.hpp"

#if defined(GMSLAB_EXE) && defined(GMSLAB_HEADLESS_EXE)
using namespace gmslab;
namespace fs = std::filesystem;

namespace {
const std::string kExe = GMSLAB_EXE, kHeadless = GMSLAB_HEADLESS_EXE;
const std::string kPreset = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2a_presliding.json";
const std::string kMissingDir = "/nonexistent-gmslab-dir";  // outputs here cannot be written

struct Tmp {
  fs::path dir;
  Tmp() {
    std::string tmpl = (fs::temp_directory_path() / "gmslab-exit-XXXXXX").string();
    dir = ::mkdtemp(tmpl.data());
  }
  ~Tmp() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string operator()(const std::string& name) const { return (dir / name).string(); }
};

// Runs a shell command; its exit status, and its standard error in `err`.
int run(const std::string& cmd, std::string* err = nullptr) {
  const std::string log = (fs::temp_directory_path() / ("gmslab-exit-" + std::to_string(::getpid()) + ".log")).string();
  const int rc = std::system((cmd + " >/dev/null 2>" + log).c_str());
  if (err) {
    std::ifstream in(log);
    err->assign(std::istreambuf_iterator<char>(in), {});
  }
  fs::remove(log);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// A preset that loads and passes every check but diverges at t = 1.024 s (explicit damping
// beyond its limit: the energy watch stops it). Saved as `path`.
void write_diverging_preset(const std::string& path) {
  Scenario s;
  s.name = "diverges";
  s.friction = GmsParams::reference(false).to_params();
  s.plant = {1.0, 0.0, 2040.0};
  s.drive.kind = Drive::Kind::Force;
  s.drive.signal = Signal::sine(0.0, 10.0, 2.0);
  s.run = {1e-3, 10.0, 1};
  save_scenario(s, path);
}
}  // namespace

TEST(ExitCodes, ErrorKindsMapToTheReadmeCodes) {
  EXPECT_EQ(exit_code(InputError("x").kind()), 2);
  EXPECT_EQ(exit_code(ident::Cancelled().kind()), 130);
  EXPECT_EQ(exit_code(SimulationError("x").kind()), 3);
  EXPECT_EQ(exit_code(IoError("x").kind()), 1);
  EXPECT_EQ(exit_code(InternalError("x").kind()), 1);
  // An output that cannot be written is an IoError naming the path.
  try {
    write_file_atomic(kMissingDir + "/x.txt", "x");
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(kMissingDir + "/x.txt"), std::string::npos) << e.what();
  }
}

// Every kind's exit code, the hand-over's 127 and success are rows of the README's exit-code table,
// and the table has no other row; each kind is raised as itself (throw_error), a cancelled
// identification is an Error of kind Cancelled, an unknown model key an InputError.
TEST(ExitCodes, EveryCodeIsARowOfTheReadmeTable) {
  const std::vector<ErrorKind> kinds = {ErrorKind::Input, ErrorKind::Simulation, ErrorKind::Io, ErrorKind::Internal,
                                        ErrorKind::Cancelled};
  std::ifstream in(std::string(GMSLAB_SOURCE_DIR) + "/README.md");
  std::stringstream text;
  text << in.rdbuf();
  std::set<int> rows;
  const std::string readme = text.str();
  const std::regex row(R"(\n\| (\d+) \| )");
  for (auto it = std::sregex_iterator(readme.begin(), readme.end(), row); it != std::sregex_iterator(); ++it)
    rows.insert(std::stoi((*it)[1].str()));
  std::set<int> codes = {0, cli::kExitCannotStart};
  for (ErrorKind k : kinds) codes.insert(exit_code(k));
  EXPECT_EQ(rows, codes);
  EXPECT_EQ(exit_code(ErrorKind::Cancelled), 130);
  for (ErrorKind k : kinds) {
    try {
      throw_error(k, "what");
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), k);
      EXPECT_STREQ(e.what(), "what");
    }
  }
  try {
    throw ident::Cancelled();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Cancelled);
    EXPECT_EQ(exit_code(e.kind()), 130);
  }
  try {
    (void)GmsParams::reference(false).to_params().scalar("no_such_key");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'no_such_key'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Fs"), std::string::npos) << e.what();  // the keys it has
  }
}

// gmslab hands render / figures to gmslab-headless and sweep to python3: when the program cannot be
// started (here a copy of gmslab alone in a folder, with an empty PATH) it exits 127 and says so.
TEST(ExitCodes, AHandOverThatCannotStartIs127) {
  Tmp t;
  fs::copy_file(kExe, t("gmslab"));
  fs::permissions(t("gmslab"), fs::perms::owner_all);
  std::string err;
  EXPECT_EQ(run("env PATH=" + t("empty") + " " + t("gmslab") + " render " + kPreset + " --out " + t("a.png"), &err),
            cli::kExitCannotStart);
  EXPECT_NE(err.find("cannot run gmslab-headless"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(t("a.png")));
}

TEST(ExitCodes, Simulate) {
  Tmp t;
  std::string err;
  EXPECT_EQ(run(kExe + " simulate " + kPreset + " --out " + t("a.csv")), 0);
  EXPECT_TRUE(fs::exists(t("a.csv")));
  EXPECT_EQ(run(kExe + " simulate " + t("missing.json") + " --out " + t("b.csv"), &err), 2);
  EXPECT_NE(err.find(t("missing.json")), std::string::npos) << err;
  EXPECT_EQ(run(kExe + " simulate " + kPreset + " --bogus --out " + t("b.csv")), 2);  // bad option
  write_diverging_preset(t("div.json"));
  EXPECT_EQ(run(kExe + " simulate " + t("div.json") + " --out " + t("div.csv"), &err), 3);
  EXPECT_NE(err.find("simulation stopped: simulation diverged at t = 1.024 s"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(t("div.csv")));  // nothing half-written
  EXPECT_EQ(run(kExe + " simulate " + kPreset + " --out " + kMissingDir + "/a.csv", &err), 1);
  EXPECT_NE(err.find("cannot write"), std::string::npos) << err;
  EXPECT_NE(err.find(kMissingDir), std::string::npos) << err;
}

TEST(ExitCodes, Render) {
  Tmp t;
  std::string err;
  const std::string render = kHeadless + " render ";
  EXPECT_EQ(run(render + kPreset + " --size 320x200 --out " + t("a.png")), 0);
  EXPECT_EQ(run(render + kPreset + " --size 10x10 --out " + t("b.png")), 2);
  EXPECT_EQ(run(render + t("missing.json") + " --out " + t("b.png")), 2);
  write_diverging_preset(t("div.json"));
  EXPECT_EQ(run(render + t("div.json") + " --size 320x200 --out " + t("div.png"), &err), 3);
  EXPECT_NE(err.find("diverged"), std::string::npos) << err;
  EXPECT_EQ(run(render + kPreset + " --size 320x200 --out " + kMissingDir + "/a.png", &err), 1);
  EXPECT_NE(err.find(kMissingDir), std::string::npos) << err;
  // The window executable forwards render to gmslab-headless and returns its code.
  EXPECT_EQ(run(kExe + " render " + kPreset + " --size 10x10 --out " + t("c.png")), 2);
}

TEST(ExitCodes, OpenChecksThePresetAndTabBeforeAnyWindow) {
  Tmp t;
  std::string err;
  // No window is opened for a bad request (DISPLAY unset: the checks come first all the same).
  const std::string open = "env -u DISPLAY -u WAYLAND_DISPLAY " + kExe + " --open ";
  EXPECT_EQ(run(open + "no_such_preset", &err), 2);
  EXPECT_NE(err.find("--open 'no_such_preset': no such file"), std::string::npos) << err;
  EXPECT_EQ(run(open + "two_mass_drive --tab plot", &err), 2);
  EXPECT_NE(err.find("--tab"), std::string::npos) << err;
  EXPECT_EQ(run(open + "two_mass_drive --tab simulation", &err), 2);
  EXPECT_NE(err.find("--tab plant"), std::string::npos) << err;
  EXPECT_EQ(run(open + "fig4_stick_slip --tab identify --run", &err), 2);
  EXPECT_NE(err.find("drop --run"), std::string::npos) << err;
  EXPECT_EQ(run("env -u DISPLAY " + kExe + " --tab plant", &err), 2);  // --tab needs --open
  EXPECT_NE(err.find("--open"), std::string::npos) << err;
  EXPECT_EQ(run(open + "fig4_stick_slip simulate " + kPreset + " --out " + t("a.csv"), &err), 2);
  EXPECT_NE(err.find("do not go with a command"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(t("a.csv")));
  // A good request without a display: exit 1 and how to get an image instead.
  EXPECT_EQ(run(open + "two_mass_drive --run", &err), 1);
  EXPECT_NE(err.find("needs a display"), std::string::npos) << err;
}

TEST(ExitCodes, Figures) {
  Tmp t;
  std::string err;
  const std::string figures = kHeadless + " figures --size 320x200 --only fig2a_presliding ";
  EXPECT_EQ(run(figures + "--out " + t("figs")), 0);
  EXPECT_TRUE(fs::exists(t("figs") + "/fig2a_presliding.png"));
  EXPECT_EQ(run(kHeadless + " figures --only no_such_figure --out " + t("figs2"), &err), 2);
  EXPECT_NE(err.find("no_such_figure"), std::string::npos) << err;
  std::ofstream(t("file")) << "x";  // a file where the output folder should be
  EXPECT_EQ(run(figures + "--out " + t("file") + "/figs", &err), 1);
  EXPECT_NE(err.find("cannot write"), std::string::npos) << err;
  // A figure's preset that diverges (presets from $GMSLAB_PRESETS).
  fs::create_directories(t("presets"));
  write_diverging_preset(t("presets") + "/fig2a_presliding.json");
  EXPECT_EQ(run("GMSLAB_PRESETS=" + t("presets") + " " + figures + "--out " + t("figs3"), &err), 3);
  EXPECT_NE(err.find("diverged"), std::string::npos) << err;
}

TEST(ExitCodes, Design) {
  Tmp t;
  const std::string design = kExe + " design --num 4 --den \"1 2 0\" --wn 4 ";
  EXPECT_EQ(run(design + "--zeta 0.5 --json " + t("d.json")), 0);
  EXPECT_TRUE(fs::exists(t("d.json")));
  EXPECT_EQ(run(design + "--zeta 1.2 --json " + t("e.json")), 2);
  std::string err;
  EXPECT_EQ(run(design + "--zeta 0.5 --json " + kMissingDir + "/d.json", &err), 1);
  EXPECT_NE(err.find(kMissingDir), std::string::npos) << err;
}

TEST(ExitCodes, Identify) {
  Tmp t;
  synth::SynthOptions so;
  so.moves = 4;
  const MeasuredRecord r = synth::synthesize(so);
  {
    std::ofstream o(t("train.csv"));
    o << "t_s,x_m,F_N\n";
    o.precision(12);
    for (std::size_t k = 0; k < r.size(); ++k) o << r.t[k] << ',' << r.x[k] << ',' << r.F[k] << '\n';
  }
  const std::string identify = kExe + " identify --starts 1 --effects offset --data ";
  EXPECT_EQ(run(identify + t("train.csv") + " --report " + t("r.json")), 0);
  EXPECT_TRUE(fs::exists(t("r.json")));
  EXPECT_EQ(run(identify + t("missing.csv") + " --report " + t("s.json")), 2);
  EXPECT_FALSE(fs::exists(t("s.json")));
  // A column position no unsigned long holds is bad input naming it (not an internal error).
  std::string col_err;
  EXPECT_EQ(run(identify + t("train.csv") + " --columns t=99999999999999999999999 --report " + t("c.json"), &col_err), 2);
  EXPECT_NE(col_err.find("99999999999999999999999"), std::string::npos) << col_err;
  std::string err;
  EXPECT_EQ(run(identify + t("train.csv") + " --report " + kMissingDir + "/r.json", &err), 1);
  EXPECT_NE(err.find(kMissingDir), std::string::npos) << err;
}

TEST(ExitCodes, PlotFigure) {
  Tmp t;
  Figure f;
  f.id = "exit";
  f.title = "exit codes";
  f.panels.push_back({"", "line", "x [-]", "y [-]", {{"y = x", {0.0, 1.0}, {0.0, 1.0}}}});
  save_figure_json(f, t("f.json"));
  const std::string plot = kHeadless + " plot-figure ";
  EXPECT_EQ(run(plot + t("f.json") + " --size 320x200 --out " + t("f.png")), 0);
  EXPECT_TRUE(fs::exists(t("f.png")));
  EXPECT_EQ(run(plot + t("missing.json") + " --out " + t("g.png")), 2);
  EXPECT_EQ(run(plot + t("f.json") + " --size 1x1 --out " + t("g.png")), 2);
  std::string err;
  EXPECT_EQ(run(plot + t("f.json") + " --size 320x200 --out " + kMissingDir + "/f.png", &err), 1);
  EXPECT_NE(err.find(kMissingDir), std::string::npos) << err;
}
#endif
