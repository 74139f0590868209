#include "core/control/assembly_plant.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <complex>

#include "core/error.hpp"
#include "core/friction/param_specs.hpp"

namespace gmslab::control {

TransferFunction assembly_transfer_function(const Assembly& a, std::size_t drive, const std::string& output,
                                            Regime r, double v0) {
  if (drive >= a.drives.size())
    throw InputError("drive " + std::to_string(drive) + ": the plant has " + std::to_string(a.drives.size()) + " drives");
  const DrivePart& d = a.drives[drive];
  if (d.kind != DrivePart::Kind::Force && d.kind != DrivePart::Kind::Pull)
    throw InputError("drive '" + d.name + "': a " + std::string(to_string(d.kind)) +
                     " drive prescribes motion; the transfer function starts at a force or pull drive");
  // Free bodies (prescribed ones are fixed).
  std::vector<int> dof(a.bodies.size(), -1);
  int n = 0;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    bool fixed = false;
    for (const auto& x : a.drives)
      fixed = fixed || ((x.kind == DrivePart::Kind::Displacement || x.kind == DrivePart::Kind::Velocity) &&
                        x.body == static_cast<int>(i));
    if (!fixed) dof[i] = n++;
  }
  int out = -1;
  bool velocity = false;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    if (output == "x." + a.bodies[i].name) out = static_cast<int>(i);
    if (output == "v." + a.bodies[i].name) out = static_cast<int>(i), velocity = true;
  }
  if (out < 0) throw InputError("output '" + output + "': expected x.BODY or v.BODY of a body of the plant");
  if (dof[out] < 0 || dof[d.body] < 0) throw InputError("output '" + output + "': the body's motion is prescribed");
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n), C = M, K = M;
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (dof[i] >= 0) M(dof[i], dof[i]) = a.bodies[i].mass;
  auto add = [&](Eigen::MatrixXd& A, int ia, int ib, double v) {
    const int da = ia >= 0 ? dof[ia] : -1, db = ib >= 0 ? dof[ib] : -1;
    if (da >= 0) A(da, da) += v;
    if (db >= 0) A(db, db) += v;
    if (da >= 0 && db >= 0) A(da, db) -= v, A(db, da) -= v;
  };
  for (const auto& s : a.springs) add(K, s.a, s.b, s.stiffness);
  for (const auto& s : a.dampers) add(C, s.a, s.b, s.damping);
  for (const auto& x : a.drives)
    if (x.kind == DrivePart::Kind::Pull) add(K, x.body, kGround, x.pull_spring), add(C, x.body, kGround, x.pull_damper);
  for (const auto& c : a.contacts) {
    if (r == Regime::Presliding) {
      add(K, c.a, c.b, stuck_stiffness(c.friction));
      add(C, c.a, c.b, contact_damping(c.friction));
    } else {
      const double v = v0 > 0.0 ? v0 : default_sliding_velocity(c.friction);
      if (!(v > 0.0) || !std::isfinite(v))
        throw InputError("sliding velocity " + specs::num(v) + " m/s: must be > 0");
      const auto model = build_model(c.friction);
      const double h = 1e-4 * v;
      add(C, c.a, c.b, (model->steady_state(v + h) - model->steady_state(v - h)) / (2 * h));
    }
  }
  // Cramer: x_out = det(A with column out replaced by b) / det(A), A(s) = M s^2 + C s + K.
  const int deg = 2 * n;
  const int N = deg + 2;  // samples for a polynomial of degree <= deg + 1
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, (K(i, i) + 1e-300) / M(i, i));
  scale = std::max(1.0, std::sqrt(scale));
  const double bk = d.kind == DrivePart::Kind::Pull ? d.pull_spring : 1.0;
  const double bc = d.kind == DrivePart::Kind::Pull ? d.pull_damper : 0.0;
  std::vector<cplx> den_s(N), num_s(N);
  for (int k = 0; k < N; ++k) {
    const cplx s = scale * std::polar(1.0, 2.0 * M_PI * k / N);
    Eigen::MatrixXcd A = (M.cast<cplx>() * (s * s) + C.cast<cplx>() * s + K.cast<cplx>());
    den_s[k] = A.determinant();
    Eigen::MatrixXcd B = A;
    B.col(dof[out]).setZero();
    B(dof[d.body], dof[out]) = bk + bc * s;
    num_s[k] = B.determinant() * (velocity ? s : cplx(1.0));
  }
  auto coeffs = [&](const std::vector<cplx>& v) {
    std::vector<double> c(N);
    double big = 0.0;
    for (int j = 0; j < N; ++j) {
      cplx acc = 0.0;
      for (int k = 0; k < N; ++k) acc += v[k] * std::polar(1.0, -2.0 * M_PI * j * k / N);
      c[j] = (acc / static_cast<double>(N)).real() / std::pow(scale, j);
      big = std::max(big, std::abs(c[j]) * std::pow(scale, j));
    }
    for (int j = 0; j < N; ++j)  // rounding noise of the DFT: below 1e-12 of the largest term
      if (std::abs(c[j]) * std::pow(scale, j) < 1e-12 * big) c[j] = 0.0;
    return Poly(c);
  };
  TransferFunction g{coeffs(num_s), coeffs(den_s)};
  return g;
}

}  // namespace gmslab::control
