#include "core/control/discrete.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
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

}  // namespace gmslab::control
