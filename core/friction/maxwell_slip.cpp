#include "core/friction/maxwell_slip.hpp"

#include <algorithm>
#include <numeric>

#include "core/friction/param_specs.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab {

ModelInfo maxwell_slip_model_info() {
  ModelInfo m;
  m.tag = "maxwell_slip";
  m.name = "Maxwell-slip (Jenkin elements)";
  m.citation = "Iwan, J. Appl. Mech. 33, 1966; Lampaert, Al-Bender, Swevers, Tribology Letters "
               "16(1-2), 2004";
  m.equation =
      "stick: dF_i/dt = k_i v while |F_i| < W_i; slip: F_i = W_i sgn(v) until v reverses; "
      "F = sum F_i + sigma2 v";
  m.scalars = {specs::sigma2()};
  m.columns = {
      {"k", "k_i", "N/m", "element stiffness (presliding)", 0, 1e12, true, true},
      {"W", "W_i", "N", "element slip (saturation) force", 0, 1e7, true, true},
  };
  m.min_elements = 1;
  m.max_elements = 100000;
  m.defaults = [] {  // the GMS reference set with S = Fs: break-away at 2, 5, 10, 20 um
    return ModelParams{"maxwell_slip",
                       {0.4},
                       {{75000, 0.15}, {60000, 0.3}, {45000, 0.45}, {30000, 0.6}}};
  };
  m.build = [](const ModelParams& p) { return std::make_unique<MaxwellSlipModel>(p); };
  return m;
}

MaxwellSlipModel::MaxwellSlipModel(const ModelParams& p)
    : params_(p), k_(p.column("k")), W_(p.column("W")), sigma2_(p.scalar("sigma2")) {
  W_total_ = std::accumulate(W_.begin(), W_.end(), 0.0);
}

const ModelInfo& MaxwellSlipModel::info() const { return model_info("maxwell_slip"); }

void MaxwellSlipModel::reset(std::span<double> state) const {
  std::fill(state.begin(), state.end(), 0.0);
}

double MaxwellSlipModel::steady_state(double v) const { return sgn(v) * W_total_ + sigma2_ * v; }

double MaxwellSlipModel::step(std::span<double> state, const FrictionInput& in) const {
  const std::size_t n = k_.size();
  const double vh = in.v * in.h;
  const double s = sgn(in.v);
  double* F = state.data();
  double* d = state.data() + n;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = F[i] + k_[i] * vh;
    const bool slips = s * f >= W_[i] && s != 0.0;  // pushed to its limit in the direction of v
    F[i] = slips ? s * W_[i] : std::clamp(f, -W_[i], W_[i]);
    d[i] = slips ? s : 0.0;
    sum += F[i];
  }
  return sum + sigma2_ * in.v;
}

ElementState MaxwellSlipModel::element(std::span<const double> state, std::size_t i) const {
  return {state[i], state[k_.size() + i] != 0.0};
}

}  // namespace gmslab
