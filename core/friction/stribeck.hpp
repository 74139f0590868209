// gmslab core: the Stribeck magnitude shared by LuGre, elasto-plastic, Leuven and GMS.
//   S(v) = Fc + (Fs - Fc) exp(-(|v| / Vs)^delta)     [N], S > 0
#pragma once

#include <cmath>

namespace gmslab {

// exp(-x) for x >= 0, within 1 ulp of std::exp(-x), with fast paths for the regimes a
// friction simulation spends most steps in: x < 1/64 (the degree-7 Taylor polynomial, truncation
// error below x^8/8! < 1e-19; evaluated in Estrin's scheme, whose dependency chain is three
// multiply-adds deep instead of Horner's seven: this sits on the latency chain of every step) and
// x > 745 (underflow: exactly 0, avoiding libm's slow error path).
inline double exp_neg(double x) {
  if (x < 1.0 / 64) {
    const double x2 = x * x;
    const double x4 = x2 * x2;
    const double p01 = 1.0 - x;
    const double p23 = 1.0 / 2 - x * (1.0 / 6);
    const double p45 = 1.0 / 24 - x * (1.0 / 120);
    const double p67 = 1.0 / 720 - x * (1.0 / 5040);
    return p01 + (x2 * p23 + x4 * (p45 + x2 * p67));
  }
  if (x > 745.0) return 0.0;
  return std::exp(-x);
}

struct Stribeck {
  double Fs = 1.5;     // static (break-away) force level [N]
  double Fc = 1.0;     // Coulomb (sliding) force level [N]
  double Vs = 1e-3;    // Stribeck velocity [m/s]
  double delta = 2.0;  // Stribeck shape exponent [-]

  double operator()(double v) const { return at_scaled(std::abs(v) / Vs); }
  // S at |v| / Vs = r (lets hot loops precompute 1 / Vs).
  double at_scaled(double r) const {
    const double e = (delta == 2.0) ? r * r : std::pow(r, delta);
    return Fc + (Fs - Fc) * exp_neg(e);
  }
};

inline double sgn(double v) { return static_cast<double>((v > 0.0) - (v < 0.0)); }

}  // namespace gmslab
