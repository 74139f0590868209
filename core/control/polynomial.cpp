#include "core/control/polynomial.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace gmslab::control {

Poly::Poly(std::vector<double> ascending) : c_(std::move(ascending)) {
  while (!c_.empty() && c_.back() == 0.0) c_.pop_back();
}

Poly Poly::descending(const std::vector<double>& coeffs) {
  return Poly(std::vector<double>(coeffs.rbegin(), coeffs.rend()));
}

Poly Poly::from_roots(const std::vector<cplx>& roots, double lead) {
  std::vector<cplx> c{cplx(lead)};
  for (const cplx& r : roots) {
    std::vector<cplx> n(c.size() + 1, 0.0);
    for (std::size_t i = 0; i < c.size(); ++i) {
      n[i + 1] += c[i];
      n[i] -= r * c[i];
    }
    c = std::move(n);
  }
  std::vector<double> re(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) re[i] = c[i].real();
  return Poly(std::move(re));
}

double Poly::coeff(int i) const {
  return (i >= 0 && i < static_cast<int>(c_.size())) ? c_[static_cast<std::size_t>(i)] : 0.0;
}

std::vector<double> Poly::descending_coeffs() const { return {c_.rbegin(), c_.rend()}; }

int Poly::zeros_at_origin() const {
  int n = 0;
  while (n < static_cast<int>(c_.size()) && c_[static_cast<std::size_t>(n)] == 0.0) ++n;
  return n;
}

double Poly::operator()(double s) const {
  double y = 0.0;
  for (auto it = c_.rbegin(); it != c_.rend(); ++it) y = y * s + *it;
  return y;
}

cplx Poly::operator()(cplx s) const {
  cplx y = 0.0;
  for (auto it = c_.rbegin(); it != c_.rend(); ++it) y = y * s + *it;
  return y;
}

Poly Poly::derivative() const {
  std::vector<double> d;
  for (std::size_t i = 1; i < c_.size(); ++i) d.push_back(static_cast<double>(i) * c_[i]);
  return Poly(std::move(d));
}

namespace {
// Newton polishing on p; keeps a step only when it lowers |p(r)|.
cplx polish(const Poly& p, const Poly& dp, cplx r) {
  double res = std::abs(p(r));
  for (int it = 0; it < 8 && res > 0.0; ++it) {
    const cplx d = dp(r);
    if (d == 0.0) break;
    const cplx next = r - p(r) / d;
    const double rn = std::abs(p(next));
    if (!(rn < res)) break;
    r = next;
    res = rn;
  }
  return r;
}
// Diagonal similarity scaling by powers of 2 (Osborne / LAPACK gebal) so that every row and
// column of the companion matrix have comparable norms. Eigen's EigenSolver does not balance, and
// without it a polynomial with widely spread coefficients (e.g. s^6 + ... + 2e10, a root locus at
// a large gain) gets eigenvalues wrong by O(1) (found by the root-locus continuation test).
void balance(Eigen::MatrixXd& A) {
  const int n = static_cast<int>(A.rows());
  bool changed = true;
  for (int sweep = 0; sweep < 100 && changed; ++sweep) {
    changed = false;
    for (int i = 0; i < n; ++i) {
      double c = 0.0, r = 0.0;
      for (int j = 0; j < n; ++j)
        if (j != i) c += std::abs(A(j, i)), r += std::abs(A(i, j));
      // Zero: nothing to scale. Not finite (a companion matrix of coefficients that overflow):
      // the scaling loops below would never end (inf >= 2 inf), and scaling cannot help.
      if (c == 0.0 || r == 0.0 || !std::isfinite(c) || !std::isfinite(r)) continue;
      double f = 1.0;
      const double s = c + r;
      while (c < 0.5 * r) c *= 2.0, r *= 0.5, f *= 2.0;
      while (c >= 2.0 * r) c *= 0.5, r *= 2.0, f *= 0.5;
      if (c + r < 0.95 * s) {
        changed = true;
        A.row(i) /= f;
        A.col(i) *= f;
      }
    }
  }
}
}  // namespace

std::vector<cplx> Poly::roots() const {
  std::vector<cplx> out;
  const int z = zeros_at_origin();
  for (int i = 0; i < z; ++i) out.emplace_back(0.0, 0.0);
  const Poly q = shift_down(z);
  const int n = q.degree();
  if (n <= 0) return out;
  if (n == 1) {
    out.emplace_back(-q.c_[0] / q.c_[1], 0.0);
    return out;
  }
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, n);
  for (int i = 1; i < n; ++i) C(i, i - 1) = 1.0;
  for (int i = 0; i < n; ++i) C(i, n - 1) = -q.c_[static_cast<std::size_t>(i)] / q.c_.back();
  balance(C);
  Eigen::EigenSolver<Eigen::MatrixXd> es(C, false);
  const Poly dq = q.derivative();
  for (int i = 0; i < n; ++i) {
    cplx r = polish(q, dq, es.eigenvalues()(i));
    if (std::abs(r.imag()) <= 1e-9 * std::abs(r)) r = cplx(r.real(), 0.0);
    out.push_back(r);
  }
  // Make complex roots exact conjugate pairs (polishing may break the symmetry slightly).
  std::vector<bool> paired(out.size(), false);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out[i].imag() <= 0.0 || paired[i]) continue;
    std::size_t best = out.size();
    double bd = 0.0;
    for (std::size_t j = 0; j < out.size(); ++j) {
      if (j == i || paired[j] || out[j].imag() >= 0.0) continue;
      const double d = std::abs(out[j] - std::conj(out[i]));
      if (best == out.size() || d < bd) best = j, bd = d;
    }
    if (best == out.size()) continue;
    const cplx avg = 0.5 * (out[i] + std::conj(out[best]));
    out[i] = avg;
    out[best] = std::conj(avg);
    paired[i] = paired[best] = true;
  }
  std::sort(out.begin(), out.end(), [](cplx a, cplx b) {
    return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
  });
  return out;
}

Poly Poly::operator+(const Poly& o) const {
  std::vector<double> r(std::max(c_.size(), o.c_.size()), 0.0);
  for (std::size_t i = 0; i < c_.size(); ++i) r[i] += c_[i];
  for (std::size_t i = 0; i < o.c_.size(); ++i) r[i] += o.c_[i];
  return Poly(std::move(r));
}

Poly Poly::operator-(const Poly& o) const { return *this + o * -1.0; }

Poly Poly::operator*(const Poly& o) const {
  if (c_.empty() || o.c_.empty()) return {};
  std::vector<double> r(c_.size() + o.c_.size() - 1, 0.0);
  for (std::size_t i = 0; i < c_.size(); ++i)
    for (std::size_t j = 0; j < o.c_.size(); ++j) r[i + j] += c_[i] * o.c_[j];
  return Poly(std::move(r));
}

Poly Poly::operator*(double k) const {
  std::vector<double> r = c_;
  for (double& x : r) x *= k;
  return Poly(std::move(r));
}

Poly Poly::shift_up(int n) const {
  if (c_.empty()) return {};
  std::vector<double> r(static_cast<std::size_t>(n), 0.0);
  r.insert(r.end(), c_.begin(), c_.end());
  return Poly(std::move(r));
}

Poly Poly::shift_down(int n) const {
  if (n >= static_cast<int>(c_.size())) return {};
  return Poly(std::vector<double>(c_.begin() + n, c_.end()));
}

std::vector<double> parse_coefficients(const std::string& text, std::string& why) {
  why.clear();
  std::string t = text;
  std::replace(t.begin(), t.end(), ',', ' ');
  std::istringstream in(t);
  std::vector<double> v;
  std::string tok;
  while (in >> tok) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(tok, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != tok.size() || !std::isfinite(x)) {
      why = "'" + tok + "' is not a finite number; expected coefficients highest power of s first, "
            "separated by spaces or commas, e.g. \"1 2 0\" for s^2 + 2 s";
      return {};
    }
    v.push_back(x);
  }
  if (v.empty()) {
    why = "empty; expected coefficients highest power of s first, e.g. \"1 2 0\" for s^2 + 2 s";
    return {};
  }
  if (std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0; })) {
    why = "all coefficients are zero";
    return {};
  }
  if (const auto d = Poly::descending(v).degree(); d > 40) {
    why = "degree " + std::to_string(d) + " is above the limit 40";
    return {};
  }
  return v;
}

Poly parse_polynomial(const std::string& text, const std::string& what) {
  std::string why;
  const auto v = parse_coefficients(text, why);
  if (!why.empty()) throw InputError(what + " '" + text + "': " + why);
  return Poly::descending(v);
}

std::string to_string(const Poly& p) {
  if (p.is_zero()) return "0";
  std::ostringstream o;
  bool first = true;
  for (int i = p.degree(); i >= 0; --i) {
    const double c = p.coeff(i);
    if (c == 0.0) continue;
    if (!first) o << (c < 0 ? " - " : " + ");
    else if (c < 0) o << "-";
    const double a = std::abs(c);
    if (a != 1.0 || i == 0) o << a << (i > 0 ? " " : "");
    if (i >= 1) o << "s";
    if (i >= 2) o << "^" << i;
    first = false;
  }
  return o.str();
}

}  // namespace gmslab::control
