// Columns that are never silently wrong (core/io/csv.hpp): gmslab's own trace read as it is (the
// friction force as F, --force applied for the applied force), headers as labs write them
// (t [s], x (mm), F [N], pos_um, Time, Position), a mapped column keeping its header's unit also
// when given by position, .mat variables named time/position/force, and one column mapped to two
// roles rejected naming both. Every expectation comes from the values the test wrote.
#include <gtest/gtest.h>
#include <matio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/ident/dataset.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/measured_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_csv.hpp"
#include "core/sim/simulation.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {

fs::path tmp(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("gmslab_columns_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d / name;
}

void write_text(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Random t (increasing), x, F, the values as written (in the file's units).
struct Values {
  std::vector<double> t, x, F;
};
Values random_values(unsigned seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dt(1e-3, 5e-3), u(-20.0, 20.0);
  Values v;
  double t = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    t += dt(rng);
    v.t.push_back(t);
    v.x.push_back(u(rng));
    v.F.push_back(u(rng));
  }
  return v;
}

// A CSV with `header` (separator `sep`) and the columns t, x, F in that order.
std::string csv(const std::string& header, const Values& v, const std::string& sep = ",") {
  std::string s = header + "\n";
  for (std::size_t i = 0; i < v.t.size(); ++i) s += num(v.t[i]) + sep + num(v.x[i]) + sep + num(v.F[i]) + "\n";
  return s;
}

// The record loaded from text (written to a file) with the column map and force.
MeasuredRecord load(const std::string& text, const std::string& map = "", const std::string& force = "",
                    const std::string& name = "rec.csv") {
  const auto p = tmp(name);
  write_text(p, text);
  CsvColumns c = map.empty() ? CsvColumns{} : parse_column_map(map);
  c.force = force;
  return load_measured(p.string(), c);
}

std::string error_of(const std::string& text, const std::string& map = "", const std::string& force = "") {
  try {
    load(text, map, force);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_scaled(const std::vector<double>& got, const std::vector<double>& written, double scale,
                   const std::string& what) {
  ASSERT_EQ(got.size(), written.size()) << what;
  for (std::size_t i = 0; i < written.size(); ++i) ASSERT_DOUBLE_EQ(got[i], written[i] * scale) << what << " [" << i << "]";
}

}  // namespace

// Headers as labs write them: units in brackets or parentheses, word names in any case, pos_um.
TEST(Columns, LabHeadersAreFoundAndConvertedToSI) {
  const auto v = random_values(1, 40);
  struct Case {
    std::string header, sep;
    double st, sx, sF;
  };
  const std::vector<Case> cases = {
      {"t [s],x (mm),F [N]", ",", 1.0, 1e-3, 1.0},
      {"t [ms];pos_um;F [kN]", ";", 1e-3, 1e-6, 1e3},
      {"Time [s]\tPosition (\xC2\xB5m)\tForce (mN)", "\t", 1.0, 1e-6, 1e-3},
      {"time,position_cm,force", ",", 1.0, 1e-2, 1.0},
      {"t(s),x[nm],F(N)", ",", 1.0, 1e-9, 1.0},
  };
  for (const auto& c : cases) {
    const auto r = load(csv(c.header, v, c.sep));
    expect_scaled(r.t, v.t, c.st, c.header + " t");
    expect_scaled(r.x, v.x, c.sx, c.header + " x");
    expect_scaled(r.F, v.F, c.sF, c.header + " F");
  }
  // Velocity with a unit in brackets; "F1_N" (an element force) is not F.
  std::string s = "t_s,x_m,v [mm/s],F_N,F1_N\n";
  for (std::size_t i = 0; i < v.t.size(); ++i)
    s += num(v.t[i]) + "," + num(v.x[i]) + "," + num(v.F[i]) + "," + num(v.x[i]) + "," + num(v.F[i] * 2) + "\n";
  const auto r = load(s);
  expect_scaled(r.v, v.F, 1e-3, "v [mm/s]");
  expect_scaled(r.F, v.x, 1.0, "F_N");
  ASSERT_NE(r.extra_column("F1_N"), nullptr);
  // A word name followed by a word that is no unit names something else (kept as an extra column);
  // a letter with an unknown suffix is an unknown unit (an error, below).
  std::string w = "t_s,position_cmd_m,x_mm,F_N,force_sensor_V,time_stamp\n";
  for (std::size_t i = 0; i < v.t.size(); ++i)
    w += num(v.t[i]) + ",0," + num(v.x[i]) + "," + num(v.F[i]) + ",1," + num(v.t[i]) + "\n";
  const auto rw = load(w);
  expect_scaled(rw.x, v.x, 1e-3, "x_mm beside position_cmd_m");
  expect_scaled(rw.F, v.F, 1.0, "F_N beside force_sensor_V");
  EXPECT_NE(rw.extra_column("position_cmd_m"), nullptr);
  EXPECT_NE(rw.extra_column("time_stamp"), nullptr);
  EXPECT_NE(error_of(csv("t_s,x_in,F_N", v)).find("'x_in': unknown unit 'in'"), std::string::npos);
  // An unknown unit in brackets is an error naming it and what is accepted.
  const auto e = error_of(csv("t [s],x [inch],F [N]", v));
  EXPECT_NE(e.find("'x [inch]': unknown unit 'inch'; accepted: x (SI) or x with a unit of m, cm, mm, um"),
            std::string::npos) << e;
}

// A mapped column keeps its header's unit, however it is given: by name or by position.
TEST(Columns, MappedColumnKeepsItsHeadersUnitByNameAndByPosition) {
  const auto v = random_values(2, 30);
  const std::string text = csv("Zeit_s;Weg_mm;Kraft_N", v, ";");
  for (const std::string map : {"t=1,x=2,F=3", "t=Zeit_s,x=Weg_mm,F=Kraft_N", "t=1,x=Weg_mm,F=3"}) {
    const auto r = load(text, map);
    expect_scaled(r.t, v.t, 1.0, map + " t");
    expect_scaled(r.x, v.x, 1e-3, map + " x");  // millimetres, never metres
    expect_scaled(r.F, v.F, 1.0, map + " F");
  }
  const auto r = load(csv("Zeit [ms],Weg (um),Kraft [kN]", v), "t=1,x=2,F=3");
  expect_scaled(r.t, v.t, 1e-3, "Zeit [ms]");
  expect_scaled(r.x, v.x, 1e-6, "Weg (um)");
  expect_scaled(r.F, v.F, 1e3, "Kraft [kN]");
  // A name without a unit is SI (documented); a file without a header has no units.
  const auto raw = load(csv("a,b,c", v), "t=a,x=b,F=c");
  expect_scaled(raw.x, v.x, 1.0, "b");
  // A unit of another quantity, or a role's name, on the mapped column is an error.
  auto e = error_of(text, "t=1,x=3,F=2");
  EXPECT_NE(e.find("column 'Kraft_N' is mapped to x (length), but its unit 'N' is a force unit; accepted for x: m, cm, mm"),
            std::string::npos) << e;
  e = error_of(csv("t_s,x_mm,F_N", v), "t=1,x=3,F=2");
  EXPECT_NE(e.find("column 'F_N' is mapped to x (length), but its name says F (force)"), std::string::npos) << e;
  e = error_of(csv("t_s,x [furlong],F_N", v), "t=1,x=2,F=3");
  EXPECT_NE(e.find("'x [furlong]' (mapped to x): unknown unit 'furlong'"), std::string::npos) << e;
}

// One column for two roles is an error naming the column and both roles; so is a role given twice.
TEST(Columns, ColumnMappedTwiceIsAnErrorNamingBoth) {
  const auto v = random_values(3, 20);
  auto e = error_of(csv("t [s],Weg,Kraft", v), "t=1,x=2,F=2");
  EXPECT_NE(e.find("column 'Weg' is mapped to both x and F"), std::string::npos) << e;
  e = error_of(csv("t [s],Weg,Kraft", v), "t=1,x=Weg,F=2");
  EXPECT_NE(e.find("column 'Weg' is mapped to both x and F"), std::string::npos) << e;
  // Found by name for one role, mapped to another.
  e = error_of(csv("t_s,x_m,F_N", v), "Fn=F_N");
  EXPECT_NE(e.find("column 'F_N' is mapped to both F and Fn"), std::string::npos) << e;
  e = error_of(csv("a,b,c", v), "t=1,x=1,F=3");
  EXPECT_NE(e.find("column 'a' is mapped to both t and x"), std::string::npos) << e;
  try {
    parse_column_map("t=1,x=2,x=3,F=4");
    ADD_FAILURE() << "a role given twice was accepted";
  } catch (const InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find("x is given twice ('x=2' and 'x=3')"), std::string::npos) << ex.what();
  }
}

namespace {
void write_mat(const fs::path& p, const std::vector<std::pair<std::string, std::vector<double>>>& vars) {
  mat_t* m = Mat_CreateVer(p.c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(m, nullptr) << p;
  for (const auto& [name, values] : vars) {
    size_t dims[2] = {values.size(), 1};
    matvar_t* mv = Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                                 const_cast<double*>(values.data()), 0);
    ASSERT_NE(mv, nullptr);
    ASSERT_EQ(Mat_VarWrite(m, mv, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(mv);
  }
  Mat_Close(m);
}
}  // namespace

// MATLAB variables named as labs name them are found without a map, with their units.
TEST(Columns, MatVariablesTimePositionForceAreFound) {
  const auto v = random_values(4, 50);
  const auto p = tmp("lab.mat");
  write_mat(p, {{"time", v.t}, {"position", v.x}, {"force", v.F}, {"code", v.x}});
  auto r = load_measured(p.string());
  expect_scaled(r.t, v.t, 1.0, "time");
  expect_scaled(r.x, v.x, 1.0, "position");
  expect_scaled(r.F, v.F, 1.0, "force");
  EXPECT_EQ(r.force_column, "force");
  write_mat(p, {{"Time", v.t}, {"position_mm", v.x}, {"Force_kN", v.F}});
  r = load_measured(p.string());
  expect_scaled(r.x, v.x, 1e-3, "position_mm");
  expect_scaled(r.F, v.F, 1e3, "Force_kN");
  write_mat(p, {{"time", v.t}, {"pos_um", v.x}, {"F", v.F}, {"F2", v.F}});
  r = load_measured(p.string(), parse_column_map("F=F2"));  // F mapped; "F" is then an extra column
  expect_scaled(r.x, v.x, 1e-6, "pos_um");
  expect_scaled(r.F, v.F, 1.0, "F2");
}

// gmslab simulate's trace read as it is: F is the friction force; --force applied the applied one.
TEST(Columns, SimulateTraceIsReadAsItIs) {
  Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2d_nondrifting.json");
  sc.run.duration = 1.0;  // a force drive: the applied force differs from the friction force
  const Trace tr = simulate(sc);
  const auto p = tmp("trace.csv");
  save_trace_csv_streamed(sc, p.string());
  ASSERT_EQ(read_file(p.string()).substr(0, 41), "t_s,x_m,v_mps,F_friction_N,F_applied_N,F1");
  const auto close = [](const std::vector<double>& got, const std::vector<double>& want, const std::string& what) {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (std::size_t i = 0; i < want.size(); ++i)
      ASSERT_NEAR(got[i], want[i], 1e-9 * std::max(1.0, std::abs(want[i]))) << what << " [" << i << "]";  // %.10g
  };
  CsvColumns none;
  const auto r = load_measured(p.string(), none);
  close(r.t, tr.t, "t");
  close(r.x, tr.x, "x");
  close(r.v, tr.v, "v");
  close(r.F, tr.friction, "F (friction)");
  EXPECT_EQ(r.force_column, "F_friction_N");
  ASSERT_NE(r.extra_column("F_applied_N"), nullptr);
  CsvColumns friction;
  friction.force = "friction";
  close(load_measured(p.string(), friction).F, tr.friction, "--force friction");
  CsvColumns applied;
  applied.force = "applied";
  const auto ra = load_measured(p.string(), applied);
  close(ra.F, tr.applied, "--force applied");
  EXPECT_EQ(ra.force_column, "F_applied_N");
  double differ = 0.0;
  for (std::size_t i = 0; i < tr.size(); ++i) differ = std::max(differ, std::abs(tr.applied[i] - tr.friction[i]));
  EXPECT_GT(differ, 1e-3);  // the two choices are different columns
  // The identification loader reads it the same way.
  ident::RecordSpec spec;
  spec.path = p.string();
  spec.force = "applied";
  close(ident::load_dataset(spec).F, tr.applied, "load_dataset --force applied");
  // --force on a file without that force, --force with F=, an unknown --force: errors naming them.
  const auto v = random_values(5, 20);
  auto e = error_of(csv("t_s,x_m,F_N", v), "", "applied");
  EXPECT_NE(e.find("--force applied: no column for the applied force (expected F_applied or F_applied_N"),
            std::string::npos) << e;
  e = error_of(csv("t_s,x_m,F_N", v), "F=F_N", "applied");
  EXPECT_NE(e.find("--force applied and --columns F=F_N both choose the force column"), std::string::npos) << e;
  e = error_of(csv("t_s,x_m,F_applied_N", v));
  EXPECT_NE(e.find("'F_applied_N' (applied): choose it with --force"), std::string::npos) << e;
  e = error_of(csv("t_s,x_m,F_N", v), "", "motor");
  EXPECT_NE(e.find("--force 'motor': expected friction or applied"), std::string::npos) << e;
}

#ifdef GMSLAB_EXE
namespace {
int exit_code(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
}  // namespace

// End to end: `gmslab simulate PRESET --out rec.csv`, then `gmslab identify --data rec.csv` with no
// --columns; --force applied selects the applied force; a conflicting or unknown --force exits 2.
TEST(Columns, IdentifyReadsSimulateCsvAsItIs) {
  Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2c_periodic_1hz.json");
  sc.run.record_every = 100;  // 2000 samples: a quick identification
  const auto preset = tmp("short.json"), rec = tmp("rec.csv"), report = tmp("r.json"), log = tmp("log.txt");
  save_scenario(sc, preset.string());
  const std::string exe = GMSLAB_EXE;
  ASSERT_EQ(exit_code(exe + " simulate " + preset.string() + " --out " + rec.string() + " 2>/dev/null"), 0);
  const std::string ident = exe + " identify --data " + rec.string() + " --starts 1 --effects offset --report ";
  ASSERT_EQ(exit_code(ident + report.string() + " >/dev/null 2>" + log.string()), 0) << read_file(log.string());
  const auto j = nlohmann::json::parse(read_file(report.string()));
  EXPECT_EQ(j["train"]["source"], rec.string());
  EXPECT_GT(j["train"]["samples_used"].get<int>(), 1000);
  EXPECT_EQ(exit_code(ident + tmp("ra.json").string() + " --force applied >/dev/null 2>" + log.string()), 0)
      << read_file(log.string());
  EXPECT_EQ(exit_code(ident + tmp("rb.json").string() + " --force applied --columns F=F_friction_N >/dev/null 2>" +
                      log.string()),
            2);
  EXPECT_NE(read_file(log.string()).find("both choose the force column"), std::string::npos) << read_file(log.string());
  EXPECT_EQ(exit_code(ident + tmp("rc.json").string() + " --force motor >/dev/null 2>" + log.string()), 2);
  EXPECT_NE(read_file(log.string()).find("--force"), std::string::npos) << read_file(log.string());
  fs::remove_all(rec.parent_path());
}
#endif
