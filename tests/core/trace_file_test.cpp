// Traces in the formats analysis tools read (core/io/trace_file.hpp): gmslab simulate --out chooses
// CSV, HDF5 or MATLAB v7.3 by the extension and rejects any other; each file holds the CSV's columns
// with the simulated values (HDF5 and .mat exactly, CSV to its 10 digits), HDF5 with a unit
// attribute per dataset; the identification loader reads each of them as it is.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/measured_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_file.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {

fs::path tmp(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("gmslab_trace_file_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d / name;
}

Scenario short_force_drive() {
  Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2d_nondrifting.json");
  sc.run.duration = 0.6;  // a force drive: applied and friction differ
  return sc;
}

// The trace's columns as the CSV names them, from the in-memory Trace.
std::vector<NamedColumn> expected_columns(const Trace& tr) {
  std::vector<NamedColumn> c = {{"t_s", tr.t}, {"x_m", tr.x}, {"v_mps", tr.v}, {"F_friction_N", tr.friction},
                                {"F_applied_N", tr.applied}};
  const std::size_t ne = tr.n_elements;
  for (std::size_t i = 0; i < ne; ++i) {
    NamedColumn f{"F" + std::to_string(i + 1) + "_N", {}};
    for (std::size_t k = 0; k < tr.size(); ++k) f.values.push_back(tr.element_force[k * ne + i]);
    c.push_back(f);
  }
  for (std::size_t i = 0; i < ne; ++i) {
    NamedColumn s{"slip" + std::to_string(i + 1), {}};
    for (std::size_t k = 0; k < tr.size(); ++k) s.values.push_back(tr.element_slip[k * ne + i]);
    c.push_back(s);
  }
  return c;
}

std::string unit_attribute(const std::string& file, const std::string& dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  const hid_t a = H5Aopen(d, "unit", H5P_DEFAULT);
  const hid_t t = H5Aget_type(a);
  std::string s(H5Tget_size(t), '\0');
  H5Aread(a, t, s.data());
  H5Tclose(t), H5Aclose(a), H5Dclose(d), H5Fclose(f);
  return s.substr(0, s.find('\0'));
}

}  // namespace

TEST(TraceFile, EveryFormatHoldsTheSimulatedColumns) {
  const Scenario sc = short_force_drive();
  const Trace tr = simulate(sc);
  const auto want = expected_columns(tr);
  for (const std::string ext : {".csv", ".h5", ".hdf5", ".mat", ".H5"}) {
    SCOPED_TRACE(ext);
    const auto p = tmp("trace" + ext).string();
    EXPECT_EQ(save_trace_file(sc, p), tr.size());
    auto got = load_trace_columns(p);
    ASSERT_EQ(got.size(), want.size());
    if (ext == ".mat") {  // matio lists a v7.3 file's variables by name: compare in the CSV's order
      std::vector<NamedColumn> ordered;
      for (const auto& w : want)
        for (const auto& g : got)
          if (g.name == w.name) ordered.push_back(g);
      got = ordered;
      ASSERT_EQ(got.size(), want.size());
    }
    for (std::size_t c = 0; c < want.size(); ++c) {
      ASSERT_EQ(got[c].name, want[c].name);
      ASSERT_EQ(got[c].values.size(), want[c].values.size()) << want[c].name;
      for (std::size_t k = 0; k < want[c].values.size(); ++k) {
        if (ext == ".csv")  // %.10g text
          ASSERT_NEAR(got[c].values[k], want[c].values[k], 1e-9 * std::max(1.0, std::abs(want[c].values[k]))) << want[c].name;
        else
          ASSERT_EQ(got[c].values[k], want[c].values[k]) << want[c].name << " [" << k << "]";
      }
    }
  }
  const auto h5 = tmp("trace.h5").string();
  EXPECT_TRUE(is_hdf5_file(h5));
  EXPECT_EQ(unit_attribute(h5, "t_s"), "s");
  EXPECT_EQ(unit_attribute(h5, "x_m"), "m");
  EXPECT_EQ(unit_attribute(h5, "v_mps"), "m/s");
  EXPECT_EQ(unit_attribute(h5, "F_friction_N"), "N");
  EXPECT_EQ(unit_attribute(h5, "slip1"), "");
  EXPECT_LT(fs::file_size(h5), fs::file_size(tmp("trace.csv")));  // compressed
}

// The identification loader reads every format as it is: F = the friction force, force=applied.
TEST(TraceFile, IdentificationLoaderReadsEachFormatAsItIs) {
  const Scenario sc = short_force_drive();
  const Trace tr = simulate(sc);
  for (const std::string ext : {".h5", ".mat"}) {
    SCOPED_TRACE(ext);
    const auto p = tmp("rec" + ext).string();
    save_trace_file(sc, p);
    const auto r = load_measured(p);
    EXPECT_EQ(r.t, tr.t);
    EXPECT_EQ(r.x, tr.x);
    EXPECT_EQ(r.v, tr.v);
    EXPECT_EQ(r.F, tr.friction);
    CsvColumns applied;
    applied.force = "applied";
    EXPECT_EQ(load_measured(p, applied).F, tr.applied);
  }
}

TEST(TraceFile, UnknownExtensionIsRejectedBeforeAnyWork) {
  const Scenario sc = short_force_drive();
  for (const std::string name : {"trace.txt", "trace", "trace.h5.bak"}) {
    const auto p = tmp(name).string();
    try {
      save_trace_file(sc, p);
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--out '" + p + "': "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(".csv (text), .h5 or .hdf5 (HDF5), .mat (MATLAB v7.3)"), std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(p));
  }
  // A file that is not HDF5 is not read as one, and says why.
  const auto fake = tmp("fake.h5").string();
  write_file_atomic(fake, "t_s,x_m\n");
  EXPECT_THROW(load_hdf5_columns(fake), InputError);
}

// An assembled plant's trace: the CSV's channel columns in HDF5 and .mat ('.' as '_' in MATLAB).
TEST(TraceFile, AssembledPlantInEveryFormat) {
  AssemblyScenario as = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json");
  as.run.duration = 0.3;
  const auto csv = tmp("plant.csv").string(), h5 = tmp("plant.h5").string(), mat = tmp("plant.mat").string();
  const std::size_t n = save_assembly_trace_file(as, csv);
  EXPECT_EQ(save_assembly_trace_file(as, h5), n);
  EXPECT_EQ(save_assembly_trace_file(as, mat), n);
  const auto c = load_trace_columns(csv), h = load_trace_columns(h5), m_by_name = load_trace_columns(mat);
  std::vector<NamedColumn> m;  // matio lists a v7.3 file's variables by name: in the CSV's order
  for (const auto& col : c)
    for (const auto& g : m_by_name) {
      std::string mname = col.name;
      for (char& ch : mname)
        if (ch == '.') ch = '_';
      if (g.name == mname) m.push_back(g);
    }
  ASSERT_EQ(c.size(), h.size());
  ASSERT_EQ(c.size(), m.size());
  AssemblySimulation sim(as);
  sim.run_to_end();
  const auto x_motor = sim.trace().series("x.motor");
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_EQ(h[i].name, c[i].name);
    std::string mname = c[i].name;
    for (char& ch : mname)
      if (ch == '.') ch = '_';
    EXPECT_EQ(m[i].name, mname);
    ASSERT_EQ(h[i].values.size(), n);
    for (std::size_t k = 0; k < n; ++k) {  // the CSV prints 17 digits: exact
      ASSERT_EQ(h[i].values[k], c[i].values[k]) << c[i].name;
      ASSERT_EQ(m[i].values[k], c[i].values[k]) << c[i].name;
    }
    if (c[i].name == "x.motor_m") {
      EXPECT_EQ(h[i].values, x_motor);
    }
  }
  fs::remove_all(tmp("x").parent_path());
}
