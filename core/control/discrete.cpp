#include "core/control/discrete.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <numbers>
#include <unsupported/Eigen/MatrixFunctions>

#include "core/error.hpp"

namespace gmslab::control {

namespace {
void check_T(double T) {
  if (!(T > 0.0) || !std::isfinite(T)) throw InputError("discrete time: the sample time T must be > 0 s");
}
Poly charpoly(const Eigen::MatrixXd& M) {
  if (M.rows() == 0) return Poly({1.0});
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  std::vector<cplx> r;
  for (int i = 0; i < M.rows(); ++i) r.push_back(es.eigenvalues()(i));
  return Poly::from_roots(r);
}
// (a + b x)^k as a polynomial in x.
Poly power(double a, double b, int k) {
  Poly p({1.0});
  for (int i = 0; i < k; ++i) p = p * Poly({a, b});
  return p;
}
}  // namespace

TransferFunction zoh(const TransferFunction& G, double T) {
  check_T(T);
  G.check_proper("zero-order hold");
  const int n = G.den.degree();
  const double a_n = G.den.lead();
  const double d = G.num.degree() == n ? G.num.lead() / a_n : 0.0;
  if (n == 0) return {Poly({d}), Poly({1.0})};
  const Poly b = G.num * (1.0 / a_n) - G.den * (d / a_n);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + 1, n + 1);
  for (int i = 0; i + 1 < n; ++i) M(i, i + 1) = 1.0;
  for (int j = 0; j < n; ++j) M(n - 1, j) = -G.den.coeff(j) / a_n;
  M(n - 1, n) = 1.0;
  const Eigen::MatrixXd E = (M * T).exp();
  const Eigen::MatrixXd Ad = E.topLeftCorner(n, n);
  const Eigen::VectorXd Bd = E.topRightCorner(n, 1);
  Eigen::RowVectorXd C(n);
  for (int j = 0; j < n; ++j) C(j) = b.coeff(j);
  std::vector<cplx> zp;
  for (const cplx& p : G.poles()) zp.push_back(std::exp(p * T));
  const Poly den = Poly::from_roots(zp);
  const Poly num = charpoly(Ad - Bd * C) - charpoly(Ad) + den * d;
  return {num, den};
}

TransferFunction tustin(const TransferFunction& C, double T) {
  check_T(T);
  C.check_proper("Tustin");
  const int n = C.den.degree();
  // s^k -> (2/T)^k (z - 1)^k (z + 1)^(n - k)
  const auto map = [&](const Poly& p) {
    Poly out;
    for (int k = 0; k <= p.degree(); ++k)
      out = out + power(-1.0, 1.0, k) * power(1.0, 1.0, n - k) * (p.coeff(k) * std::pow(2.0 / T, k));
    return out;
  };
  return {map(C.num), map(C.den)};
}

TransferFunction to_w_plane(const TransferFunction& Lz, double T) {
  check_T(T);
  const int n = std::max(Lz.num.degree(), Lz.den.degree());
  // z^k -> (1 + wT/2)^k (1 - wT/2)^(n - k)
  const auto map = [&](const Poly& p) {
    Poly out;
    for (int k = 0; k <= p.degree(); ++k)
      out = out + power(1.0, T / 2, k) * power(1.0, -T / 2, n - k) * p.coeff(k);
    return out;
  };
  return {map(Lz.num), map(Lz.den)};
}

DiscreteFrequencyReport discrete_frequency_response(const TransferFunction& Lz, double T, int points) {
  check_T(T);
  Lz.check_proper("discrete loop");
  if (points < 2) throw InputError("discrete frequency response: need at least 2 points");
  DiscreteFrequencyReport r;
  r.T = T;
  r.nyquist_frequency = std::numbers::pi / T;
  const TransferFunction Lw = to_w_plane(Lz, T);
  const auto back = [&](double nu) { return 2.0 / T * std::atan(nu * T / 2.0); };
  r.margins = margins(Lw);
  for (double& w : r.margins.gain_crossovers) w = back(w);
  for (double& w : r.margins.phase_crossovers) w = back(w);
  if (std::isfinite(r.margins.gain_crossover)) r.margins.gain_crossover = back(r.margins.gain_crossover);
  if (std::isfinite(r.margins.phase_crossover)) r.margins.phase_crossover = back(r.margins.phase_crossover);
  r.nyquist = nyquist_count(Lw);
  r.closed_loop_poles = (Lz.den + Lz.num).roots();
  // Bode from omega_N / 1e4 up to (just below) the Nyquist frequency; phase continuous through the
  // w-plane factors (arg L(e^{j omega T}) = arg Lw(j nu)).
  const double lo = r.nyquist_frequency * 1e-4, hi = r.nyquist_frequency * 0.999;
  std::vector<double> nus;
  for (int i = 0; i < points; ++i) {
    const double w = lo * std::pow(hi / lo, static_cast<double>(i) / (points - 1));
    nus.push_back(2.0 / T * std::tan(w * T / 2.0));
    r.open.w.push_back(w);
    r.open.mag_db.push_back(20.0 * std::log10(std::abs(Lz(std::exp(cplx(0.0, w * T))))));
    r.nyquist.curve.push_back(Lz(std::exp(cplx(0.0, w * T))));
  }
  for (double ph : continuous_phase(Lw, nus)) r.open.phase_deg.push_back(ph * 180.0 / std::numbers::pi);
  return r;
}

TransferFunction sampled_loop(const TransferFunction& G, double z, double p, double T) {
  const TransferFunction Cz = tustin({Poly({z, 1.0}), Poly({p, 1.0})}, T);
  const TransferFunction Gz = zoh(G, T);
  return {Cz.num * Gz.num, Cz.den * Gz.den};
}

TransferFunction sampled_loop(const TransferFunction& G, const LeadCompensator& c, double T) {
  const TransferFunction Cz = tustin({c.num_poly(), c.den_poly()}, T);
  const TransferFunction Gz = zoh(G, T);
  return {Cz.num * Gz.num, Cz.den * Gz.den};
}

bool roots_inside_unit_circle(const TransferFunction& Lz, double k) {
  for (const cplx& z : closed_loop_poles(Lz, k))
    if (!(std::abs(z) < 1.0 - 1e-12)) return false;
  return true;
}

ZLocus z_root_locus(const TransferFunction& Lz, double T, const LocusOptions& opt) {
  check_T(T);
  Lz.check_proper("z-plane root locus");
  ZLocus r;
  r.T = T;
  // Unit-circle crossings from the w-plane image's imaginary-axis crossings, plus z = -1.
  // An open-loop pole on the circle (the ZOH of a pole at s = 0 is z = 1) is where the locus
  // starts (k = 0), not a crossing: dropped when den(z) is at rounding level there.
  const TransferFunction Lw = to_w_plane(Lz, T);
  double den_size = 0.0;
  for (double c : Lz.den.ascending()) den_size += std::abs(c);
  for (const LocusPoint& p : imaginary_axis_crossings(Lw, false)) {
    const double nu = p.s.imag();
    const cplx z = cplx(1.0, nu * T / 2) / cplx(1.0, -nu * T / 2);
    if (std::abs(Lz.den(z)) <= 1e-10 * den_size) continue;
    r.crossings.push_back({z, 2.0 / T * std::atan(nu * T / 2), p.k});
  }
  const cplx nm1 = Lz.num(cplx(-1.0, 0.0));
  if (std::abs(nm1) > 0.0) {
    const double k = (-Lz.den(cplx(-1.0, 0.0)) / nm1).real();
    if (k > 0.0 && std::abs(Lz.den(cplx(-1.0, 0.0))) > 1e-10 * den_size) r.crossings.push_back({cplx(-1.0, 0.0), std::numbers::pi / T, k});
  }
  std::sort(r.crossings.begin(), r.crossings.end(),
            [](const UnitCircleCrossing& a, const UnitCircleCrossing& b) { return a.k < b.k; });
  // Stable gain intervals.
  std::vector<double> edges{0.0};
  for (const auto& c : r.crossings)
    if (c.k > edges.back()) edges.push_back(c.k);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const double lo = edges[i];
    const double hi = i + 1 < edges.size() ? edges[i + 1] : std::numeric_limits<double>::infinity();
    const double mid = std::isinf(hi) ? (lo > 0.0 ? 10.0 * lo : 1.0) : (lo > 0.0 ? std::sqrt(lo * hi) : 0.5 * hi);
    if (!roots_inside_unit_circle(Lz, mid)) continue;
    if (!r.stable_gains.empty() && r.stable_gains.back().second == lo) r.stable_gains.back().second = hi;
    else r.stable_gains.emplace_back(lo, hi);
  }
  // The locus itself, sampled at the crossing gains.
  LocusOptions o = opt;
  for (const auto& c : r.crossings) o.extra_gains.push_back(c.k);
  if (!o.view) {
    std::vector<cplx> pts{{1.0, 0.0}, {-1.0, 0.0}, {0.0, 1.0}, {0.0, -1.0}};
    for (const cplx& p : Lz.poles()) pts.push_back(p);
    for (const cplx& z : Lz.zeros())
      if (std::abs(z) < 10.0) pts.push_back(z);
    ViewBox v = view_around(pts);  // square; widened to a 16:10 canvas so its sides are resolved too
    const double c = 0.5 * (v.re_min + v.re_max), h = 0.8 * v.height();
    v.re_min = std::min(v.re_min, c - h), v.re_max = std::max(v.re_max, c + h);
    o.view = v;
  }
  r.locus = root_locus(Lz, o);
  return r;
}

}  // namespace gmslab::control
