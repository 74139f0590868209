#include "core/control/transfer_function.hpp"

#include "core/error.hpp"

namespace gmslab::control {

void TransferFunction::check_proper(const std::string& what) const {
  if (num.is_zero()) throw InputError(what + ": the numerator is zero");
  if (den.is_zero()) throw InputError(what + ": the denominator is zero");
  if (num.degree() > den.degree())
    throw InputError(what + ": improper transfer function (numerator degree " +
                     std::to_string(num.degree()) + " > denominator degree " +
                     std::to_string(den.degree()) + "); allowed: deg num <= deg den");
}

PlantType plant_type(const TransferFunction& g) {
  if (g.num.zeros_at_origin() > 0)
    throw InputError("plant: the numerator has a zero at s = 0, so every error constant is 0; "
                     "remove the factor s from the numerator and the denominator");
  PlantType t;
  t.n = g.den.zeros_at_origin();
  t.K0 = g.num.coeff(0) / g.den.coeff(t.n);
  return t;
}

std::string error_constant_name(int n) {
  switch (n) {
    case 0: return "Kp";
    case 1: return "Kv";
    case 2: return "Ka";
    default: return "K" + std::to_string(n);
  }
}

}  // namespace gmslab::control
