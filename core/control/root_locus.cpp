#include "core/control/root_locus.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/control/assignment.hpp"

namespace gmslab::control {

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_nan(cplx s) { return std::isnan(s.real()) || std::isnan(s.imag()); }

bool sign_ok(double k, bool negative) { return negative ? k < 0.0 : k > 0.0; }

std::vector<LocusPoint> breakaway_points(const TransferFunction& L, bool negative) {
  const Poly b = L.den.derivative() * L.num - L.den * L.num.derivative();
  std::vector<LocusPoint> out;
  if (b.degree() < 1) return out;
  for (const cplx& s : b.roots()) {
    const cplx ns = L.num(s);
    if (std::abs(ns) == 0.0) continue;
    const cplx k = -L.den(s) / ns;
    if (std::abs(k.imag()) > 1e-6 * std::abs(k) || !sign_ok(k.real(), negative)) continue;
    if (std::abs(k.real()) < 1e-12) continue;
    out.push_back({s, k.real()});
  }
  return out;
}

// den(jw) = Dr(w) + j Di(w): real polynomials in w.
void split_jw(const Poly& p, Poly& re, Poly& im) {
  std::vector<double> r(p.ascending().size(), 0.0), i(r.size(), 0.0);
  for (std::size_t n = 0; n < r.size(); ++n) {
    const double c = p.ascending()[n];
    switch (n % 4) {
      case 0: r[n] = c; break;
      case 1: i[n] = c; break;
      case 2: r[n] = -c; break;
      case 3: i[n] = -c; break;
    }
  }
  re = Poly(r);
  im = Poly(i);
}

std::vector<LocusPoint> axis_crossings(const TransferFunction& L, bool negative) {
  Poly dr, di, nr, ni;
  split_jw(L.den, dr, di);
  split_jw(L.num, nr, ni);
  const Poly p = di * nr - dr * ni;
  std::vector<LocusPoint> out;
  if (p.is_zero()) return out;
  for (const cplx& w : p.roots()) {
    if (std::abs(w.imag()) > 1e-9 * std::max(1.0, std::abs(w)) || w.real() < 0.0) continue;
    const cplx s(0.0, w.real());
    const cplx ns = L.num(s);
    if (std::abs(ns) == 0.0) continue;
    const double k = (-L.den(s) / ns).real();
    if (!sign_ok(k, negative)) continue;
    out.push_back({s, k});
  }
  return out;
}

inline double distance_in_view(cplx a, cplx b, const ViewBox& v) {
  if (is_nan(a) || is_nan(b)) return 0.0;
  if (!v.contains(a) && !v.contains(b)) return 0.0;
  auto clamp = [&](cplx s) {
    return cplx(std::clamp(s.real(), v.re_min, v.re_max), std::clamp(s.imag(), v.im_min, v.im_max));
  };
  return std::sqrt(std::norm(clamp(a) - clamp(b)));
}

// Reorders `next` so that next[i] continues prev[i].
// When every prev[i]'s nearest root of `next` is next[i] (the usual case: continued_roots keeps
// each root's identity), the identity is optimal (each row's minimum is on the diagonal, so no
// permutation has a lower sum) and the O(n^3) assignment is skipped.
std::vector<cplx> match(const std::vector<cplx>& prev, const std::vector<cplx>& next) {
  const int n = static_cast<int>(prev.size());
  bool identity = next.size() == prev.size();
  for (int i = 0; i < n && identity; ++i) {
    if (is_nan(prev[i]) || is_nan(next[i])) { identity = false; break; }
    const double own = std::norm(prev[i] - next[i]);
    for (int j = 0; j < n; ++j)
      if (j != i && !(std::norm(prev[i] - next[j]) > own)) { identity = false; break; }
  }
  if (identity) return next;
  double big = 1.0;
  for (const auto& s : prev) if (!is_nan(s)) big = std::max(big, std::abs(s));
  for (const auto& s : next) if (!is_nan(s)) big = std::max(big, std::abs(s));
  big *= 1e3;
  std::vector<double> cost(static_cast<std::size_t>(n * n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const cplx a = prev[i], b = next[j];
      double c = 0.0;
      if (is_nan(a) && is_nan(b)) c = 0.0;
      else if (is_nan(a)) c = big - std::abs(b);
      else if (is_nan(b)) c = big - std::abs(a);
      else c = std::sqrt(std::norm(a - b));  // |a - b| without hypot's overflow care (hot)
      cost[static_cast<std::size_t>(i * n + j)] = c;
    }
  const auto col = solve_assignment(cost, n);
  std::vector<cplx> out(prev.size());
  for (int i = 0; i < n; ++i) out[i] = next[static_cast<std::size_t>(col[i])];
  return out;
}

// The loop's coefficients, padded to one length, with their derivatives: evaluated without
// allocating (continued_roots runs a few hundred times per locus).
struct LocusPolys {
  int n = 0;                        // max(deg den, deg num)
  std::vector<double> den, num;     // ascending, n + 1 entries
  std::vector<double> dden, dnum;   // derivatives, n entries
  explicit LocusPolys(const TransferFunction& L) : n(std::max(L.den.degree(), L.num.degree())) {
    den.assign(static_cast<std::size_t>(n + 1), 0.0);
    num.assign(static_cast<std::size_t>(n + 1), 0.0);
    for (int i = 0; i <= n; ++i) den[i] = L.den.coeff(i), num[i] = L.num.coeff(i);
    dden.assign(static_cast<std::size_t>(std::max(n, 1)), 0.0);
    dnum.assign(dden.size(), 0.0);
    for (int i = 1; i <= n; ++i) dden[i - 1] = i * den[i], dnum[i - 1] = i * num[i];
  }
};

inline cplx horner(const double* a, int deg, cplx z) {  // a[0] + a[1] z + ... + a[deg] z^deg
  double re = a[deg], im = 0.0;
  const double x = z.real(), y = z.imag();
  for (int m = deg - 1; m >= 0; --m) {
    const double t = re * x - im * y + a[m];
    im = re * y + im * x;
    re = t;
  }
  return {re, im};
}
inline cplx inv(cplx b) { const double d = std::norm(b); return {b.real() / d, -b.imag() / d}; }
inline cplx mul(cplx a, cplx b) {  // without the library's NaN recovery (hot; inputs finite)
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}

constexpr double kEps = std::numeric_limits<double>::epsilon();

// c(z) and c'(z) by Horner, with the rounding bound sum |c_i| |z|^i of c(z); true when c(z) is at
// rounding level (|c(z)| <= 16 eps bound: the polynomial's backward error, so a double root at a
// breakaway gain is then as accurate as double precision allows).
inline bool eval_at(const double* c, const double* ac, int n, cplx z, cplx& p, cplx& dp) {
  const double x = z.real(), y = z.imag();
  double pr = c[n], pi = 0.0, dr = 0.0, di = 0.0, bound = ac[n];
  const double r = std::sqrt(x * x + y * y);
  for (int m = n - 1; m >= 0; --m) {
    const double tdr = dr * x - di * y + pr;
    di = dr * y + di * x + pi;
    dr = tdr;
    const double tpr = pr * x - pi * y + c[m];
    pi = pr * y + pi * x;
    pr = tpr;
    bound = bound * r + ac[m];
  }
  p = {pr, pi};
  dp = {dr, di};
  return pr * pr + pi * pi <= (16.0 * kEps * bound) * (16.0 * kEps * bound);
}

// Newton on each root alone (O(n) per step, one division): from a tangent-predicted start it
// converges quadratically in 2-3 steps. A root is done at rounding-level residual or once its
// correction is below 1e-9 relative (the corrected root is then at rounding level). False when a
// root does not converge in 30 steps or a step is not finite; two roots that converge to the same
// root are caught by roots_consistent(). The active roots are stepped in lockstep (Horner over
// the roots innermost): their recurrences are independent, so the CPU overlaps them.
bool newton_roots(const double* c, const double* ac, int n, cplx* z, double scale) {
  int act[64], na = n;
  for (int i = 0; i < n; ++i) act[i] = i;
  double x[64], y[64], r[64], pr[64], pi[64], dr[64], di[64], bd[64];
  for (int it = 0; it < 30 && na > 0; ++it) {
    for (int a = 0; a < na; ++a) {
      const cplx zi = z[act[a]];
      x[a] = zi.real(), y[a] = zi.imag();
      r[a] = std::sqrt(x[a] * x[a] + y[a] * y[a]);
      pr[a] = c[n], pi[a] = 0.0, dr[a] = 0.0, di[a] = 0.0, bd[a] = ac[n];
    }
    for (int m = n - 1; m >= 0; --m) {
      const double cm = c[m], am = ac[m];
      for (int a = 0; a < na; ++a) {
        const double tdr = dr[a] * x[a] - di[a] * y[a] + pr[a];
        di[a] = dr[a] * y[a] + di[a] * x[a] + pi[a];
        dr[a] = tdr;
        const double tpr = pr[a] * x[a] - pi[a] * y[a] + cm;
        pi[a] = pr[a] * y[a] + pi[a] * x[a];
        pr[a] = tpr;
        bd[a] = bd[a] * r[a] + am;
      }
    }
    int keep = 0;
    for (int a = 0; a < na; ++a) {
      const int i = act[a];
      const double lim0 = 16.0 * kEps * bd[a];
      if (pr[a] * pr[a] + pi[a] * pi[a] <= lim0 * lim0) continue;  // done
      const cplx w = mul({pr[a], pi[a]}, inv({dr[a], di[a]}));
      if (!std::isfinite(w.real()) || !std::isfinite(w.imag())) return false;
      z[i] -= w;
      const double lim = 1e-9 * std::max(r[a], 1e-6 * scale);
      if (std::norm(w) > lim * lim) act[keep++] = i;
    }
    na = keep;
  }
  return na == 0;
}

// Aberth-Ehrlich (simultaneous, cubically convergent, roots repel each other so none is found
// twice): O(n^2) per sweep. Same stopping rule per root; false after 40 sweeps.
bool aberth_roots(const double* c, const double* ac, int n, cplx* z, double scale) {
  bool frozen[64] = {};
  int active = n;
  for (int it = 0; it < 40 && active > 0; ++it) {
    for (int i = 0; i < n; ++i) {
      if (frozen[i]) continue;
      const cplx zi = z[i];
      cplx p, dp;
      if (eval_at(c, ac, n, zi, p, dp)) {
        frozen[i] = true, --active;
        continue;
      }
      const cplx ratio = mul(p, inv(dp));
      cplx sum = 0.0;
      for (int j = 0; j < n; ++j)
        if (j != i) sum += inv(zi - z[j]);
      const cplx w = mul(ratio, inv(1.0 - mul(ratio, sum)));
      if (!std::isfinite(w.real()) || !std::isfinite(w.imag())) return false;
      z[i] = zi - w;
      const double lim = 1e-9 * std::max(std::sqrt(std::norm(z[i])), 1e-6 * scale);
      if (std::norm(w) <= lim * lim) frozen[i] = true, --active;
    }
  }
  return active == 0;
}

// Every z_i has a rounding-level residual; this checks they are the n roots and not one found
// twice and another lost: Vieta's first two power sums, sum z = -c_{n-1}/c_n and
// sum z^2 = (c_{n-1}/c_n)^2 - 2 c_{n-2}/c_n, within 1e-6 of sum |z| (|z|^2); no two equal.
bool roots_consistent(const double* c, int n, const cplx* z) {
  cplx s1 = 0.0, s2 = 0.0;
  double m1 = 0.0, m2 = 0.0;
  for (int i = 0; i < n; ++i) {
    s1 += z[i], s2 += mul(z[i], z[i]);
    const double a = std::norm(z[i]);
    m1 += std::sqrt(a), m2 += a;
  }
  const double e1 = -c[n - 1] / c[n];
  const double p2 = e1 * e1 - (n >= 2 ? 2.0 * c[n - 2] / c[n] : 0.0);
  if (std::norm(s1 - e1) > 1e-12 * m1 * m1 + 1e-300) return false;
  if (std::norm(s2 - p2) > 1e-12 * m2 * m2 + 1e-300) return false;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < i; ++j)
      if (z[i] == z[j]) return false;
  return true;
}

// Roots of den + k num continued from `seed0` (the roots at the nearby gain k0) instead of a
// companion eigenproblem. Each root's start is predicted along its tangent dz/dk = -num(z)/P'(z),
// P = den + k0 num (the step limited to 0.3 of its distance to the nearest other root, so roots do
// not swap); then Newton on each root (newton_roots); if that fails or two roots collide
// (roots_consistent), Aberth-Ehrlich from the same starts; if that fails too, closed_loop_poles()
// (eigenvalues). Also eigenvalues when a seed is missing (NaN: a root at infinity) or the degree
// differs (equal order at the infinite gain).
//
// Step check: when `view` is given, no predicted step had to be limited (no two roots close, so
// the tangents are reliable) and a root's predicted move inside the view exceeds 1.1 tol, the gain
// is too far: nothing is solved, the result is empty and *predicted_jump says how far it went.
std::vector<cplx> continued_roots(const TransferFunction& L, const LocusPolys& W, double k,
                                  const std::vector<cplx>& seed0, double k0,
                                  const ViewBox* view = nullptr, double tol = 0.0,
                                  double* predicted_jump = nullptr) {
  const int N = W.n;
  double c[64];
  int n = N;
  if (N + 1 > 64) return closed_loop_poles(L, k);
  for (int i = 0; i <= N; ++i) c[i] = W.den[i] + k * W.num[i];
  while (n >= 0 && c[n] == 0.0) --n;
  if (n < 1 || n != N || static_cast<int>(seed0.size()) != n ||
      std::any_of(seed0.begin(), seed0.end(), is_nan))
    return closed_loop_poles(L, k);
  // Predictor, Horner over the roots innermost (independent recurrences, overlapped by the CPU):
  // num(z), den'(z), num'(z) at every seed.
  double x[64], y[64], nr[64], ni[64], ddr[64], ddi[64], dnr[64], dni[64];
  for (int i = 0; i < n; ++i) {
    x[i] = seed0[i].real(), y[i] = seed0[i].imag();
    nr[i] = W.num[N], ni[i] = 0.0, ddr[i] = W.dden[N - 1], ddi[i] = 0.0, dnr[i] = W.dnum[N - 1], dni[i] = 0.0;
  }
  for (int m = N - 1; m >= 0; --m) {
    const double a = W.num[m];
    for (int i = 0; i < n; ++i) {
      const double t = nr[i] * x[i] - ni[i] * y[i] + a;
      ni[i] = nr[i] * y[i] + ni[i] * x[i];
      nr[i] = t;
    }
    if (m == 0) break;
    const double b = W.dden[m - 1], e = W.dnum[m - 1];
    for (int i = 0; i < n; ++i) {
      const double t = ddr[i] * x[i] - ddi[i] * y[i] + b;
      ddi[i] = ddr[i] * y[i] + ddi[i] * x[i];
      ddr[i] = t;
      const double u = dnr[i] * x[i] - dni[i] * y[i] + e;
      dni[i] = dnr[i] * y[i] + dni[i] * x[i];
      dnr[i] = u;
    }
  }
  cplx z0[64];
  double scale = 0.0, pjump = 0.0;
  bool limited = false;
  for (int i = 0; i < n; ++i) {
    const cplx zi = seed0[i];
    z0[i] = zi;
    const cplx d(ddr[i] + k0 * dnr[i], ddi[i] + k0 * dni[i]);
    if (std::norm(d) == 0.0) {
      limited = true;
      continue;
    }
    cplx step = mul({nr[i], ni[i]}, inv(d)) * (k0 - k);
    if (view) pjump = std::max(pjump, distance_in_view(zi, zi + step, *view));
    double near = std::numeric_limits<double>::infinity();
    for (int j = 0; j < n; ++j)
      if (j != i) near = std::min(near, std::norm(seed0[j] - zi));
    const double lim = 0.09 * near;  // (0.3 |distance|)^2
    if (std::norm(step) > lim) step *= std::sqrt(lim / std::norm(step)), limited = true;
    if (std::isfinite(step.real()) && std::isfinite(step.imag())) z0[i] += step;
    else limited = true;
    scale = std::max(scale, std::norm(z0[i]));
  }
  if (view && !limited && pjump > 1.1 * tol) {
    if (predicted_jump) *predicted_jump = pjump;
    return {};
  }
  scale = std::max(std::sqrt(scale), 1e-300);
  for (int i = 0; i < n; ++i)  // separate coincident seeds (a double root at a breakaway gain)
    for (int j = 0; j < i; ++j)
      if (std::norm(z0[i] - z0[j]) < 1e-18 * scale * scale)
        z0[i] += cplx(1e-7 * scale * (i + 1), 1e-7 * scale);
  double ac[64];
  for (int i = 0; i <= n; ++i) ac[i] = std::abs(c[i]);
  cplx z[64];
  std::copy(z0, z0 + n, z);
  bool ok = newton_roots(c, ac, n, z, scale) && roots_consistent(c, n, z);
  if (!ok) {
    std::copy(z0, z0 + n, z);
    ok = aberth_roots(c, ac, n, z, scale) && roots_consistent(c, n, z);
  }
  if (!ok) return closed_loop_poles(L, k);
  // Exact roots at the origin (the lowest coefficients zero, e.g. a type-1 loop's pole at s = 0
  // with a zero there): the roots nearest the origin are set to 0, as Poly::roots() gives them.
  for (int zc = 0; zc < n && c[zc] == 0.0; ++zc) {
    bool taken[64] = {};
    int best = -1;
    for (int t = 0; t <= zc; ++t) {  // the (zc + 1)-th nearest root to the origin
      best = -1;
      for (int i = 0; i < n; ++i)
        if (!taken[i] && (best < 0 || std::norm(z[i]) < std::norm(z[best]))) best = i;
      taken[best] = true;
    }
    z[best] = 0.0;
  }
  std::vector<cplx> out(z, z + n);
  for (cplx& r : out)
    if (std::abs(r.imag()) <= 1e-9 * std::sqrt(std::norm(r))) r = cplx(r.real(), 0.0);
  return out;
}

}  // namespace

std::vector<LocusPoint> imaginary_axis_crossings(const TransferFunction& L, bool negative) {
  return axis_crossings(L, negative);
}

std::vector<cplx> closed_loop_poles(const TransferFunction& L, double k) {
  const Poly c = L.den + L.num * k;
  std::vector<cplx> r = c.is_zero() ? std::vector<cplx>{} : c.roots();
  const int n = std::max(L.den.degree(), L.num.degree());
  while (static_cast<int>(r.size()) < n) r.emplace_back(kNaN, kNaN);
  return r;
}

cplx gain_at(const TransferFunction& L, cplx s) { return -L.den(s) / L.num(s); }

ViewBox view_around(const std::vector<cplx>& pts) {
  double lo = 0.0, hi = 0.0, im = 0.0;
  for (const auto& s : pts) {
    if (is_nan(s) || !std::isfinite(std::abs(s))) continue;
    lo = std::min(lo, s.real());
    hi = std::max(hi, s.real());
    im = std::max(im, std::abs(s.imag()));
  }
  const double c = 0.5 * (lo + hi);
  double r = std::max(0.5 * (hi - lo), im);
  if (r <= 0.0) r = 1.0;
  r *= 1.3;
  return {c - r, c + r, -r, r};
}

namespace {
// auto_view from already computed poles, zeros and key points of the 180-degree locus.
ViewBox auto_view_of(const TransferFunction& L, const std::vector<cplx>& extra,
                     const std::vector<cplx>& poles, const std::vector<cplx>& zeros,
                     const std::vector<LocusPoint>& breakaways,
                     const std::vector<LocusPoint>& crossings) {
  std::vector<cplx> pts = extra;
  for (const auto& s : poles) pts.push_back(s);
  for (const auto& s : zeros) pts.push_back(s);
  for (const auto& p : breakaways) pts.push_back(p.s);
  for (const auto& p : crossings) pts.push_back(p.s);
  const int q = L.relative_degree();
  if (q > 0) {
    double c = 0.0;
    for (const auto& s : poles) c += s.real();
    for (const auto& s : zeros) c -= s.real();
    pts.emplace_back(c / q, 0.0);
  }
  return view_around(pts);
}
}  // namespace

ViewBox auto_view(const TransferFunction& L, const std::vector<cplx>& extra) {
  std::vector<cplx> pts = extra;
  for (const auto& s : L.poles()) pts.push_back(s);
  for (const auto& s : L.zeros()) pts.push_back(s);
  for (const auto& p : breakaway_points(L, false)) pts.push_back(p.s);
  for (const auto& p : axis_crossings(L, false)) pts.push_back(p.s);
  const int q = L.relative_degree();
  if (q > 0) {
    double c = 0.0;
    for (const auto& s : L.poles()) c += s.real();
    for (const auto& s : L.zeros()) c -= s.real();
    pts.emplace_back(c / q, 0.0);
  }
  return view_around(pts);
}

RootLocus root_locus(const TransferFunction& L, const LocusOptions& opt) {
  L.check_proper("root locus");
  RootLocus rl;
  rl.negative = opt.negative;
  rl.poles = L.poles();
  rl.zeros = L.zeros();
  const int q = L.relative_degree();
  const double sgn = opt.negative ? -1.0 : 1.0;
  if (q > 0) {
    double c = 0.0;
    for (const auto& s : rl.poles) c += s.real();
    for (const auto& s : rl.zeros) c -= s.real();
    rl.centroid = c / q;
    for (int l = 0; l < q; ++l)
      rl.asymptote_angles.push_back((opt.negative ? 2.0 * l : 2.0 * l + 1.0) * std::numbers::pi / q);
  } else {
    const double kinf = -L.den.lead() / L.num.lead();
    if (sign_ok(kinf, opt.negative)) rl.infinite_gain = kinf;
  }
  rl.breakaways = breakaway_points(L, opt.negative);
  rl.crossings = axis_crossings(L, opt.negative);
  if (opt.view) {
    rl.view = *opt.view;
  } else if (!opt.negative) {
    rl.view = auto_view_of(L, {}, rl.poles, rl.zeros, rl.breakaways, rl.crossings);
  } else {
    rl.view = auto_view(L);
  }

  // Gain scale: |k| at which the asymptotic roots reach the view's far edge.
  const double rf = std::max({std::abs(rl.view.re_min), std::abs(rl.view.re_max),
                              std::abs(rl.view.im_max), 1e-12});
  const double k_mid = std::abs(L.den.lead() / L.num.lead()) * std::pow(rf, q);
  std::vector<double> gains{0.0};
  double k_hi = k_mid * 1e6;
  for (const auto& p : rl.breakaways) k_hi = std::max(k_hi, 100.0 * std::abs(p.k));
  for (const auto& p : rl.crossings) k_hi = std::max(k_hi, 100.0 * std::abs(p.k));
  for (double g : opt.extra_gains) if (sign_ok(g, opt.negative)) k_hi = std::max(k_hi, 10 * std::abs(g));
  const double k_lo = k_mid * 1e-8;
  const int base = 100;
  for (int i = 0; i < base; ++i)
    gains.push_back(sgn * k_lo * std::pow(k_hi / k_lo, static_cast<double>(i) / (base - 1)));
  for (const auto& p : rl.breakaways) gains.push_back(p.k);
  for (const auto& p : rl.crossings) gains.push_back(p.k);
  if (rl.infinite_gain) gains.push_back(*rl.infinite_gain);
  for (double g : opt.extra_gains) if (sign_ok(g, opt.negative)) gains.push_back(g);
  std::sort(gains.begin(), gains.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  gains.erase(std::unique(gains.begin(), gains.end()), gains.end());

  // Walk the gains; split an interval while a branch jumps too far inside the view.
  const double tol = opt.max_jump * rl.view.width();
  // Roots at each gain are continued from the last accepted gain's roots (continued_roots).
  std::vector<double> stack(gains.rbegin(), gains.rend() - 1);
  const LocusPolys W(L);
  std::vector<cplx> prev = rl.poles;  // the roots at k = 0
  while (prev.size() < static_cast<std::size_t>(W.n)) prev.emplace_back(kNaN, kNaN);
  const std::size_t nb = prev.size();
  rl.branches.assign(nb, {});
  auto push = [&](double k, const std::vector<cplx>& r) {
    rl.gains.push_back(k);
    for (std::size_t b = 0; b < nb; ++b) rl.branches[b].push_back(r[b]);
  };
  push(0.0, prev);
  double k_prev = 0.0;
  while (!stack.empty()) {
    const double k = stack.back();
    const bool can_split = static_cast<int>(rl.gains.size() + stack.size()) < opt.max_samples &&
                           std::abs(k - k_prev) > 1e-12 * std::abs(k);
    double jump = 0.0;
    std::vector<cplx> r = continued_roots(L, W, k, prev, k_prev, can_split ? &rl.view : nullptr, tol, &jump);
    std::vector<cplx> m;
    if (!r.empty()) {
      m = match(prev, r);
      jump = 0.0;
      for (std::size_t b = 0; b < nb; ++b) jump = std::max(jump, distance_in_view(prev[b], m[b], rl.view));
    }
    if (jump > tol && can_split) {
      // Split where the move is expected to be 0.7 tol (moves grow about linearly with log k
      // over a short interval), between 5 % and half of the interval in log k.
      const double f = std::clamp(0.7 * tol / jump, 0.05, 0.5);
      const double kmid = (k_prev == 0.0) ? 0.1 * k
                          : (k_prev * k > 0.0 ? k_prev * std::pow(k / k_prev, f)
                                              : 0.5 * (k_prev + k));
      stack.push_back(kmid);
      continue;
    }
    stack.pop_back();
    push(k, m);
    prev = std::move(m);
    k_prev = k;
  }
  return rl;
}

}  // namespace gmslab::control
