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

// The 10 significant digits m (in [10^9, 10^10)) and the decimal exponent k of |x| when the
// scaled path is certain of them (see the header), else false.
bool decimal(double a, std::int64_t& m, int& k) {
  if (!(a >= 1e-13 && a < 1e31)) return false;  // also 0, infinities and NaN
  // The decimal exponent k = floor(log10 a): a first guess from the binary exponent and a table,
  // then corrected by the digits (10 digits that round up to 11 are one decade higher).
  std::uint64_t bits = 0;
  std::memcpy(&bits, &a, sizeof bits);
  const int e2 =
      static_cast<int>((bits >> 52) & 0x7ff) - 1022;  // a in [2^(e2-1), 2^e2) (a is normal)
  k = ((e2 - 1) * 78913) >> 18;  // floor((e2 - 1) log10 2): floor(log10 a) or one less
  if (a >= kDecade[k + 1 - kDecadeLow]) ++k;
  for (int tries = 0;; ++tries) {
    const int s = 9 - k;
    if (s > 22 || s < -22 || tries > 2) return false;
    m = scaled(a, s);
    if (m < 0) return false;
    if (m >= 10000000000) {
      ++k;
      continue;
    }
    if (m < 1000000000) {
      --k;
      continue;
    }
    return true;
  }
}

// The text of -m * 10^(k-9) (when `negative`) or m * 10^(k-9) in %.10g at `out`; returns its end.
char* layout(bool negative, std::int64_t m, int k, char* out) {
  char d[24] = {};  // the 10 digits, then room for the fixed-size copies below
  five_digits(static_cast<std::uint32_t>(m / 100000), d);
  five_digits(static_cast<std::uint32_t>(m % 100000), d + 5);
  int n = 10;  // significant digits kept: trailing zeros go (no '#' flag)
  while (n > 1 && d[n - 1] == '0') --n;
  char* o = out;
  *o = '-';
  o += negative;
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

// 10^-s for s in [0, 22] (the double nearest).
constexpr double kPow10Neg[23] = {1e0,   1e-1,  1e-2,  1e-3,  1e-4,  1e-5,  1e-6,  1e-7,
                                  1e-8,  1e-9,  1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15,
                                  1e-16, 1e-17, 1e-18, 1e-19, 1e-20, 1e-21, 1e-22};

}  // namespace

char* format_g10(double x, char* out) {
  std::int64_t m = 0;
  int k = 0;
  if (!decimal(std::fabs(x), m, k)) return exact(x, out);
  return layout(x < 0, m, k, out);
}

char* format_g10_remember(double x, char* out, G10Last& last) {
  std::int64_t m = 0;
  int k = 0;
  char* end = nullptr;
  const double a = std::fabs(x);
  bool known = false;
  if (a >= last.dlo && a < last.dhi) {  // the decade of the column's last number, most likely
    k = last.k;
    m = scaled(a, 9 - k);
    known = m >= 1000000000 && m < 10000000000;  // else another decade, or uncertain
  }
  if (known || decimal(a, m, k)) {
    last.k = k;
    last.dlo = kDecade[k - kDecadeLow];
    last.dhi = kDecade[k + 1 - kDecadeLow];
    end = layout(x < 0, m, k, out);
    // |x| has this text while |x| * 10^s rounds to m: inside (m - 0.5, m + 0.5) * 10^-s, less a
    // margin of 1e-5 in units of the 10th digit, more than the error of computing the bounds:
    // m -+ (0.5 - 1e-5) is rounded (< 1e10: 0.95e-6), times 10^-s (the nearest double) rounded
    // again (2.2e-16 relative: 2.2e-6).
    const int s = 9 - k;
    const double f = s >= 0 ? kPow10Neg[s] : kPow10[-s];
    const double lo = (static_cast<double>(m) - (0.5 - 1e-5)) * f;
    const double hi = (static_cast<double>(m) + (0.5 - 1e-5)) * f;
    last.lo = x < 0 ? -hi : lo;
    last.hi = x < 0 ? -lo : hi;
  } else {
    end = exact(x, out);
    last.lo = last.hi = 0.0;  // empty: never taken for another value
    last.dlo = last.dhi = 0.0;
  }
  last.text = out;
  last.len = static_cast<int>(end - out);
  return end;
}

}  // namespace gmslab
