// Test helpers shared by tests/models and tests/figures: the protocols of docs/references.md run
// with any registered model, and the measurements the reference numbers are stated in.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"
#include "tests/core/test_util.hpp"

namespace gmslab::testing {

using test_util::at_time;
using test_util::preset_path;

// Every registered model tag.
inline std::vector<std::string> all_tags() {
  std::vector<std::string> t;
  for (const auto& m : model_registry()) t.emplace_back(m.tag);
  return t;
}

// The preset's scenario with its friction replaced by the defaults of `tag` ("gms": unchanged).
inline Scenario preset_with(const std::string& preset, const std::string& tag) {
  Scenario s = load_scenario(preset_path(preset));
  if (tag != s.friction.model) s.friction = model_info(tag).defaults();
  return s;
}

// y at the first crossing of x through x0 in the given direction (+1 rising, -1 falling), at or
// after time t_from, linearly interpolated; NaN if none.
inline double value_at_crossing(const std::vector<double>& t, const std::vector<double>& x,
                                const std::vector<double>& y, double x0, int direction,
                                double t_from = -1e300) {
  for (std::size_t k = 1; k < x.size(); ++k) {
    if (t[k - 1] < t_from) continue;
    const double a = direction * (x[k - 1] - x0), b = direction * (x[k] - x0);
    if (a < 0.0 && b >= 0.0) return y[k - 1] + (y[k] - y[k - 1]) * (x0 - x[k - 1]) / (x[k] - x[k - 1]);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Steps a model along prescribed positions x[0..n] with step h (mass 0); returns the forces
// (one per step) and accumulates the work W = sum F_k (x_{k+1} - x_k) [J].
struct Drive1 {
  std::vector<double> force;
  double work = 0.0;
};
inline Drive1 drive_positions(const FrictionModel& m, std::vector<double>& state,
                              const std::vector<double>& x, double h) {
  Drive1 out;
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double dx = x[k + 1] - x[k];
    const double f = m.step(state, {dx / h, h, 0.0, 0.0});
    out.force.push_back(f);
    out.work += f * dx;
  }
  return out;
}

}  // namespace gmslab::testing
