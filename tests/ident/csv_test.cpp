// The measured-data CSV reader: columns by name and unit suffix, explicit mapping, unit
// conversion, and every kind of bad file rejected with the file, line and column.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "core/ident/dataset.hpp"
#include "core/io/csv.hpp"

using namespace gmslab;

namespace {

std::string rows(int n, const std::string& header = "t_s,x_m,F_N", double dt = 0.001) {
  std::string s = header + "\n";
  for (int i = 0; i < n; ++i)
    s += std::to_string(i * dt) + "," + std::to_string(1e-6 * i) + "," + std::to_string(0.5 * i) + "\n";
  return s;
}

// The InputError message of parsing text, or "" when it parses.
std::string error_of(const std::string& text, const CsvColumns& c = {}) {
  try {
    parse_measured_csv(text, "rec.csv", c);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(IdentCsv, ColumnsFoundByNameWithAndWithoutUnitSuffix) {
  const auto r = parse_measured_csv(rows(20), "a.csv");
  ASSERT_EQ(r.size(), 20u);
  EXPECT_DOUBLE_EQ(r.t[3], 0.003);
  EXPECT_DOUBLE_EQ(r.x[3], 3e-6);
  EXPECT_DOUBLE_EQ(r.F[3], 1.5);
  EXPECT_TRUE(r.v.empty());
  EXPECT_EQ(r.force_column, "F_N");
  const auto plain = parse_measured_csv(rows(20, "t,x,F"), "b.csv");
  EXPECT_DOUBLE_EQ(plain.F[4], 2.0);
}

TEST(IdentCsv, UnitSuffixesAreConvertedToSI) {
  std::string s = "F_kN,x_mm,t_ms,v_mmps,Fn_N,pulse_code\n";
  for (int i = 0; i < 12; ++i)
    s += "0.002," + std::to_string(i) + "," + std::to_string(10 * i) + ",5,100,1\n";
  const auto r = parse_measured_csv(s, "u.csv");
  EXPECT_DOUBLE_EQ(r.F[0], 2.0);       // 0.002 kN
  EXPECT_DOUBLE_EQ(r.x[3], 3e-3);      // 3 mm
  EXPECT_DOUBLE_EQ(r.t[2], 0.02);      // 20 ms
  EXPECT_DOUBLE_EQ(r.v[0], 5e-3);      // 5 mm/s
  EXPECT_DOUBLE_EQ(r.Fn[0], 100.0);
  ASSERT_NE(r.extra_column("pulse_code"), nullptr);
  EXPECT_EQ(r.extra_column("pulse_code")->size(), 12u);
}

TEST(IdentCsv, ExplicitMappingAndNonUniformSamplingAndCrlf) {
  std::string s = "time,pos_mm,force\r\n";
  double t = 0;
  for (int i = 0; i < 15; ++i) {
    t += 0.001 * (1 + i % 3);
    s += std::to_string(t) + "," + std::to_string(i) + ",1.0\r\n";
  }
  const auto c = parse_column_map("t=time, x=pos_mm ,F=force");
  const auto r = parse_measured_csv(s, "m.csv", c);
  ASSERT_EQ(r.size(), 15u);
  EXPECT_DOUBLE_EQ(r.x[2], 2e-3);
  EXPECT_NEAR(r.t[1] - r.t[0], 0.002, 1e-12);
  EXPECT_NE(error_of(s, parse_column_map("t=time,x=nope,F=force")).find("'nope'"), std::string::npos);
  EXPECT_THROW(parse_column_map("q=foo"), InputError);
  EXPECT_THROW(parse_column_map("t"), InputError);
}

TEST(IdentCsv, BadFilesNameFileLineAndColumn) {
  EXPECT_NE(error_of("").find("empty"), std::string::npos);
  EXPECT_NE(error_of("t_s,x_m\n0,0\n").find("no column for F"), std::string::npos);
  EXPECT_NE(error_of("t_s,x_in,F_N\n").find("unknown unit 'in'"), std::string::npos);
  EXPECT_NE(error_of("t_s,x_m,F_N,F\n").find("two columns for F"), std::string::npos);
  std::string text = rows(12);
  text.replace(text.find("\n0.005000,") + 1, 8, "abc");  // row 7 (file line 7)
  const auto e1 = error_of(text);
  EXPECT_NE(e1.find("rec.csv:7"), std::string::npos) << e1;
  EXPECT_NE(e1.find("'t_s'"), std::string::npos) << e1;
  EXPECT_NE(e1.find("not a number"), std::string::npos) << e1;
  const auto e2 = error_of("t_s,x_m,F_N\n0,0,1\n0.1,0,nan\n");
  EXPECT_NE(e2.find("rec.csv:3"), std::string::npos) << e2;
  EXPECT_NE(e2.find("'F_N'"), std::string::npos) << e2;
  const auto e3 = error_of("t_s,x_m,F_N\n0,0,1\n0.1,0,1\n0.1,0,1\n");
  EXPECT_NE(e3.find("rec.csv:4"), std::string::npos) << e3;
  EXPECT_NE(e3.find("strictly increase"), std::string::npos) << e3;
  const auto e4 = error_of("t_s,x_m,F_N\n0,0,1\n0.1,0\n");
  EXPECT_NE(e4.find("rec.csv:3"), std::string::npos) << e4;
  EXPECT_NE(e4.find("truncated"), std::string::npos) << e4;
  EXPECT_NE(error_of(rows(5)).find("at least 10"), std::string::npos);
  EXPECT_NE(error_of("t_s,x_m,F_N\n0,0,\xff\n").find("not UTF-8"), std::string::npos);
  EXPECT_NE(error_of("t_s,x_m,F_N\n0,0,1e999\n").find("'F_N'"), std::string::npos);
}

TEST(IdentCsv, CommentsBlankLinesAndByteOrderMarkAreSkipped) {
  const std::string s = "\xEF\xBB\xBF# recorded 2026\n\n" + rows(11) + "\n\n";
  EXPECT_EQ(parse_measured_csv(s, "c.csv").size(), 11u);
}

// --mask-edges: windows around every change of an extra column, a note (not a silent nothing)
// when the record lacks the column, and malformed specs named with the field they came from.
TEST(IdentCsv, EdgeMasksAroundEveryChangeOfAColumn) {
  std::string text = "t_s,x_m,F_N,pulse_code\n";
  for (int i = 0; i < 40; ++i)
    text += std::to_string(0.01 * i) + ",0," + std::to_string(i) + "," + (i >= 10 && i < 25 ? "1" : "0") + "\n";
  const auto r = parse_measured_csv(text, "pulses.csv");
  std::string note;
  const auto w = ident::parse_edge_masks("pulse_code:0.015:0.045", r, "--mask-edges", &note);
  ASSERT_EQ(w.size(), 2u);  // rising edge at t = 0.10 s, falling edge at t = 0.25 s
  EXPECT_NEAR(w[0].t0, 0.085, 1e-12);
  EXPECT_NEAR(w[0].t1, 0.145, 1e-12);
  EXPECT_NEAR(w[1].t0, 0.235, 1e-12);
  EXPECT_NEAR(w[1].t1, 0.295, 1e-12);
  EXPECT_EQ(note, "");
  // The prepared dataset ignores exactly the samples inside those windows (and 10 edge samples).
  const auto d = ident::prepare_dataset(r, w, 0);
  std::size_t masked = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const double t = d.t[k];
    const bool inside = (t > 0.085 && t < 0.145) || (t > 0.235 && t < 0.295);
    EXPECT_EQ(d.use[k] == 0, inside) << "t = " << t;
    masked += d.use[k] == 0;
  }
  EXPECT_EQ(masked, 12u);  // 0.09 ... 0.14 and 0.24 ... 0.29

  const auto none = ident::parse_edge_masks("code:0:0.1", r, "mask edges", &note);
  EXPECT_TRUE(none.empty());
  EXPECT_NE(note.find("no column 'code' in pulses.csv"), std::string::npos) << note;
  EXPECT_NE(note.find("pulse_code"), std::string::npos) << note;  // lists what the file has

  for (const char* bad : {"pulse_code", "pulse_code:0.1", "pulse_code:x:0.1", ":0:1", "pulse_code:-1:0.1",
                          "pulse_code:0:nan"}) {
    try {
      ident::parse_edge_masks(bad, r, "mask edges");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("mask edges '", 0), 0u) << e.what();
    }
  }
}
