// gmslab core: the Stribeck magnitude shared by LuGre, elasto-plastic, Leuven and GMS.
//   S(v) = Fc + (Fs - Fc) exp(-(|v| / Vs)^delta)     [N], S > 0
#pragma once

#include <cmath>

namespace gmslab {

// exp(-x) for x >= 0, equal to std::exp to rounding, with fast paths for the two regimes a
// friction simulation spends most steps in: x < 2e-3 (a 5th-order Taylor series, truncation error
// below x^6/720 < 1e-19) and x > 745 (underflow: exactly 0, avoiding libm's slow error path).
inline double exp_neg(double x) {
  if (x < 2e-3) return 1.0 - x * (1.0 - x * (0.5 - x * (1.0 / 6 - x * (1.0 / 24 - x * (1.0 / 120)))));
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
