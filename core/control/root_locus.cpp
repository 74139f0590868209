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

double distance_in_view(cplx a, cplx b, const ViewBox& v) {
  if (is_nan(a) || is_nan(b)) return 0.0;
  if (!v.contains(a) && !v.contains(b)) return 0.0;
  auto clamp = [&](cplx s) {
    return cplx(std::clamp(s.real(), v.re_min, v.re_max), std::clamp(s.imag(), v.im_min, v.im_max));
  };
  return std::sqrt(std::norm(clamp(a) - clamp(b)));
}

// Reorders `next` so that next[i] continues prev[i].
std::vector<cplx> match(const std::vector<cplx>& prev, const std::vector<cplx>& next) {
  const int n = static_cast<int>(prev.size());
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

// Roots of den + k num continued from `seed` (the roots at a nearby gain) by Aberth-Ehrlich
// iterations: a few O(n^2) sweeps instead of a companion eigenproblem. Falls back to
// closed_loop_poles() (eigenvalues) when a seed is missing (NaN: a root at infinity), the degree
// differs, or the iteration does not converge in 40 sweeps (converged: every correction below 1e-9
// relative; Aberth converges cubically, so the corrected roots are then at rounding level).
std::vector<cplx> continued_roots(const TransferFunction& L, double k, const std::vector<cplx>& seed0,
                                  double k0) {
  const Poly c = L.den + L.num * k;
  // Predictor: each root moved along its tangent dz/dk = -num(z) / P'(z), P = den + k0 num, over
  // k - k0 (at most 0.3 of its distance to the nearest other root, so roots do not swap).
  std::vector<cplx> seed = seed0;
  if (std::none_of(seed0.begin(), seed0.end(), is_nan)) {
    const Poly P = L.den + L.num * k0;
    const Poly dP = P.derivative();
    for (std::size_t i = 0; i < seed0.size(); ++i) {
      const cplx d = dP(seed0[i]);
      if (std::norm(d) == 0.0) continue;
      cplx step = -L.num(seed0[i]) * (k - k0) / d;
      double near = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < seed0.size(); ++j)
        if (j != i) near = std::min(near, std::norm(seed0[j] - seed0[i]));
      const double lim = 0.09 * near;  // (0.3 |distance|)^2
      if (std::norm(step) > lim) step *= std::sqrt(lim / std::norm(step));
      if (std::isfinite(step.real()) && std::isfinite(step.imag())) seed[i] += step;
    }
  }
  const int n = c.degree();
  if (n < 1 || static_cast<int>(seed.size()) != n || std::any_of(seed.begin(), seed.end(), is_nan))
    return closed_loop_poles(L, k);
  const auto& a = c.ascending();
  double scale = 0.0;
  for (const cplx& z : seed) scale = std::max(scale, std::abs(z));
  scale = std::max(scale, 1e-300);
  std::vector<cplx> z = seed;
  for (int i = 0; i < n; ++i)  // separate coincident seeds (a double root at a breakaway gain)
    for (int j = 0; j < i; ++j)
      if (std::abs(z[i] - z[j]) < 1e-9 * scale) z[i] += cplx(1e-7 * scale * (i + 1), 1e-7 * scale);
  bool done = false;
  for (int it = 0; it < 40 && !done; ++it) {
    done = true;
    for (int i = 0; i < n; ++i) {
      cplx p = a.back(), dp = 0.0;
      for (int m = n - 1; m >= 0; --m) dp = dp * z[i] + p, p = p * z[i] + a[static_cast<std::size_t>(m)];
      if (p == 0.0) continue;
      // Divisions as conj(b) / |b|^2 (no overflow guards needed at these magnitudes; a
      // non-finite result falls back below): 3x faster than the library's complex division.
      const auto inv = [](cplx b) { return std::conj(b) / std::norm(b); };
      const cplx ratio = p * inv(dp);
      cplx sum = 0.0;
      for (int j = 0; j < n; ++j)
        if (j != i) sum += inv(z[i] - z[j]);
      const cplx w = ratio * inv(1.0 - ratio * sum);
      if (!std::isfinite(w.real()) || !std::isfinite(w.imag())) return closed_loop_poles(L, k);
      z[i] -= w;
      const double lim = 1e-9 * std::max(std::norm(z[i]) > 0 ? std::sqrt(std::norm(z[i])) : 0.0, 1e-6 * scale);
      if (std::norm(w) > lim * lim) done = false;
    }
  }
  if (!done) return closed_loop_poles(L, k);
  for (cplx& r : z)
    if (std::abs(r.imag()) <= 1e-9 * std::abs(r)) r = cplx(r.real(), 0.0);
  const int m = std::max(L.den.degree(), L.num.degree());
  while (static_cast<int>(z.size()) < m) z.emplace_back(kNaN, kNaN);
  return z;
}

}  // namespace

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
  rl.view = opt.view ? *opt.view : auto_view(L);

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
  std::vector<cplx> prev = closed_loop_poles(L, 0.0);
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
    std::vector<cplx> m = match(prev, continued_roots(L, k, prev, k_prev));
    double jump = 0.0;
    for (std::size_t b = 0; b < nb; ++b) jump = std::max(jump, distance_in_view(prev[b], m[b], rl.view));
    const bool can_split = static_cast<int>(rl.gains.size() + stack.size()) < opt.max_samples &&
                           std::abs(k - k_prev) > 1e-12 * std::abs(k);
    if (jump > tol && can_split) {
      const double kmid = (k_prev == 0.0) ? 0.1 * k
                          : (k_prev * k > 0.0 ? std::copysign(std::sqrt(k_prev * k), k)
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
