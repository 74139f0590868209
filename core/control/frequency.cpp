#include "core/control/frequency.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "core/error.hpp"

namespace gmslab::control {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// p(jw) = re(u) + j w im(u), u = w^2.
struct Split {
  Poly re, im;
};
Split split(const Poly& p) {
  std::vector<double> re, im;
  const auto& c = p.ascending();
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double sgn = ((k / 2) % 2 == 0) ? 1.0 : -1.0;
    (k % 2 == 0 ? re : im).push_back(sgn * c[k]);
  }
  return {Poly(re), Poly(im)};
}
Poly abs2(const Split& s) { return s.re * s.re + (s.im * s.im).shift_up(1); }

// Real roots u > 0 of q, each polished by Newton steps on q. The variable is scaled to the
// geometric mean of the root magnitudes first and coefficients below 1e-12 of the largest
// (cancellation residue of a difference of squares) are dropped.
std::vector<double> positive_roots(const Poly& q0) {
  std::vector<double> out;
  if (q0.degree() < 1) return out;
  const Poly q = q0.shift_down(q0.zeros_at_origin());
  const int n = q.degree();
  if (n < 1) return out;
  const double sigma = std::pow(std::abs(q.coeff(0) / q.lead()), 1.0 / n);
  std::vector<double> c(q.ascending());
  double big = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) c[k] *= std::pow(sigma, static_cast<double>(k)), big = std::max(big, std::abs(c[k]));
  for (double& x : c)
    if (std::abs(x) < 1e-12 * big) x = 0.0;
  const Poly qs(c);
  const Poly dq = q.derivative();
  for (const cplx& r : qs.roots()) {
    if (std::abs(r.imag()) > 1e-6 * std::abs(r) || !(r.real() > 0.0)) continue;
    double u = r.real() * sigma;
    for (int it = 0; it < 6; ++it) {  // Newton on the unscaled polynomial, kept while it helps
      const double d = dq(u);
      if (d == 0.0) break;
      const double next = u - q(u) / d;
      if (!(next > 0.0) || !(std::abs(q(next)) < std::abs(q(u)))) break;
      u = next;
    }
    out.push_back(u);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end(), [](double a, double b) { return std::abs(a - b) <= 1e-9 * b; }),
            out.end());
  return out;
}

// The factors of H: gain, zeros, poles (computed once, then the phase is continuous in w).
struct Factored {
  double gain_sign = 1.0;  // sign of lead(num) / lead(den)
  std::vector<cplx> zeros, poles;
  explicit Factored(const TransferFunction& H)
      : gain_sign(H.num.lead() / H.den.lead() < 0 ? -1.0 : 1.0), zeros(H.zeros()), poles(H.poles()) {}
  double phase(double w) const {
    double a = gain_sign < 0 ? kPi : 0.0;
    const cplx s(0.0, w);
    for (const cplx& z : zeros) a += std::arg(s - z);
    for (const cplx& p : poles) a -= std::arg(s - p);
    return a;
  }
};

double wrap180(double deg) {
  double x = std::fmod(deg + 180.0, 360.0);
  if (x <= 0.0) x += 360.0;
  return x - 180.0;
}

double cauchy_bound(const Poly& p) {
  if (p.degree() < 1) return 0.0;
  double m = 0.0;
  for (int i = 0; i < p.degree(); ++i) m = std::max(m, std::abs(p.coeff(i) / p.lead()));
  return 1.0 + m;
}

void check(const TransferFunction& L) { L.check_proper("frequency response"); }
}  // namespace

double continuous_phase(const TransferFunction& H, double w) { return Factored(H).phase(w); }
std::vector<double> continuous_phase(const TransferFunction& H, const std::vector<double>& w) {
  const Factored f(H);
  std::vector<double> out;
  out.reserve(w.size());
  for (double x : w) out.push_back(f.phase(x));
  return out;
}

Margins margins(const TransferFunction& L) {
  check(L);
  Margins m;
  const Split N = split(L.num), D = split(L.den);
  for (double u : positive_roots(abs2(N) - abs2(D))) m.gain_crossovers.push_back(std::sqrt(u));
  const Poly im = N.im * D.re - N.re * D.im;  // Im(N conj D) / w
  const Poly re = N.re * D.re + (N.im * D.im).shift_up(1);
  for (double u : positive_roots(im))
    if (re(u) < 0.0) m.phase_crossovers.push_back(std::sqrt(u));
  const Factored f(L);
  m.phase_margin = kInf;
  m.gain_crossover = kNaN;
  for (double w : m.gain_crossovers) {
    const double pm = wrap180(180.0 + f.phase(w) * 180.0 / kPi);
    if (pm < m.phase_margin) m.phase_margin = pm, m.gain_crossover = w;
  }
  m.gain_margin = kInf;
  m.gain_margin_db = kInf;
  m.phase_crossover = kNaN;
  for (double w : m.phase_crossovers) {
    const double gm = 1.0 / std::abs(L(cplx(0.0, w)));
    const double db = 20.0 * std::log10(gm);
    if (std::abs(db) < std::abs(m.gain_margin_db)) m.gain_margin = gm, m.gain_margin_db = db, m.phase_crossover = w;
  }
  return m;
}

Nyquist nyquist_count(const TransferFunction& L) {
  check(L);
  Nyquist ny;
  const std::vector<cplx> poles = L.poles();
  double scale = 0.0;
  for (const cplx& p : poles) scale = std::max(scale, std::abs(p));
  for (const cplx& z : L.zeros()) scale = std::max(scale, std::abs(z));
  if (scale == 0.0) scale = 1.0;
  std::vector<double> axis;  // imaginary parts of the poles on the axis
  for (const cplx& p : poles) {
    if (std::abs(p.real()) <= 1e-9 * std::max(1.0, std::abs(p))) {
      ++ny.axis_poles;
      if (std::none_of(axis.begin(), axis.end(), [&](double w) { return std::abs(w - p.imag()) <= 1e-9 * scale; }))
        axis.push_back(p.imag());
    } else if (p.real() > 0.0) {
      ++ny.open_rhp_poles;
    }
  }
  std::sort(axis.begin(), axis.end());
  // Indentation radius: well inside the nearest other open-loop root.
  const std::vector<cplx> zeros = L.zeros();
  std::vector<double> eps(axis.size(), 1e-3 * scale);
  for (std::size_t k = 0; k < axis.size(); ++k) {
    const cplx c(0.0, axis[k]);
    for (const auto* set : {&poles, &zeros})
      for (const cplx& r : *set) {
        const double d = std::abs(r - c);
        if (d > 1e-9 * scale) eps[k] = std::min(eps[k], 1e-3 * d);
      }
    // Near a pole of order m at c, L ~ g / (s - c)^m: closed-loop roots lie near |s - c| =
    // |g|^(1/m); the indentation stays well inside that radius so they are all on its right.
    int order = 0;
    cplx g = L.num(c) / L.den.lead();
    for (const cplx& p : poles) {
      if (std::abs(p - c) <= 1e-9 * scale) ++order;
      else g /= (c - p);
    }
    if (order > 0 && std::abs(g) > 0.0) eps[k] = std::min(eps[k], 1e-3 * std::pow(std::abs(g), 1.0 / order));
  }
  const double R = 10.0 * std::max({cauchy_bound(L.den + L.num), cauchy_bound(L.den), scale, 1.0});

  // Winding of f = 1 + L along a path s(t), t in [0, 1], refined where arg f moves > 0.3 rad.
  const auto f = [&](cplx s) { return 1.0 + L.num(s) / L.den(s); };
  // A non-finite f (coefficients near the double range overflow) or a path that needs more than
  // kMaxEvaluations points cannot be counted: the count is then marked marginal (not stable),
  // instead of refining every segment to the depth limit (2^48 points: the fuzzer's timeout).
  constexpr long kMaxEvaluations = 2'000'000;
  long evaluations = 0;
  double total = 0.0;
  bool marginal = false;
  const std::function<void(const std::function<cplx(double)>&, double, double, cplx, cplx, int)> refine =
      [&](const std::function<cplx(double)>& s, double t0, double t1, cplx f0, cplx f1, int depth) {
        const double d = std::arg(f1 / f0);
        if (!std::isfinite(d) || evaluations > kMaxEvaluations) {
          marginal = true;
          return;
        }
        if (std::abs(d) <= 0.3 || depth > 48) {
          if (depth > 48 || std::abs(f0) < 1e-12 || std::abs(f1) < 1e-12) marginal = true;
          total += d;
          return;
        }
        ++evaluations;
        const double tm = 0.5 * (t0 + t1);
        const cplx fm = f(s(tm));
        refine(s, t0, tm, f0, fm, depth + 1);
        refine(s, tm, t1, fm, f1, depth + 1);
      };
  const auto path = [&](const std::function<cplx(double)>& s, int n0) {
    cplx prev = f(s(0.0));
    for (int i = 1; i <= n0; ++i) {
      const double t = static_cast<double>(i) / n0;
      const cplx cur = f(s(t));
      refine(s, static_cast<double>(i - 1) / n0, t, prev, cur, 0);
      prev = cur;
    }
  };
  // Up the imaginary axis, w on an asinh scale (fine near 0, logarithmic far out), with the
  // indentations to the right.
  const double w0 = 1e-3 * scale;
  const auto axis_segment = [&](double wa, double wb) {
    const double a = std::asinh(wa / w0), b = std::asinh(wb / w0);
    path([&](double t) { return cplx(0.0, w0 * std::sinh(a + t * (b - a))); }, 256);
  };
  double w_from = -R;
  for (std::size_t k = 0; k < axis.size(); ++k) {
    axis_segment(w_from, axis[k] - eps[k]);
    const cplx c(0.0, axis[k]);
    const double e = eps[k];
    path([&](double t) { return c + e * std::exp(cplx(0.0, -kPi / 2 + t * kPi)); }, 64);
    w_from = axis[k] + eps[k];
  }
  axis_segment(w_from, R);
  path([&](double t) { return R * std::exp(cplx(0.0, kPi / 2 - t * kPi)); }, 256);
  // Clockwise contour: total = -2 pi (Z - P); N (clockwise encirclements of -1) = Z - P.
  ny.encirclements = static_cast<int>(std::lround(-total / (2.0 * kPi)));
  ny.closed_rhp_poles = ny.encirclements + ny.open_rhp_poles;
  ny.marginal = marginal;
  ny.stable = !marginal && ny.closed_rhp_poles == 0;
  return ny;
}

namespace {
Bode bode_on(const TransferFunction& H, const std::vector<double>& w) {
  Bode b;
  b.w = w;
  const Factored fac(H);
  for (double x : w) {
    const cplx v = H(cplx(0.0, x));
    b.mag_db.push_back(20.0 * std::log10(std::abs(v)));
    b.phase_deg.push_back(fac.phase(x) * 180.0 / kPi);
  }
  return b;
}
}  // namespace

FrequencyReport frequency_response(const TransferFunction& L, const FrequencyOptions& opt) {
  check(L);
  if (opt.points < 2) throw InputError("frequency response: need at least 2 points");
  FrequencyReport r;
  r.margins = margins(L);
  r.nyquist = nyquist_count(L);
  const TransferFunction T{L.num, L.den + L.num};
  // Closed loop: DC gain, bandwidth, peak.
  const Split N = split(T.num), Dc = split(T.den);
  const double n0 = T.num.coeff(0), d0 = T.den.coeff(0);
  r.dc_gain = d0 != 0.0 ? std::abs(n0 / d0) : kInf;
  r.bandwidth = kNaN;
  if (std::isfinite(r.dc_gain) && r.dc_gain > 0.0) {
    const auto bw = positive_roots(abs2(N) * 2.0 - abs2(Dc) * (r.dc_gain * r.dc_gain));
    if (!bw.empty()) r.bandwidth = std::sqrt(bw.front());
  }
  {
    const Poly A = abs2(N), B = abs2(Dc);
    const Poly dd = A.derivative() * B - A * B.derivative();
    double best = std::isfinite(r.dc_gain) ? r.dc_gain : 0.0;
    r.peak_w = 0.0;
    for (double u : positive_roots(dd)) {
      const double m = std::abs(T(cplx(0.0, std::sqrt(u))));
      if (m > best) best = m, r.peak_w = std::sqrt(u);
    }
    r.peak_db = 20.0 * std::log10(best);
  }
  // Grid: the open loop's break frequencies and the crossovers, widened 20x each way.
  double lo = kInf, hi = 0.0;
  const auto take = [&](double w) {
    if (w > 0.0 && std::isfinite(w)) lo = std::min(lo, w), hi = std::max(hi, w);
  };
  for (const cplx& p : L.poles()) take(std::abs(p));
  for (const cplx& z : L.zeros()) take(std::abs(z));
  for (double w : r.margins.gain_crossovers) take(w);
  for (double w : r.margins.phase_crossovers) take(w);
  take(r.bandwidth);
  take(r.peak_w);
  if (!(hi > 0.0)) lo = hi = 1.0;
  const double w_lo = opt.w_min > 0 ? opt.w_min : lo / 20.0;
  const double w_hi = opt.w_max > 0 ? opt.w_max : hi * 20.0;
  if (!(w_hi > w_lo)) throw InputError("frequency response: need 0 < w_min < w_max [rad/s]");
  std::vector<double> w(static_cast<std::size_t>(opt.points));
  for (int i = 0; i < opt.points; ++i)
    w[static_cast<std::size_t>(i)] = w_lo * std::pow(w_hi / w_lo, static_cast<double>(i) / (opt.points - 1));
  r.open = bode_on(L, w);
  r.closed = bode_on(T, w);
  r.nyquist.curve.reserve(w.size());
  for (double x : w) r.nyquist.curve.push_back(L(cplx(0.0, x)));
  return r;
}

}  // namespace gmslab::control
