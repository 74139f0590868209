// gmslab core: the Stribeck magnitude shared by LuGre, elasto-plastic, Leuven and GMS.
//   S(v) = Fc + (Fs - Fc) exp(-(|v| / Vs)^delta)     [N], S > 0
#pragma once

#include <cmath>

namespace gmslab {

struct Stribeck {
  double Fs = 1.5;     // static (break-away) force level [N]
  double Fc = 1.0;     // Coulomb (sliding) force level [N]
  double Vs = 1e-3;    // Stribeck velocity [m/s]
  double delta = 2.0;  // Stribeck shape exponent [-]

  double operator()(double v) const {
    const double r = std::abs(v) / Vs;
    const double e = (delta == 2.0) ? r * r : std::pow(r, delta);
    return Fc + (Fs - Fc) * std::exp(-e);
  }
};

inline double sgn(double v) { return static_cast<double>((v > 0.0) - (v < 0.0)); }

}  // namespace gmslab
