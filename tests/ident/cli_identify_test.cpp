// `gmslab identify` end to end: a generated CSV in, report JSON + scenario preset + report PNG out;
// bad input exits with code 2 and names the file and line.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/ident/synthetic.hpp"

#ifdef GMSLAB_EXE
using namespace gmslab;

namespace {
std::string temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("gmslab_ident_cli_" + std::to_string(::getpid()) + "_" + name)).string();
}
void write_csv(const MeasuredRecord& r, const std::string& path) {
  std::ofstream o(path);
  o << "t_s,x_m,F_N\n";
  o.precision(12);
  for (std::size_t k = 0; k < r.size(); ++k) o << r.t[k] << ',' << r.x[k] << ',' << r.F[k] << '\n';
}
}  // namespace

TEST(IdentCli, IdentifyWritesReportScenarioAndPlot) {
  synth::SynthOptions so;
  so.effect = ident::Effect::Offset;
  so.moves = 6;
  const std::string csv = temp("train.csv"), report = temp("report.json"), png = temp("report.png");
  write_csv(synth::synthesize(so), csv);
  const std::string cmd = std::string(GMSLAB_EXE) + " identify --data " + csv + " --report " + report +
                          " --plot " + png + " --size 800x500 --starts 1 --effects offset,inertia 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto j = nlohmann::json::parse(read_file(report));
  EXPECT_EQ(j["effects_added"], nlohmann::json::array({"offset"}));
  EXPECT_LT(j["rms_after"]["validation"].get<double>(), j["rms_before"]["validation"].get<double>());
  const Scenario sc = load_scenario(j["scenario_file"].get<std::string>());
  EXPECT_EQ(sc.friction.model, "gms");
  const std::string bytes = read_file(png);
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  for (const auto& f : {csv, report, png, j["scenario_file"].get<std::string>(),
                        std::filesystem::path(png).replace_extension(".figure.json").string()})
    std::filesystem::remove(f);
}

TEST(IdentCli, BadCsvExitsWithCode2) {
  const std::string csv = temp("bad.csv");
  std::ofstream(csv) << "t_s,x_m,F_N\n0,0,1\n0.1,0,abc\n";
  const std::string cmd = std::string(GMSLAB_EXE) + " identify --data " + csv + " --report " +
                          temp("r.json") + " 2>/dev/null";
  const int rc = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::filesystem::remove(csv);
}
#endif
