#include "core/control/lead_design.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"

namespace gmslab::control {

namespace {
constexpr double kPi = std::numbers::pi;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string num_text(double x) {
  std::ostringstream o;
  o.precision(5);
  o << x;
  return o.str();
}

std::vector<cplx> cl_poles(const TransferFunction& g, double Kc, double z, double p) {
  return (g.den * Poly({p, 1.0}) + g.num * Poly({Kc * z, Kc})).roots();
}
}  // namespace

cplx DominantRoot::s() const { return {-zeta * wn, wn * std::sqrt(1.0 - zeta * zeta)}; }
double DominantRoot::beta() const { return std::acos(zeta); }

void check_root(const DominantRoot& d) {
  if (!(d.zeta > 0.0 && d.zeta < 1.0))
    throw InputError("zeta = " + num_text(d.zeta) +
                     ": the damping ratio of the dominant roots must be in (0, 1)");
  if (!(d.wn >= kMinWn && d.wn <= kMaxWn))
    throw InputError("wn = " + num_text(d.wn) + " rad/s: the natural frequency must be in [" + num_text(kMinWn) +
                     ", " + num_text(kMaxWn) + "] rad/s");
}

LeadLimits lead_limits(const TransferFunction& g, const DominantRoot& d) {
  check_root(d);
  const PlantType t = plant_type(g);
  LeadLimits L;
  L.s_d = d.s();
  L.beta = d.beta();
  const cplx G = g(L.s_d);
  L.G_abs = std::abs(G);
  double phi = -kPi - std::arg(G);
  while (phi <= -kPi) phi += 2 * kPi;
  while (phi > kPi) phi -= 2 * kPi;
  L.phi = phi;
  L.M = t.K0 / L.G_abs;
  L.applicable = phi > 0.0 && phi < kPi - L.beta;
  if (phi <= 0.0)
    L.reason = "phi = " + num_text(phi * 180 / kPi) +
               " deg <= 0: s_d needs phase lag, not lead (a pure gain places it only at phi = 0); "
               "use a lag network or move s_d";
  else if (!L.applicable)
    L.reason = "phi = " + num_text(phi * 180 / kPi) + " deg >= 180 - beta = " +
               num_text(180 - L.beta * 180 / kPi) +
               " deg: one lead cannot place s_d; use two leads or move s_d";
  if (L.applicable) {
    L.K_max = L.M * std::sin(phi + L.beta) / std::sin(L.beta);
    L.pd_z = d.wn * std::sin(phi + L.beta) / std::sin(phi);
    L.pd_Kd = 1.0 / (L.G_abs * std::abs(L.s_d + L.pd_z));
  } else {
    L.K_max = kNaN;
  }
  return L;
}

namespace {
Dominance dominance_of(const Poly& nt, const Poly& ct, const DominantRoot& d, double z, double p,
                       const std::vector<cplx>& poles) {
  Dominance D;
  const cplx sd = d.s();
  const Poly dct = ct.derivative();
  const double final_value = std::abs(nt(0.0) / ct(0.0));
  // The two poles closest to s_d and its conjugate are the dominant pair.
  std::size_t i1 = 0, i2 = 0;
  for (std::size_t i = 0; i < poles.size(); ++i) {
    if (std::abs(poles[i] - sd) < std::abs(poles[i1] - sd)) i1 = i;
    if (std::abs(poles[i] - std::conj(sd)) < std::abs(poles[i2] - std::conj(sd))) i2 = i;
  }
  D.dominant = true;
  for (std::size_t i = 0; i < poles.size(); ++i) {
    const cplx a = poles[i];
    if (i == i1 || i == i2 || a.imag() < 0.0) continue;
    Dominance::Other o;
    o.pole = a;
    o.speed_ratio = a.real() / sd.real();
    const cplx der = dct(a);
    o.residue = (std::abs(der) > 0.0 && std::abs(a) > 0.0 && final_value > 0.0)
                    ? std::abs(nt(a) / (a * der)) / final_value * (a.imag() > 0.0 ? 2.0 : 1.0)
                    : std::numeric_limits<double>::infinity();
    if (a.real() >= 0.0) {
      D.dominant = false;
      D.notes.push_back("closed-loop pole " + num_text(a.real()) + (a.imag() > 0 ? " +- j" + num_text(a.imag()) : "") +
                        " is not in the open left half plane: the loop is unstable");
    } else if (o.speed_ratio < 5.0 && o.residue > 0.1) {
      D.dominant = false;
      D.notes.push_back("pole at " + num_text(a.real()) + (a.imag() > 0 ? " +- j" + num_text(a.imag()) : "") +
                        " is only " + num_text(o.speed_ratio) + "x as fast as s_d and carries " +
                        num_text(100 * o.residue) + "% of the step: s_d does not dominate");
    } else if (o.speed_ratio < 5.0) {
      D.notes.push_back("slow pole at " + num_text(a.real()) + " is nearly cancelled by a zero (" +
                        num_text(100 * o.residue) + "% of the step): expect a small slow tail");
    }
    D.others.push_back(o);
  }
  if (z < 2.0 * d.zeta * d.wn)
    D.notes.push_back("the compensator zero -" + num_text(z) + " is within 2x of Re s_d = " +
                      num_text(-d.zeta * d.wn) + ": it adds overshoot beyond what zeta = " +
                      num_text(d.zeta) + " predicts");
  if (p > 50.0 * d.wn)
    D.notes.push_back("p = " + num_text(p) + " rad/s is more than 50 wn: the lead is close to a "
                      "pure PD, noise is amplified by p/z = " + num_text(p / z));
  return D;
}

}  // namespace

Dominance check_dominance(const TransferFunction& g, const DominantRoot& d, double Kc, double z,
                          double p, const std::vector<cplx>& poles) {
  const Poly nt = g.num * Poly({Kc * z, Kc});
  return dominance_of(nt, g.den * Poly({p, 1.0}) + nt, d, z, p, poles);
}

Dominance check_dominance(const TransferFunction& g, const DominantRoot& d, const LeadCompensator& c,
                          const std::vector<cplx>& poles) {
  if (!c.second) return check_dominance(g, d, c.Kc, c.z, c.p, poles);
  const TransferFunction C = c.tf();
  const Poly nt = g.num * C.num;
  return dominance_of(nt, g.den * C.den + nt, d, c.z, c.p, poles);
}

LeadDesign design_at_zero_angle(const TransferFunction& g, const DominantRoot& d, double theta_z) {
  const LeadLimits L = lead_limits(g, d);
  const double b = L.beta;
  LeadDesign r;
  r.theta_z = theta_z;
  r.theta_p = theta_z - L.phi;
  r.z = d.wn * std::sin(theta_z + b) / std::sin(theta_z);
  r.p = d.wn * std::sin(r.theta_p + b) / std::sin(r.theta_p);
  r.Kc = std::sin(theta_z) / (std::sin(r.theta_p) * L.G_abs);
  r.K = r.Kc * r.z / r.p * plant_type(g).K0;
  r.closed_loop_poles = cl_poles(g, r.Kc, r.z, r.p);
  r.dominance = check_dominance(g, d, r.Kc, r.z, r.p, r.closed_loop_poles);
  return r;
}

LeadDesign design_for_constant(const TransferFunction& g, const DominantRoot& d, double K_des) {
  if (!(K_des > 0.0) || !std::isfinite(K_des))
    throw InputError("K = " + num_text(K_des) + ": the desired error constant must be > 0");
  const LeadLimits L = lead_limits(g, d);
  if (!L.applicable) throw InputError("no lead design at this s_d: " + L.reason);
  if (K_des >= L.K_max)
    throw InputError("K = " + num_text(K_des) + " is not reachable at this s_d: K_max = " +
                     num_text(L.K_max));
  const double u = std::arg(K_des * std::polar(1.0, L.phi) - L.M);
  return design_at_zero_angle(g, d, u - L.beta);
}

LeadDesign design_by_linear_system(const TransferFunction& g, const DominantRoot& d, double K_des) {
  const PlantType t = plant_type(g);
  const cplx s = d.s();
  // Normalised N, s^n D with N(0) = D(0) = 1: num = num(0) N, den = den_n s^n D.
  const cplx N = g.num(s) / g.num.coeff(0);
  const cplx snD = g.den(s) / g.den.coeff(t.n);
  // x1 = Kc, x2 = Kc z:  x1 K0 s N + x2 (K0 snD / K_des + K0 N) = -s snD
  const cplx a1 = t.K0 * s * N;
  const cplx a2 = t.K0 * snD / K_des + t.K0 * N;
  const cplx rhs = -s * snD;
  Eigen::Matrix2d A;
  A << a1.real(), a2.real(), a1.imag(), a2.imag();
  const Eigen::Vector2d x = A.partialPivLu().solve(Eigen::Vector2d(rhs.real(), rhs.imag()));
  LeadDesign r;
  r.Kc = x(0);
  r.z = x(1) / x(0);
  r.p = x(1) * t.K0 / K_des;
  r.K = K_des;
  r.closed_loop_poles = cl_poles(g, r.Kc, r.z, r.p);
  return r;
}

namespace {
double ratio_at(const DominantRoot& d, const LeadLimits& L, double theta_z) {
  const double b = L.beta, tp = theta_z - L.phi;
  const double z = std::sin(theta_z + b) / std::sin(theta_z);
  const double p = std::sin(tp + b) / std::sin(tp);
  return p / z;
}
}  // namespace

double usable_max(const TransferFunction& g, const DominantRoot& d, double max_ratio,
                  std::optional<LeadDesign>* at) {
  if (!(max_ratio > 1.0))
    throw InputError("--max-ratio = " + num_text(max_ratio) + ": the bound on p/z must be > 1");
  const LeadLimits L = lead_limits(g, d);
  if (!L.applicable) return kNaN;
  // p/z -> inf at both ends of (phi, pi - beta); K rises as theta_z falls toward phi. Find the
  // smallest theta_z with p/z <= max_ratio.
  const double lo = L.phi, hi = kPi - L.beta;
  const int n = 2000;
  double prev = lo;
  for (int i = 1; i < n; ++i) {
    const double th = lo + (hi - lo) * i / n;
    if (ratio_at(d, L, th) <= max_ratio) {
      double a = prev, b = th;
      for (int it = 0; it < 100; ++it) {
        const double m = 0.5 * (a + b);
        (ratio_at(d, L, m) <= max_ratio ? b : a) = m;
      }
      const LeadDesign r = design_at_zero_angle(g, d, b);
      if (at) *at = r;
      return r.K;
    }
    prev = th;
  }
  return kNaN;
}

namespace {
struct Path {
  std::string name;
  std::string param;  // name of the varied quantity for messages
  std::function<DominantRoot(double)> at;  // t in [0, 1]
  std::function<double(const DominantRoot&)> value;  // the varied quantity
};

double kmax_or_nan(const TransferFunction& g, const DominantRoot& d) {
  const LeadLimits L = lead_limits(g, d);
  return L.applicable ? L.K_max : kNaN;
}

Relocation search_path(const TransferFunction& g, const Path& path, double K_des, double target) {
  Relocation r;
  r.path = path.name;
  const int n = 600;
  double t_prev = 0.0;
  bool prev_ok = false;
  double lost_at = kNaN;
  bool lost_by_excess = true;  // phi >= pi - beta (else phi <= 0: lag needed)
  double peak_t = 0.0;
  r.peak_K = -1.0;
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    const DominantRoot d = path.at(t);
    const double k = kmax_or_nan(g, d);
    const bool ok = std::isfinite(k);
    if (ok && k > r.peak_K) r.peak_K = k, r.peak_root = d, peak_t = t;
    if (!ok && prev_ok && std::isnan(lost_at)) {  // bisect where the lead stops applying
      double a = t_prev, b = t;
      for (int it = 0; it < 100; ++it) {
        const double m = 0.5 * (a + b);
        (std::isfinite(kmax_or_nan(g, path.at(m))) ? a : b) = m;
      }
      lost_at = path.value(path.at(b));
      lost_by_excess = lead_limits(g, path.at(b)).phi > 0.0;
    }
    if (i > 0 && ok && k >= target) {
      double a = t_prev, b = t;  // predicate false at a, true at b
      for (int it = 0; it < 200; ++it) {
        const double m = 0.5 * (a + b);
        const double km = kmax_or_nan(g, path.at(m));
        (std::isfinite(km) && km >= target ? b : a) = m;
      }
      r.found = true;
      r.root = path.at(b);
      r.K_max = kmax_or_nan(g, r.root);
      r.design = design_for_constant(g, r.root, K_des);
      return r;
    }
    t_prev = t;
    prev_ok = ok;
  }
  // Refine the peak by golden-section search around the best grid point.
  if (r.peak_K > 0.0) {
    double a = std::max(0.0, peak_t - 1.0 / n);
    double b = std::min(1.0, peak_t + 1.0 / n);
    const double gr = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int it = 0; it < 100; ++it) {
      const double c = b - gr * (b - a), e = a + gr * (b - a);
      const double kc = kmax_or_nan(g, path.at(c)), ke = kmax_or_nan(g, path.at(e));
      if (std::isfinite(kc) && (!std::isfinite(ke) || kc > ke)) b = e;
      else a = c;
    }
    const DominantRoot d = path.at(0.5 * (a + b));
    const double k = kmax_or_nan(g, d);
    if (std::isfinite(k) && k > r.peak_K) r.peak_K = k, r.peak_root = d;
  }
  std::ostringstream o;
  o.precision(5);
  if (r.peak_K > 0.0 && peak_t >= 1.0 - 1.0 / n)
    o << "along the explored range (up to 100x the start in wn or wd, or zeta down to 0.1 % of "
         "it) K_max only reaches " << r.peak_K << " (wn = " << r.peak_root.wn
      << " rad/s, zeta = " << r.peak_root.zeta << "), below the target " << target;
  else if (r.peak_K > 0.0)
    o << "along this path K_max peaks at " << r.peak_K << " (wn = " << r.peak_root.wn
      << " rad/s, zeta = " << r.peak_root.zeta << "), below the target " << target;
  else
    o << "no point of this path admits a single lead";
  if (std::isfinite(lost_at))
    o << (path.param == "zeta" ? "; below zeta = " : "; above " + path.param + " = ") << lost_at
      << (path.param == "zeta" ? " " : " rad/s ")
      << (lost_by_excess ? "phi reaches pi - beta and no single lead places the roots"
                         : "phi drops to 0 (beyond, s_d needs lag, not lead), so this path "
                           "leaves the lead family");
  r.reason = o.str();
  return r;
}
}  // namespace

std::vector<Relocation> relocate(const TransferFunction& g, const DominantRoot& d, double K_des,
                                 double margin) {
  check_root(d);
  if (!(margin > 0.0)) throw InputError("margin must be > 0 (relocation target K (1 + margin))");
  const double target = K_des * (1.0 + margin);
  const double sigma = d.zeta * d.wn, wd = d.wn * std::sqrt(1 - d.zeta * d.zeta);
  const double span = 100.0;  // each path explores up to 100x the start (wn, wd) or zeta -> 0
  std::vector<Path> paths = {
      {"keep_zeta", "wn", [=](double t) { return DominantRoot{d.zeta, d.wn * std::pow(span, t)}; },
       [](const DominantRoot& r) { return r.wn; }},
      {"keep_zeta_wn", "wd",
       [=](double t) {
         const double w = wd * std::pow(span, t);
         const double wn = std::hypot(sigma, w);
         return DominantRoot{sigma / wn, wn};
       },
       [](const DominantRoot& r) { return r.wn * std::sqrt(1 - r.zeta * r.zeta); }},
      {"keep_wn", "zeta", [=](double t) { return DominantRoot{d.zeta * (1.0 - 0.999 * t), d.wn}; },
       [](const DominantRoot& r) { return r.zeta; }},
  };
  std::vector<Relocation> out;
  for (const auto& p : paths) out.push_back(search_path(g, p, K_des, target));
  return out;
}

const Relocation* best_relocation(const LeadReport& r) {
  auto stable = [](const Relocation& rel) {
    for (const cplx& p : rel.design.closed_loop_poles)
      if (!(p.real() < 0.0)) return false;
    return true;
  };
  for (const auto& rel : r.relocations)
    if (rel.found && rel.design.dominance.dominant) return &rel;
  for (const auto& rel : r.relocations)
    if (rel.found && stable(rel)) return &rel;
  for (const auto& rel : r.relocations)
    if (rel.found) return &rel;
  return nullptr;
}

LeadReport lead_design(const TransferFunction& g, const DominantRoot& d,
                       std::optional<double> K_des, const LeadOptions& opt) {
  g.check_proper("plant");
  check_root(d);
  LeadReport r;
  r.type = plant_type(g);
  if (!(r.type.K0 > 0.0))
    throw InputError("plant: K0 = lim s^n G(s) = " + num_text(r.type.K0) +
                     " is not > 0 (a negative static gain or an unstable real pole); the error "
                     "constant design needs K0 > 0");
  r.root = d;
  r.limits = lead_limits(g, d);
  r.K_max_usable = usable_max(g, d, opt.max_ratio, &r.usable_design);
  r.K_des = K_des;
  if (K_des) {
    if (!(*K_des > 0.0) || !std::isfinite(*K_des))
      throw InputError("--K = " + num_text(*K_des) + ": the desired error constant must be > 0");
    if (r.limits.applicable && *K_des < r.limits.K_max) {
      r.design = design_for_constant(g, d, *K_des);
      r.within_max_ratio = r.design->p / r.design->z <= opt.max_ratio;
    } else {
      r.relocations = relocate(g, d, *K_des, opt.margin);
    }
  }
  return r;
}

}  // namespace gmslab::control
