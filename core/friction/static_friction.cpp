#include "core/friction/static_friction.hpp"

#include <algorithm>
#include <cmath>

#include "core/friction/param_specs.hpp"

namespace gmslab {

namespace {
ParamSpec v_stick_spec() {
  return {"v_stick", "Delta v", "m/s",
          "Karnopp stick band half-width: below it a body sticks (and prescribed motion uses a "
          "straight line through zero)",
          0, 1e3, true, true};
}
}  // namespace

ModelInfo coulomb_model_info() {
  ModelInfo m;
  m.tag = "coulomb";
  m.name = "Coulomb + viscous (Karnopp stick)";
  m.citation = "Coulomb 1785; stick band: Karnopp, ASME J. Dyn. Sys. Meas. Control 107, 1985";
  m.equation =
      "F = Fc sgn(v) + sigma2 v while sliding; sticking (|v| < v_stick or v would reverse in the "
      "step): F = f_other + m v / h clipped to +-Fs, so the body comes to rest";
  m.scalars = {specs::Fs(), specs::Fc(), specs::sigma2(), v_stick_spec()};
  m.defaults = [] {
    return ModelParams{"coulomb", {1.5, 1.0, 0.4, 1e-5}, {}};
  };
  m.check = specs::check_fc_le_fs;
  m.build = [](const ModelParams& p) { return std::make_unique<StaticFrictionModel>(p, true); };
  return m;
}

ModelInfo stribeck_model_info() {
  ModelInfo m;
  m.tag = "stribeck";
  m.name = "Stribeck static curve (Karnopp stick)";
  m.citation = "Stribeck 1902; Armstrong-Helouvry et al., Automatica 30(7), 1994; Karnopp 1985";
  m.equation =
      "F = sgn(v) S(v) + sigma2 v, S(v) = Fc + (Fs - Fc) exp(-(|v|/Vs)^delta) while sliding; "
      "sticking (|v| < v_stick or v would reverse in the step): F = f_other + m v / h clipped to "
      "+-Fs";
  m.scalars = {specs::Fs(), specs::Fc(), specs::Vs(), specs::delta(), specs::sigma2(),
               v_stick_spec()};
  m.defaults = [] {
    return ModelParams{"stribeck", {1.5, 1.0, 1e-3, 2.0, 0.4, 1e-5}, {}};
  };
  m.check = specs::check_fc_le_fs;
  m.build = [](const ModelParams& p) { return std::make_unique<StaticFrictionModel>(p, false); };
  return m;
}

StaticFrictionModel::StaticFrictionModel(const ModelParams& p, bool coulomb)
    : params_(p), coulomb_(coulomb), sigma2_(p.scalar("sigma2")), v_stick_(p.scalar("v_stick")) {
  S_.Fs = p.scalar("Fs");
  S_.Fc = p.scalar("Fc");
  if (!coulomb) {
    S_.Vs = p.scalar("Vs");
    S_.delta = p.scalar("delta");
  }
}

const ModelInfo& StaticFrictionModel::info() const {
  return model_info(coulomb_ ? "coulomb" : "stribeck");
}

double StaticFrictionModel::sliding_magnitude(double v) const {
  return coulomb_ ? S_.Fc : S_(v);
}

double StaticFrictionModel::steady_state(double v) const {
  return sgn(v) * sliding_magnitude(v) + sigma2_ * v;
}

double StaticFrictionModel::step(std::span<double>, const FrictionInput& in) const {
  const double v = in.v;
  if (in.mass <= 0.0) {  // prescribed motion: regularised curve inside the band
    if (std::abs(v) >= v_stick_) return steady_state(v);
    return (v / v_stick_) * (sliding_magnitude(v_stick_) + sigma2_ * v_stick_);
  }
  const double slide = steady_state(v);
  const double v_next = v + in.h * (in.f_other - slide) / in.mass;
  const bool sticks = std::abs(v) < v_stick_ || v_next * v < 0.0;
  if (!sticks) return slide;
  const double stop = in.f_other + in.mass * v / in.h;  // brings v to 0 in this step
  const double limit = std::max(S_.Fs, std::abs(slide));
  return std::clamp(stop, -limit, limit);
}

}  // namespace gmslab
