// gmslab core: parameter specs shared by several friction models (one definition, so every model
// names, ranges and documents its Stribeck and viscous parameters the same way), plus the
// cross-field checks they share.
#pragma once

#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab::specs {

inline ParamSpec Fs() {
  return {"Fs", "F_s", "N", "static (break-away) force level of the Stribeck curve", 0, 1e7, true};
}
inline ParamSpec Fc() {
  return {"Fc", "F_c", "N", "Coulomb (sliding) force level, Fc <= Fs", 0, 1e7, true};
}
inline ParamSpec Vs() {
  return {"Vs", "V_s", "m/s", "Stribeck velocity", 0, 1e3, true, true};
}
inline ParamSpec delta() { return {"delta", "delta", "-", "Stribeck shape exponent", 0.1, 10}; }
inline ParamSpec sigma2() {
  return {"sigma2", "sigma_2", "N s/m", "viscous friction coefficient", 0, 1e7};
}
inline ParamSpec sigma0() {
  return {"sigma0", "sigma_0", "N/m", "bristle (presliding) stiffness", 0, 1e12, true, true};
}
inline ParamSpec sigma1() {
  return {"sigma1", "sigma_1", "N s/m", "bristle (micro-)damping", 0, 1e9};
}

// Stribeck curve from the scalars Fs, Fc, Vs, delta of p.
inline Stribeck stribeck_from(const ModelParams& p) {
  return {p.scalar("Fs"), p.scalar("Fc"), p.scalar("Vs"), p.scalar("delta")};
}

// "Fc must not exceed Fs" when it does.
void check_fc_le_fs(const ModelParams& p, std::vector<std::string>& out);
std::string num(double x);  // short decimal text for messages

}  // namespace gmslab::specs
