#include "core/text/format_g10.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace gmslab {

namespace {

constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                               1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                               1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
// 10^j for j in [-14, 32] (the double nearest; only a first guess of the decade, checked by the
// digits).
constexpr int kDecadeLow = -14;
constexpr double kDecade[] = {1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5,
                              1e-4,  1e-3,  1e-2,  1e-1,  1e0,   1e1,  1e2,  1e3,  1e4,  1e5,
                              1e6,   1e7,   1e8,   1e9,   1e10,  1e11, 1e12, 1e13, 1e14, 1e15,
                              1e16,  1e17,  1e18,  1e19,  1e20,  1e21, 1e22, 1e23, 1e24, 1e25,
                              1e26,  1e27,  1e28,  1e29,  1e30,  1e31, 1e32};

constexpr char kPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

char* exact(double x, char* out) {
  return std::to_chars(out, out + kFormatG10MaxChars, x, std::chars_format::general, 10).ptr;
}

// x * 10^s rounded to an integer when that rounding is certain (see the header), else -1.
inline std::int64_t scaled(double x, int s) {
  const double p = s >= 0 ? x * kPow10[s] : x / kPow10[-s];  // < 1e11: fits, truncation is floor
  const auto whole = static_cast<std::int64_t>(p);
  const double frac = p - static_cast<double>(whole);  // exact
  if (std::fabs(frac - 0.5) < 4e-6) return -1;
  return whole + (frac > 0.5 ? 1 : 0);
}

// Five digits of v (< 100000) at d.
inline void five_digits(std::uint32_t v, char* d) {
  const std::uint32_t hi = v / 100, lo = v % 100;  // hi < 1000
  d[0] = static_cast<char>('0' + hi / 100);
  std::memcpy(d + 1, kPairs + 2 * (hi % 100), 2);
  std::memcpy(d + 3, kPairs + 2 * lo, 2);
}

}  // namespace

char* format_g10(double x, char* out) {
  if (!(x != 0.0 && std::isfinite(x))) return exact(x, out);
  const double a = std::fabs(x);
  if (!(a >= 1e-13 && a < 1e31)) return exact(x, out);
  // The decimal exponent k = floor(log10 a): a first guess from the binary exponent and a table,
  // then corrected by the digits (10 digits that round up to 11 are one decade higher).
  std::uint64_t bits = 0;
  std::memcpy(&bits, &a, sizeof bits);
  const int e2 =
      static_cast<int>((bits >> 52) & 0x7ff) - 1022;  // a in [2^(e2-1), 2^e2) (a is normal)
  int k = ((e2 - 1) * 78913) >> 18;  // floor((e2 - 1) log10 2): floor(log10 a) or one less
  if (a >= kDecade[k + 1 - kDecadeLow]) ++k;
  std::int64_t m = 0;
  for (int tries = 0;; ++tries) {
    const int s = 9 - k;
    if (s > 22 || s < -22 || tries > 2) return exact(x, out);
    m = scaled(a, s);
    if (m < 0) return exact(x, out);
    if (m >= 10000000000) {
      ++k;
      continue;
    }
    if (m < 1000000000) {
      --k;
      continue;
    }
    break;
  }
  char d[24] = {};  // the 10 digits, then room for the fixed-size copies below
  five_digits(static_cast<std::uint32_t>(m / 100000), d);
  five_digits(static_cast<std::uint32_t>(m % 100000), d + 5);
  int n = 10;  // significant digits kept: trailing zeros go (no '#' flag)
  while (n > 1 && d[n - 1] == '0') --n;
  char* o = out;
  *o = '-';
  o += x < 0;
  if (k >= -4 && k < 10) {  // fixed notation (%.{9-k}f), trailing zeros removed
    if (k >= 0) {
      const int whole = k + 1;
      std::memcpy(o, d, 10);  // the whole part, then the fraction moved one place right
      o += whole;
      if (n > whole) {
        std::memmove(o + 1, d + whole, 10);
        *o = '.';
        o += 1 + (n - whole);
      }
    } else {
      std::memcpy(o, "0.0000", 6);  // "0." and -k - 1 zeros
      o += 1 - k;
      std::memcpy(o, d, 10);
      o += n;
    }
    return o;
  }
  *o++ = d[0];  // scientific: d.ddde+XX
  std::memcpy(o + 1, d + 1, 9);
  *o = '.';
  o += n > 1 ? n : 0;
  *o++ = 'e';
  *o++ = k < 0 ? '-' : '+';
  const int ek = k < 0 ? -k : k;
  if (ek >= 100) *o++ = static_cast<char>('0' + ek / 100);
  std::memcpy(o, kPairs + 2 * (ek % 100), 2);
  return o + 2;
}

}  // namespace gmslab
