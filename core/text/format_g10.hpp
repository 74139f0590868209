// gmslab core: a double as printf's "%.10g" writes it, byte for byte, at a fraction of the cost
// (the trace CSV's number format, core/io/trace_csv.hpp).
#pragma once

namespace gmslab {

// Longest text format_g10 writes ("-1.234567891e-300"): 17 characters.
inline constexpr int kFormatG10MaxChars = 24;

// Writes `x` at `out` exactly as std::snprintf(out, n, "%.10g", x) would (no terminating NUL) and
// returns the end. `out` must have room for kFormatG10MaxChars characters.
//
// How: the 10 significant digits are x * 10^s rounded to an integer, where 10^s is exact in double
// (|s| <= 22) and the product (or quotient) is rounded once, so it is within 1.2e-6 of the exact
// value; when that is closer than 4e-6 to a rounding boundary (x.5), or |s| > 22, or x is 0, not
// finite or outside [1e-13, 1e31], std::to_chars (printf's rules, exact) writes it instead.
char* format_g10(double x, char* out);

}  // namespace gmslab
