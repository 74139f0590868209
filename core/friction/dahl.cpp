#include "core/friction/dahl.hpp"

#include <cmath>

#include "core/friction/param_specs.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

ModelInfo dahl_model_info() {
  ModelInfo m;
  m.tag = "dahl";
  m.name = "Dahl";
  m.citation = "Dahl, The Aerospace Corporation TR-0158(3107-18)-1, 1968; AIAA J. 14(12), 1976";
  m.equation = "dF_d/dt = sigma0 v (1 - (F_d/Fc) sgn v)^a; F = F_d + sigma2 v";
  m.scalars = {
      specs::sigma0(),
      {"Fc", "F_c", "N", "Coulomb force level (the asymptote of the hysteresis)", 0, 1e7, true},
      {"a", "alpha", "-", "shape exponent of the Dahl curve (1: exponential)", 0.2, 10},
      specs::sigma2(),
  };
  m.defaults = [] { return ModelParams{"dahl", {1e5, 1.0, 1.0, 0.4}, {}}; };
  m.build = [](const ModelParams& p) { return std::make_unique<DahlModel>(p); };
  return m;
}

DahlModel::DahlModel(const ModelParams& p)
    : SingleStateModel(p),
      sigma0_(p.scalar("sigma0")),
      Fc_(p.scalar("Fc")),
      a_(p.scalar("a")),
      sigma2_(p.scalar("sigma2")) {}

double DahlModel::steady_state(double v) const { return sgn(v) * Fc_ + sigma2_ * v; }

double DahlModel::step(std::span<double> state, const FrictionInput& in) const {
  const double v = in.v;
  if (v == 0.0) return state[0];
  const double s = sgn(v);
  const double u = 1.0 - state[0] * s / Fc_;
  const double ch = sigma0_ * std::abs(v) * in.h / Fc_;
  double u1;
  if (a_ == 1.0) {
    u1 = u * std::exp(-ch);
  } else {
    const double e = 1.0 - a_;
    const double q = std::pow(std::abs(u), e) - e * ch;  // |u|^(1-a) evolves linearly in time
    const double mag = (a_ < 1.0) ? (q > 0.0 ? std::pow(q, 1.0 / e) : 0.0) : std::pow(q, 1.0 / e);
    u1 = (u < 0.0 ? -mag : mag);
    if (u == 0.0) u1 = 0.0;
  }
  state[0] = s * Fc_ * (1.0 - u1);
  return state[0] + sigma2_ * v;
}

}  // namespace gmslab
