// libFuzzer target: measured records from MATLAB files (core/io/measured_file.hpp).
//
// The bytes describe a MAT-file, which is written with matio and then loaded: if the input holds a
// NUL byte, the part before it is an explicit column map ("t=time,x=data:2,F=force",
// parse_column_map). The rest: byte 0 picks the version (v5, v5 compressed, v7.3), then variables,
// each as [name length][name][class][rows][cols][values...] (classes double, single, int16,
// uint8, char, struct; names, shapes and values as the bytes say, NaN and Inf included). What is
// fuzzed is gmslab's own code (variable listing, matrix columns, the map, role choice, checks),
// not matio's or HDF5's parsers of damaged files: those are other projects' and are exercised by
// the error tests with a non-MAT file. The file and the map must be accepted or rejected with
// InputError; an accepted record keeps the CSV loader's promises (kMinSamples, equal lengths,
// finite values, strictly increasing time).
#include <matio.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/io/measured_file.hpp"

namespace {
bool finite(const std::vector<double>& c) {
  for (double x : c)
    if (!std::isfinite(x)) return false;
  return true;
}

struct Reader {
  std::string_view in;
  std::uint8_t byte() {
    if (in.empty()) return 0;
    const auto b = static_cast<std::uint8_t>(in.front());
    in.remove_prefix(1);
    return b;
  }
};

// Writes the variables the bytes describe; false when nothing could be written.
bool write_mat(const std::string& path, Reader& rd) {
  const auto v = rd.byte() % 3;
  const mat_ft ver = v == 2 ? MAT_FT_MAT73 : MAT_FT_MAT5;
  const auto comp = v == 1 ? MAT_COMPRESSION_ZLIB : MAT_COMPRESSION_NONE;
  mat_t* m = Mat_CreateVer(path.c_str(), nullptr, ver);
  if (!m) return false;
  for (int k = 0; k < 8 && !rd.in.empty(); ++k) {
    std::string name;
    const auto len = 1 + rd.byte() % 8;
    for (int i = 0; i < len; ++i) {
      const char c = static_cast<char>(rd.byte());
      name += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : 'a' + (c & 7);
    }
    if (std::isdigit(static_cast<unsigned char>(name[0]))) name[0] = 'v';
    const auto cls = rd.byte() % 6;
    size_t dims[2] = {static_cast<size_t>(rd.byte() % 40), static_cast<size_t>(1 + rd.byte() % 4)};
    if (rd.byte() & 1) std::swap(dims[0], dims[1]);
    const std::size_t n = dims[0] * dims[1];
    std::vector<double> d(n);
    std::vector<float> f(n);
    std::vector<std::int16_t> i16(n);
    std::vector<std::uint8_t> u8(n);
    std::vector<char> ch(n, 'a');
    for (std::size_t i = 0; i < n; ++i) {
      const auto b = rd.byte();
      d[i] = b == 255 ? NAN : b == 254 ? INFINITY : (i / dims[0]) * 1.0 + (i % dims[0]) * 0.01 * (b % 3 ? 1 : -1) + b * 1e-4;
      f[i] = static_cast<float>(d[i]);
      i16[i] = static_cast<std::int16_t>(b * 37 - 4000);
      u8[i] = b;
    }
    matvar_t* mv = nullptr;
    if (cls == 0) mv = Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, d.data(), 0);
    if (cls == 1) mv = Mat_VarCreate(name.c_str(), MAT_C_SINGLE, MAT_T_SINGLE, 2, dims, f.data(), 0);
    if (cls == 2) mv = Mat_VarCreate(name.c_str(), MAT_C_INT16, MAT_T_INT16, 2, dims, i16.data(), 0);
    if (cls == 3) mv = Mat_VarCreate(name.c_str(), MAT_C_UINT8, MAT_T_UINT8, 2, dims, u8.data(), 0);
    if (cls == 4) mv = Mat_VarCreate(name.c_str(), MAT_C_CHAR, MAT_T_UINT8, 2, dims, ch.data(), 0);
    if (cls == 5) {
      size_t one[2] = {1, 1};
      const char* fields[] = {"a"};
      mv = Mat_VarCreateStruct(name.c_str(), 2, one, fields, 1);
    }
    if (mv) {
      Mat_VarWrite(m, mv, comp);
      Mat_VarFree(mv);
    }
  }
  Mat_Close(m);
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gmslab;
  std::string_view in(reinterpret_cast<const char*>(data), size);
  static const std::string path = "/tmp/gmslab_mat_fuzz_" + std::to_string(getpid()) + ".mat";
  try {
    CsvColumns cols;
    if (const auto nul = in.find('\0'); nul != std::string_view::npos) {
      cols = parse_column_map(in.substr(0, nul));
      in.remove_prefix(nul + 1);
    }
    Reader rd{in};
    if (!write_mat(path, rd)) return 0;
    const MeasuredRecord r = load_measured_mat(path, cols);
    const std::size_t n = r.size();
    if (n < kMinSamples || r.x.size() != n || r.F.size() != n) __builtin_trap();
    if ((!r.v.empty() && r.v.size() != n) || (!r.Fn.empty() && r.Fn.size() != n)) __builtin_trap();
    if (!finite(r.t) || !finite(r.x) || !finite(r.F) || !finite(r.v) || !finite(r.Fn)) __builtin_trap();
    for (std::size_t i = 1; i < n; ++i)
      if (!(r.t[i] > r.t[i - 1])) __builtin_trap();
    for (const auto& [name, col] : r.extra)
      if (col.size() != n || !finite(col)) __builtin_trap();
  } catch (const InputError&) {
  }
  return 0;
}
