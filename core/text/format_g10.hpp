// gmslab core: a double as printf's "%.10g" writes it, byte for byte, at a fraction of the cost
// (the trace CSV's number format, core/io/trace_csv.hpp).
#pragma once

#include <cstring>

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

// A column's last number as format_g10_cached wrote it: where its text is (in the caller's
// buffer) and the open interval (lo, hi) of the values with that same text (empty at first, and
// after a value std::to_chars wrote).
struct G10Last {
  double lo = 0.0, hi = 0.0;
  const char* text = nullptr;
  int len = 0;
  // The decade of that number: [dlo, dhi) about [10^k, 10^(k+1)) (empty at first): the next
  // number of the column in it is scaled by 10^(9-k) at once, the digits checking the guess.
  int k = 0;
  double dlo = 0.0, dhi = 0.0;
};
// format_g10(x, out), and `last` describes x afterwards.
char* format_g10_remember(double x, char* out, G10Last& last);
// format_g10(x, out) for a column whose values often repeat their text (a constant parameter, a
// saturated element force): when x lies in last's interval, the text at last.text is copied and
// nothing is computed. The text last.text points at (the column's previous number) must still be
// there, with kFormatG10MaxChars readable characters from it, not overlapping `out`'s
// kFormatG10MaxChars (a CSV row apart). Copies kFormatG10MaxChars characters: `out` needs that
// room.
inline char* format_g10_cached(double x, char* out, G10Last& last) {
  if (x > last.lo && x < last.hi) {
    std::memcpy(out, last.text, kFormatG10MaxChars);
    last.text = out;
    return out + last.len;
  }
  return format_g10_remember(x, out, last);
}

}  // namespace gmslab
