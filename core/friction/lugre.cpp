#include "core/friction/lugre.hpp"

#include <cmath>

#include "core/friction/param_specs.hpp"

namespace gmslab {

ModelInfo lugre_model_info() {
  ModelInfo m;
  m.tag = "lugre";
  m.name = "LuGre";
  m.citation = "Canudas de Wit, Olsson, Astrom, Lischinsky, IEEE TAC 40(3), 1995";
  m.equation =
      "dz/dt = v - sigma0 |v| z / S(v); F = sigma0 z + sigma1 dz/dt + sigma2 v; "
      "S(v) = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta)";
  m.scalars = {specs::sigma0(), specs::sigma1(), specs::sigma2(), specs::Fs(),
               specs::Fc(),     specs::Vs(),     specs::delta()};
  m.defaults = [] {
    return ModelParams{"lugre", {1e5, std::sqrt(1e5), 0.4, 1.5, 1.0, 1e-3, 2.0}, {}};
  };
  m.check = specs::check_fc_le_fs;
  m.build = [](const ModelParams& p) { return std::make_unique<LuGreModel>(p); };
  return m;
}

LuGreModel::LuGreModel(const ModelParams& p)
    : SingleStateModel(p),
      S_(specs::stribeck_from(p)),
      sigma0_(p.scalar("sigma0")),
      sigma1_(p.scalar("sigma1")),
      sigma2_(p.scalar("sigma2")) {}

double LuGreModel::steady_state(double v) const { return sgn(v) * S_(v) + sigma2_ * v; }

double LuGreModel::step(std::span<double> state, const FrictionInput& in) const {
  const double v = in.v;
  const double z0 = state[0];
  if (v == 0.0) return sigma0_ * z0;
  const double g = S_(v);
  const double z_ss = sgn(v) * g / sigma0_;
  const double z1 = z_ss + (z0 - z_ss) * std::exp(-sigma0_ * std::abs(v) * in.h / g);
  state[0] = z1;
  return sigma0_ * z1 + sigma1_ * (z1 - z0) / in.h + sigma2_ * v;
}

}  // namespace gmslab
