// libFuzzer target: measured-data CSV (core/io/csv.hpp) from arbitrary bytes.
//
// If the input holds a NUL byte, the part before it is an explicit column map
// ("t=time,x=pos_mm,F=F_N", parse_column_map) and the rest is the CSV text. Both must be accepted
// or rejected with InputError. An accepted record must keep its promises: at least kMinSamples
// rows, every column the same length, every value finite, time strictly increasing.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "core/io/csv.hpp"

namespace {
bool finite(const std::vector<double>& c) {
  for (double x : c)
    if (!std::isfinite(x)) return false;
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gmslab;
  std::string_view in(reinterpret_cast<const char*>(data), size);
  try {
    CsvColumns cols;
    if (const auto nul = in.find('\0'); nul != std::string_view::npos) {
      cols = parse_column_map(in.substr(0, nul));
      in.remove_prefix(nul + 1);
    }
    const MeasuredRecord r = parse_measured_csv(in, "fuzz.csv", cols);
    const std::size_t n = r.size();
    if (n < kMinSamples || r.x.size() != n || r.F.size() != n) __builtin_trap();
    if ((!r.v.empty() && r.v.size() != n) || (!r.Fn.empty() && r.Fn.size() != n)) __builtin_trap();
    if (!finite(r.t) || !finite(r.x) || !finite(r.F) || !finite(r.v) || !finite(r.Fn))
      __builtin_trap();
    for (std::size_t i = 1; i < n; ++i)
      if (!(r.t[i] > r.t[i - 1])) __builtin_trap();
    for (const auto& [name, col] : r.extra)
      if (col.size() != n || !finite(col)) __builtin_trap();
  } catch (const InputError&) {
  }
  return 0;
}
