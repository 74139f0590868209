#include "core/control/describing_function.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "core/control/frequency.hpp"
#include "core/error.hpp"

namespace gmslab::control {

namespace {
constexpr double kPi = std::numbers::pi;
}

SteppedNonlinearity stepped(const FrictionModel& model) {
  auto st = std::make_shared<std::vector<double>>(model.state_size());
  const FrictionModel* m = &model;
  return {[m, st] { m->reset(*st); },
          [m, st](double v, double h) { return m->step(*st, {v, h, 0.0, 0.0}); }};
}

SteppedNonlinearity compensated(SteppedNonlinearity f, SteppedNonlinearity f_hat) {
  return {[f, f_hat] { f.reset(), f_hat.reset(); },
          [f, f_hat](double v, double h) { return f.step(v, h) - f_hat.step(v, h); }};
}

SteppedNonlinearity coulomb_law(double Fc_hat) {
  return {[] {}, [Fc_hat](double v, double) { return v > 0.0 ? Fc_hat : v < 0.0 ? -Fc_hat : 0.0; }};
}

namespace {
// A model owned by the returned nonlinearity (stepped() only borrows one).
SteppedNonlinearity owned(std::shared_ptr<FrictionModel> m) {
  auto st = std::make_shared<std::vector<double>>(m->state_size());
  return {[m, st] { m->reset(*st); }, [m, st](double v, double h) { return m->step(*st, {v, h, 0.0, 0.0}); }};
}
}  // namespace

SteppedNonlinearity compensated_friction(const ModelParams& friction, Compensation comp, const Mismatch& mm) {
  std::shared_ptr<FrictionModel> plant = build_model(friction);
  SteppedNonlinearity f = owned(plant);
  switch (comp) {
    case Compensation::None: return f;
    case Compensation::Coulomb: return compensated(f, coulomb_law(coulomb_feedforward_level(friction, mm)));
    case Compensation::Gms: return compensated(f, owned(build_model(feedforward_model(friction, mm))));
  }
  return f;
}

cplx describing_function(const SteppedNonlinearity& f, double a, double w, const DfOptions& opt) {
  if (!(a > 0.0) || !(w > 0.0) || !std::isfinite(a + w))
    throw InputError("describing function: need amplitude a > 0 m/s and frequency w > 0 rad/s");
  if (opt.steps < 16 || opt.periods < 1)
    throw InputError("describing function: need >= 16 steps per period and >= 1 period");
  f.reset();
  const double h = 2.0 * kPi / (w * opt.steps);
  double A = 0.0, B = 0.0;
  const long long total = static_cast<long long>(opt.steps) * opt.periods;
  const long long last = total - opt.steps;
  for (long long k = 0; k < total; ++k) {
    const double th = w * (static_cast<double>(k) + 0.5) * h;
    const double F = f.step(a * std::sin(th), h);
    if (k >= last) B += F * std::sin(th), A += F * std::cos(th);
  }
  // (2/T) sum F sin * h = (2 / steps) sum F sin
  return cplx(B, A) * (2.0 / opt.steps) / a;
}

TransferFunction friction_loop(const Plant& pl, const LeadCompensator& c) {
  const Poly G_den({pl.spring, pl.damper, pl.mass});
  const Poly sp = c.den_poly();
  return {Poly({0.0, 1.0}) * sp, G_den * sp + c.num_poly() * c.Kc};
}

namespace {
// Closed-loop root of den + n num (complex n) nearest s0.
cplx nearest_root(const TransferFunction& H, cplx n, cplx s0) {
  const int deg = H.den.degree();
  std::vector<cplx> c(static_cast<std::size_t>(deg + 1));
  for (int i = 0; i <= deg; ++i) c[static_cast<std::size_t>(i)] = H.den.coeff(i) + n * H.num.coeff(i);
  Eigen::MatrixXcd C = Eigen::MatrixXcd::Zero(deg, deg);
  for (int i = 1; i < deg; ++i) C(i, i - 1) = 1.0;
  for (int i = 0; i < deg; ++i) C(i, deg - 1) = -c[static_cast<std::size_t>(i)] / c.back();
  Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(C, false);
  cplx best = es.eigenvalues()(0);
  for (int i = 1; i < deg; ++i)
    if (std::abs(es.eigenvalues()(i) - s0) < std::abs(best - s0)) best = es.eigenvalues()(i);
  return best;
}
}  // namespace

LimitCycleReport predict_limit_cycles(const SteppedNonlinearity& f, const Plant& pl, const LeadCompensator& c,
                                      double a_min, double a_max, const DfOptions& opt) {
  if (!(pl.mass > 0.0)) throw InputError("limit cycles: need m > 0 kg");
  check_compensator(c, "limit cycles");
  if (!(a_min > 0.0) || !(a_max > a_min)) throw InputError("limit cycles: need 0 < a_min < a_max [m/s]");
  LimitCycleReport r;
  r.H = friction_loop(pl, c);
  const Margins hm = margins(r.H);  // phase crossovers of H: H(jw) real negative
  const double la0 = std::log(a_min), la1 = std::log(a_max);
  const auto N = [&](double a, double w) { return describing_function(f, a, w, opt); };
  for (double w0 : hm.phase_crossovers) {
    const double target = 1.0 / std::abs(r.H(cplx(0.0, w0)));
    // |N| - target over a log grid of a, then bisection on the first sign change.
    const int grid = 24;
    // Re N (not |N|): H(jw0) is negative real, so the balance needs N = +1/|H|; a negative N
    // (e.g. over-compensated friction) cannot meet it there.
    double prev_la = la0, prev = N(a_min, w0).real() - target;
    for (int i = 1; i <= grid; ++i) {
      const double la = la0 + (la1 - la0) * i / grid;
      const double cur = N(std::exp(la), w0).real() - target;
      if ((prev > 0) != (cur > 0)) {
        double lo = prev_la, hi = la, flo = prev;
        for (int k = 0; k < 40; ++k) {
          const double mid = 0.5 * (lo + hi);
          const double fm = N(std::exp(mid), w0).real() - target;
          if ((fm > 0) == (flo > 0)) lo = mid, flo = fm;
          else hi = mid;
        }
        LimitCycle lc;
        double x = 0.5 * (lo + hi), w = w0;
        // Newton on g(ln a, w) = 1 + H(jw) N(a, w) (2 real equations), finite differences.
        const auto g = [&](double lx, double ww) { return 1.0 + r.H(cplx(0.0, ww)) * N(std::exp(lx), ww); };
        bool conv = false;
        for (int it = 0; it < 12; ++it) {
          const cplx g0 = g(x, w);
          if (std::abs(g0) < 1e-6) {
            conv = true;
            break;
          }
          const double dx = 1e-4, dw = 1e-5 * w;
          const cplx gx = (g(x + dx, w) - g0) / dx, gw = (g(x, w + dw) - g0) / dw;
          const double det = gx.real() * gw.imag() - gw.real() * gx.imag();
          if (det == 0.0) break;
          double sx = -(g0.real() * gw.imag() - gw.real() * g0.imag()) / det;
          double sw = -(gx.real() * g0.imag() - g0.real() * gx.imag()) / det;
          const double lim = 0.5;  // keep steps modest: at most x1.65 in a, 50 % in w
          const double scale = std::max({1.0, std::abs(sx) / lim, std::abs(sw) / (lim * w)});
          x += sx / scale, w += sw / scale;
          if (!(w > 0.0) || x < la0 - 2 || x > la1 + 2) break;
        }
        if (!conv || !(w > 0.0)) x = 0.5 * (lo + hi), w = w0;  // fall back to the real estimate
        lc.converged = conv;
        lc.velocity_amplitude = std::exp(x);
        lc.frequency = w;
        lc.amplitude = lc.velocity_amplitude / w;
        lc.period = 2.0 * kPi / w;
        lc.point = r.H(cplx(0.0, w));
        const cplx s0(0.0, w);
        const double up = nearest_root(r.H, N(lc.velocity_amplitude * 1.05, w), s0).real();
        const double dn = nearest_root(r.H, N(lc.velocity_amplitude / 1.05, w), s0).real();
        lc.stable = up < 0.0 && dn > 0.0;
        r.cycles.push_back(lc);
      }
      prev_la = la, prev = cur;
    }
  }
  if (hm.phase_crossovers.empty())
    r.note = "H(jw) never crosses the negative real axis: -1/N (real for rate-independent friction) cannot meet it";
  else if (r.cycles.empty())
    r.note = "Re N(a) never equals 1/|H(jw)| at the crossing for velocity amplitudes in the searched range";
  // Curves to draw.
  double lo = 1e300, hi = 0.0;
  for (const cplx& q : r.H.poles()) if (std::abs(q) > 0) lo = std::min(lo, std::abs(q)), hi = std::max(hi, std::abs(q));
  for (double w : hm.phase_crossovers) lo = std::min(lo, w), hi = std::max(hi, w);
  if (!(hi > 0)) lo = hi = 1.0;
  for (int i = 0; i < 300; ++i) {
    const double w = lo / 30.0 * std::pow(900.0 * hi / lo, i / 299.0);
    r.h_w.push_back(w);
    r.h_curve.push_back(r.H(cplx(0.0, w)));
  }
  const double w_loc = !r.cycles.empty() ? r.cycles.front().frequency
                       : !hm.phase_crossovers.empty() ? hm.phase_crossovers.front() : std::sqrt(lo * hi);
  DfOptions coarse = opt;
  coarse.steps = std::min(opt.steps, 400);
  for (int i = 0; i <= 40; ++i) {
    const double a = std::exp(la0 + (la1 - la0) * i / 40.0);
    const cplx n = describing_function(f, a, w_loc, coarse);
    if (std::abs(n) > 0.0) r.locus_a.push_back(a), r.locus.push_back(-1.0 / n);
  }
  return r;
}

}  // namespace gmslab::control
