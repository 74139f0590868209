// Measured-data loaders on a synthetic record of 25,000 rows (the size of the EMPS record):
//   BM_CsvDialect/<dialect>: parse from memory, dialect detected (comma / semicolon + decimal
//     comma / whitespace without header, columns by position).
//   BM_MatLoad/<version>: load a MATLAB file written by matio (v5, v7.3), a 25,000 x 3 matrix
//     chosen by column (t=data:1,x=data:2,F=data:3).
#include <benchmark/benchmark.h>
#include <matio.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/measured_file.hpp"

using namespace gmslab;

namespace {
constexpr std::size_t kRows = 25000;

double t_of(std::size_t i) { return 1e-3 * static_cast<double>(i); }
double x_of(std::size_t i) { return 1e-3 * std::sin(1e-3 * static_cast<double>(i)); }
double f_of(std::size_t i) { return 2.0 * std::cos(3e-3 * static_cast<double>(i)); }

std::string text(int dialect) {
  std::string s = dialect == 0 ? "t_s,x_m,F_N\n" : dialect == 1 ? "t_s;x_m;F_N\n" : "";
  char buf[128];
  for (std::size_t i = 0; i < kRows; ++i) {
    if (dialect == 2)
      std::snprintf(buf, sizeof buf, "%.9g  %.9g  %.9g\n", t_of(i), x_of(i), f_of(i));
    else
      std::snprintf(buf, sizeof buf, dialect == 0 ? "%.9g,%.9g,%.9g\n" : "%.9g;%.9g;%.9g\n", t_of(i), x_of(i), f_of(i));
    std::string row(buf);
    if (dialect == 1)
      for (auto& c : row)
        if (c == '.') c = ',';
    s += row;
  }
  return s;
}
}  // namespace

static void BM_CsvDialect(benchmark::State& st) {
  const int dialect = static_cast<int>(st.range(0));
  const std::string s = text(dialect);
  const CsvColumns cols = dialect == 2 ? parse_column_map("t=1,x=2,F=3") : CsvColumns{};
  for (auto _ : st) {
    const auto r = parse_measured_csv(s, "bench.csv", cols);
    benchmark::DoNotOptimize(r.F.data());
  }
  st.SetLabel(dialect == 0 ? "comma" : dialect == 1 ? "semicolon, decimal comma" : "whitespace, no header");
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * kRows));
  st.SetBytesProcessed(static_cast<std::int64_t>(st.iterations() * s.size()));
}
BENCHMARK(BM_CsvDialect)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

static void BM_MatLoad(benchmark::State& st) {
  const bool v73 = st.range(0) == 1;
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("gmslab_bench_" + std::to_string(getpid()) + (v73 ? "_73.mat" : "_5.mat"))).string();
  std::vector<double> data(3 * kRows);
  for (std::size_t i = 0; i < kRows; ++i) data[i] = t_of(i), data[kRows + i] = x_of(i), data[2 * kRows + i] = f_of(i);
  mat_t* m = Mat_CreateVer(path.c_str(), nullptr, v73 ? MAT_FT_MAT73 : MAT_FT_MAT5);
  if (!m) return st.SkipWithError("matio cannot create the file");
  size_t dims[2] = {kRows, 3};
  matvar_t* v = Mat_VarCreate("data", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data.data(), 0);
  Mat_VarWrite(m, v, MAT_COMPRESSION_NONE);
  Mat_VarFree(v);
  Mat_Close(m);
  const CsvColumns cols = parse_column_map("t=data:1,x=data:2,F=data:3");
  for (auto _ : st) {
    const auto r = load_measured(path, cols);
    benchmark::DoNotOptimize(r.F.data());
  }
  std::filesystem::remove(path);
  st.SetLabel(v73 ? "v7.3" : "v5");
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * kRows));
}
BENCHMARK(BM_MatLoad)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
