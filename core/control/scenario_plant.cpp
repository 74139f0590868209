#include "core/control/scenario_plant.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/friction/param_specs.hpp"

namespace gmslab::control {

const char* to_string(Regime r) { return r == Regime::Presliding ? "presliding" : "sliding"; }

Regime regime_from_string(const std::string& s) {
  if (s == "presliding") return Regime::Presliding;
  if (s == "sliding") return Regime::Sliding;
  throw InputError("--regime '" + s + "': expected presliding or sliding");
}

namespace {
double scalar_or(const ModelParams& p, const char* key, double fallback) {
  const auto i = model_info(p.model).scalar_index(key);
  return i >= 0 ? p.scalars[static_cast<std::size_t>(i)] : fallback;
}
double column_sum(const ModelParams& p, const char* key) {
  const auto c = model_info(p.model).column_index(key);
  double s = 0.0;
  if (c >= 0)
    for (const auto& row : p.elements) s += row[static_cast<std::size_t>(c)];
  return s;
}
}  // namespace

double default_sliding_velocity(const ModelParams& friction) {
  const double vs = scalar_or(friction, "Vs", 0.0);
  return vs > 0.0 ? 10.0 * vs : 0.01;
}

LinearPlant linear_plant(const Scenario& s, Regime r, double v0) {
  const Plant& pl = s.plant;
  if (!(pl.mass > 0.0) || pl.spring < 0.0 || pl.damper < 0.0)
    throw InputError("plant: mass must be > 0 kg, spring and damper >= 0");
  LinearPlant lp;
  lp.regime = r;
  lp.mass = pl.mass;
  if (r == Regime::Presliding) {
    lp.stiffness = pl.spring + column_sum(s.friction, "k") + scalar_or(s.friction, "sigma0", 0.0);
    lp.damping = pl.damper + column_sum(s.friction, "sigma") + scalar_or(s.friction, "sigma1", 0.0) +
                 scalar_or(s.friction, "sigma2", 0.0);
  } else {
    if (v0 == 0.0) v0 = default_sliding_velocity(s.friction);
    if (!(v0 > 0.0) || !std::isfinite(v0))
      throw InputError("--velocity = " + specs::num(v0) +
                       " m/s: the sliding operating velocity must be > 0");
    const auto model = build_model(s.friction);
    const double h = 1e-4 * v0;  // central difference of the steady-state curve
    const double slope = (model->steady_state(v0 + h) - model->steady_state(v0 - h)) / (2 * h);
    lp.velocity = v0;
    lp.stiffness = pl.spring;
    lp.damping = pl.damper + slope;
  }
  lp.g = {Poly({1.0}), Poly({lp.stiffness, lp.damping, lp.mass})};
  return lp;
}

}  // namespace gmslab::control
