#include "core/control/linear_response.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "core/error.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace gmslab::control {

Poly LeadCompensator::num_poly() const {
  Poly n({z, 1.0});
  if (second) n = n * Poly({second->z, 1.0});
  return n;
}
Poly LeadCompensator::den_poly() const {
  Poly d({p, 1.0});
  if (second) d = d * Poly({second->p, 1.0});
  return d;
}
TransferFunction LeadCompensator::tf() const {
  if (!second) return {Poly({Kc * z, Kc}), Poly({p, 1.0})};  // as before the sections
  return {num_poly() * Kc, den_poly()};
}
std::vector<double> LeadCompensator::zeros() const {
  std::vector<double> r{z};
  if (second) r.push_back(second->z);
  return r;
}
std::vector<double> LeadCompensator::poles() const {
  std::vector<double> r{p};
  if (second) r.push_back(second->p);
  return r;
}

double LeadCompensator::static_gain() const {
  double g = Kc;
  for (int i = 0; i < sections(); ++i) {
    const Section s = section(i);
    g = s.p > 0.0 ? g * s.z / s.p : std::numeric_limits<double>::infinity();
  }
  return g;
}

std::string LeadCompensator::text() const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.5g ", Kc);
  std::string n = buf, d;
  int integrators = 0;
  for (int i = 0; i < sections(); ++i) {
    const Section s = section(i);
    std::snprintf(buf, sizeof buf, "(s + %.4g)", s.z);
    n += buf;
    if (s.p == 0.0) {
      ++integrators;
      continue;
    }
    std::snprintf(buf, sizeof buf, "(s + %.4g)", s.p);
    d += buf;
  }
  for (int i = 0; i < integrators; ++i) d += d.empty() ? "s" : " s";
  return n + " / " + (sections() == 2 && d != "s s" ? "(" + d + ")" : d);
}

void check_compensator(const LeadCompensator& c, const std::string& who) {
  bool ok = c.Kc > 0.0 && std::isfinite(c.Kc);
  for (int i = 0; i < c.sections(); ++i) {
    const Section s = c.section(i);
    ok = ok && s.z > 0.0 && s.p >= 0.0 && std::isfinite(s.z + s.p);
  }
  if (!ok)
    throw InputError(who + ": compensator Kc and every zero z_i must be finite and > 0, every pole p_i finite "
                           "and >= 0 rad/s (p_i = 0: integrator)");
}

TransferFunction closed_loop(const TransferFunction& g, const LeadCompensator& c) {
  const TransferFunction gc = c.tf();
  const Poly n = gc.num * g.num;
  return {n, gc.den * g.den + n};
}

StepResponse step_response(const TransferFunction& T, double t_end, int n_points) {
  T.check_proper("step response");
  if (!(t_end > 0.0) || n_points < 2)
    throw InputError("step response: need t_end > 0 s and at least 2 points");
  const int n = T.den.degree();
  const double a_n = T.den.lead();
  const double d = T.num.degree() == n ? T.num.lead() / a_n : 0.0;
  const Poly b = T.num * (1.0 / a_n) - T.den * (d / a_n);  // strictly proper remainder
  StepResponse r;
  const double h = t_end / (n_points - 1);
  if (n == 0) {
    for (int k = 0; k < n_points; ++k) r.t.push_back(k * h), r.y.push_back(d);
    return r;
  }
  // Controllable canonical form: x' = A x + B u, y = C x + D u.
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + 1, n + 1);
  for (int i = 0; i + 1 < n; ++i) M(i, i + 1) = 1.0;
  for (int j = 0; j < n; ++j) M(n - 1, j) = -T.den.coeff(j) / a_n;
  M(n - 1, n) = 1.0;  // B = e_n
  const Eigen::MatrixXd E = (M * h).exp();
  const Eigen::MatrixXd Ad = E.topLeftCorner(n, n);
  const Eigen::VectorXd Bd = E.topRightCorner(n, 1);
  Eigen::RowVectorXd C(n);
  for (int j = 0; j < n; ++j) C(j) = b.coeff(j);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < n_points; ++k) {
    r.t.push_back(k * h);
    r.y.push_back(C.dot(x) + d);
    x = Ad * x + Bd;
  }
  return r;
}

}  // namespace gmslab::control
