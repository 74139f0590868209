#include "core/friction/elastoplastic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/friction/param_specs.hpp"

namespace gmslab {

ModelInfo elastoplastic_model_info() {
  ModelInfo m;
  m.tag = "elastoplastic";
  m.name = "Elasto-plastic (Dupont)";
  m.citation = "Dupont, Hayward, Armstrong, Altpeter, IEEE TAC 47(5), 2002";
  m.equation =
      "dz/dt = v (1 - alpha(z,v) sigma0 z sgn(v) / S(v)), alpha = 0 for |z| <= z_ba or "
      "sgn z != sgn v, sine ramp to 1 at z_max = S(v)/sigma0; F = sigma0 z + sigma1 dz/dt + "
      "sigma2 v";
  m.scalars = {specs::sigma0(), specs::sigma1(), specs::sigma2(), specs::Fs(), specs::Fc(),
               specs::Vs(),     specs::delta(),
               {"z_ba", "z_ba", "m",
                "elastic (break-away) displacement: below it the bristles are purely elastic; "
                "z_ba < Fc / sigma0",
                0, 1, true, true}};
  m.defaults = [] {
    return ModelParams{"elastoplastic", {1e5, std::sqrt(1e5), 0.4, 1.5, 1.0, 1e-3, 2.0, 9e-6}, {}};
  };
  m.check = [](const ModelParams& p, std::vector<std::string>& out) {
    specs::check_fc_le_fs(p, out);
    const double zmin = p.scalar("Fc") / p.scalar("sigma0");
    if (!(p.scalar("z_ba") < zmin))
      out.push_back("z_ba must be below Fc / sigma0 = " + specs::num(zmin) + " m (z_ba = " +
                    specs::num(p.scalar("z_ba")) + " m), so the plastic ramp exists at every "
                    "velocity");
  };
  m.build = [](const ModelParams& p) { return std::make_unique<ElastoPlasticModel>(p); };
  return m;
}

ElastoPlasticModel::ElastoPlasticModel(const ModelParams& p)
    : SingleStateModel(p),
      S_(specs::stribeck_from(p)),
      sigma0_(p.scalar("sigma0")),
      sigma1_(p.scalar("sigma1")),
      sigma2_(p.scalar("sigma2")),
      z_ba_(p.scalar("z_ba")) {}

double ElastoPlasticModel::steady_state(double v) const { return sgn(v) * S_(v) + sigma2_ * v; }

double ElastoPlasticModel::ramp_rate(double w, double u, double w_max) const {
  if (w <= z_ba_) return u;                         // RK4 stages may leave the ramp:
  if (w >= w_max) return u * (1.0 - w / w_max);     // use the law that holds there
  const double mid = 0.5 * (w_max + z_ba_);
  const double alpha = 0.5 + 0.5 * std::sin(std::numbers::pi * (w - mid) / (w_max - z_ba_));
  return u * (1.0 - alpha * w / w_max);
}

double ElastoPlasticModel::advance_w(double w, double u, double w_max, double h) const {
  if (w >= w_max) return w_max + (w - w_max) * std::exp(-u * h / w_max);  // plastic, exact
  if (w < z_ba_) {                                                         // elastic, exact
    const double t_ba = (z_ba_ - w) / u;
    if (t_ba >= h) return w + u * h;
    w = z_ba_;
    h -= t_ba;
  }
  // Ramp: classical RK4 on adaptive sub-steps, each limited by the local Lipschitz constant of
  // u (1 - alpha w / w_max) (L hs <= 1/5) and to 1/16 of the ramp width of travel. Once alpha is 1
  // to within 1e-10 the remaining time is the exact exponential of the plastic law.
  const double width = w_max - z_ba_, c = std::numbers::pi / width, mid = 0.5 * (w_max + z_ba_);
  while (h > 0.0 && w < w_max) {
    const double phase = c * (w - mid);
    const double alpha = 0.5 + 0.5 * std::sin(phase);
    if (1.0 - alpha < 1e-10) return w_max + (w - w_max) * std::exp(-u * h / w_max);
    const double dalpha = std::abs(0.5 * c * std::cos(phase));  // cos(-pi/2) may be -1e-17
    const double lipschitz = u * (dalpha * w + alpha + 1e-6) / w_max;  // > 0
    const double travel_rate = u * (1.0 - alpha * w / w_max);
    const double hs = std::min({h, 0.2 / lipschitz, 0.0625 * width / travel_rate});
    const double k1 = travel_rate;
    const double k2 = ramp_rate(w + 0.5 * hs * k1, u, w_max);
    const double k3 = ramp_rate(w + 0.5 * hs * k2, u, w_max);
    const double k4 = ramp_rate(w + hs * k3, u, w_max);
    w = std::min(w + hs * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0, w_max);
    h -= hs;
  }
  return w;
}

double ElastoPlasticModel::step(std::span<double> state, const FrictionInput& in) const {
  const double v = in.v;
  const double z0 = state[0];
  if (v == 0.0) return sigma0_ * z0;
  const double s = sgn(v);
  const double z1 = s * advance_w(s * z0, std::abs(v), S_(v) / sigma0_, in.h);
  state[0] = z1;
  return sigma0_ * z1 + sigma1_ * (z1 - z0) / in.h + sigma2_ * v;
}

}  // namespace gmslab
