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
                          " --plot " + png + " --size 800x500 --starts 1 --effects offset,inertia" +
                          " --compare gms,coulomb 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto j = nlohmann::json::parse(read_file(report));
  EXPECT_EQ(j["effects_added"], nlohmann::json::array({"offset"}));
  EXPECT_LT(j["rms_after"]["validation"].get<double>(), j["rms_before"]["validation"].get<double>());
  const Scenario sc = load_scenario(j["scenario_file"].get<std::string>());
  EXPECT_EQ(sc.friction.model, "gms");
  // --compare: both models fitted with the offset; the static Coulomb law does worse on validation.
  const auto& cmp = j.at("model_comparison");
  ASSERT_EQ(cmp.size(), 2u);
  EXPECT_EQ(cmp[0]["model"], "gms");
  EXPECT_EQ(cmp[1]["model"], "coulomb");
  EXPECT_LT(cmp[0]["rms"]["validation"].get<double>(), cmp[1]["rms"]["validation"].get<double>());
  EXPECT_FALSE(cmp[0]["time_limited"].get<bool>());
  const std::string bytes = read_file(png);
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  for (const auto& f : {csv, report, png, j["scenario_file"].get<std::string>(),
                        std::filesystem::path(png).replace_extension(".figure.json").string()})
    std::filesystem::remove(f);
}

TEST(IdentCli, UnknownCompareModelExitsWithCode2NamingIt) {
  synth::SynthOptions so;
  so.moves = 4;
  const std::string csv = temp("cmp.csv"), log = temp("cmp.log");
  write_csv(synth::synthesize(so), csv);
  const std::string cmd = std::string(GMSLAB_EXE) + " identify --data " + csv + " --report " + temp("c.json") +
                          " --compare gms,frictionless 2>" + log;
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, 2);
  EXPECT_NE(read_file(log).find("frictionless"), std::string::npos) << read_file(log);
  EXPECT_FALSE(std::filesystem::exists(temp("c.json")));  // rejected before any fitting
  std::filesystem::remove(csv);
  std::filesystem::remove(log);
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
