// gmslab core/control: real polynomials in s.
//
//   p(s) = c[0] + c[1] s + ... + c[n] s^n     (coefficients stored lowest power first)
//
// Roots: eigenvalues of the balanced companion matrix (Eigen), then each root polished by Newton steps on
// the original polynomial (kept only when the residual |p(r)| drops); exact zero roots (trailing
// zero coefficients) are split off first, so a type-n plant's poles at the origin are exact.
// Complex roots come in conjugate pairs; roots whose imaginary part is below 1e-9 |r| are made real.
// Coefficients are dimensionless here; a transfer function gives them their units.
#pragma once

#include <complex>
#include <string>
#include <vector>

namespace gmslab::control {

using cplx = std::complex<double>;

class Poly {
 public:
  Poly() = default;
  explicit Poly(std::vector<double> ascending);  // c[0] + c[1] s + ...; trailing zeros trimmed
  // Highest power first, as written by hand ("1 2 0" = s^2 + 2 s).
  static Poly descending(const std::vector<double>& coeffs);
  static Poly from_roots(const std::vector<cplx>& roots, double lead = 1.0);  // real if conj pairs

  int degree() const { return static_cast<int>(c_.size()) - 1; }  // -1 for the zero polynomial
  bool is_zero() const { return c_.empty(); }
  double lead() const { return c_.empty() ? 0.0 : c_.back(); }
  double coeff(int i) const;  // 0 beyond the degree
  const std::vector<double>& ascending() const { return c_; }
  std::vector<double> descending_coeffs() const;
  // Number of roots at s = 0 (lowest zero coefficients).
  int zeros_at_origin() const;

  double operator()(double s) const;
  cplx operator()(cplx s) const;
  Poly derivative() const;
  std::vector<cplx> roots() const;

  Poly operator+(const Poly& o) const;
  Poly operator-(const Poly& o) const;
  Poly operator*(const Poly& o) const;
  Poly operator*(double k) const;
  Poly shift_up(int n) const;    // times s^n
  Poly shift_down(int n) const;  // divided by s^n (drops the n lowest coefficients)

 private:
  std::vector<double> c_;
};

// Parses a coefficient list "1 2 0" or "1, 2, 0" (highest power first). Throws InputError naming
// `what` (e.g. "--den") when a token is not a finite number or the list is empty / all zero.
// The coefficients of `text` (highest power first, separated by spaces or commas), or empty with
// `why` saying what is wrong (not a finite number, empty, all zero, degree above 40).
std::vector<double> parse_coefficients(const std::string& text, std::string& why);
Poly parse_polynomial(const std::string& text, const std::string& what);
std::string to_string(const Poly& p);  // "s^2 + 2 s" style

}  // namespace gmslab::control
