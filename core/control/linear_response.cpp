#include "core/control/linear_response.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "core/error.hpp"

namespace gmslab::control {

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
