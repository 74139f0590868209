// gmslab core/control: rational transfer functions G(s) = num(s) / den(s).
//
// A plant of type n is written G(s) = K0 N(s) / (s^n D(s)) with N(0) = D(0) = 1:
//   n  = number of poles at the origin (minus zeros there: a zero at the origin is rejected),
//   K0 = lim_{s->0} s^n G(s)  (the plant's part of the error constant Kp, Kv, Ka for n = 0, 1, 2).
#pragma once

#include <string>
#include <vector>

#include "core/control/polynomial.hpp"

namespace gmslab::control {

struct TransferFunction {
  Poly num;  // numerator
  Poly den;  // denominator (not the zero polynomial)

  cplx operator()(cplx s) const { return num(s) / den(s); }
  std::vector<cplx> poles() const { return den.roots(); }
  std::vector<cplx> zeros() const { return num.roots(); }
  int relative_degree() const { return den.degree() - num.degree(); }
  // Throws InputError (naming `what`) unless num != 0, den != 0 and deg num <= deg den.
  void check_proper(const std::string& what) const;
};

// System type n and K0 (see above). Throws InputError when num has a zero at the origin.
struct PlantType {
  int n = 0;        // poles at the origin
  double K0 = 0.0;  // lim s^n G(s)
};
PlantType plant_type(const TransferFunction& g);

// Name of the error constant for type n: "Kp", "Kv", "Ka", else "K<n>".
std::string error_constant_name(int n);

}  // namespace gmslab::control
