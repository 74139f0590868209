// Helpers shared by the core tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "core/friction/gms.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab::test_util {

inline std::string preset_path(const std::string& name) {
  return std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name;
}

inline std::string shared_dir() {
  if (const char* s = std::getenv("GMSLAB_SHARED")) return s;
  return std::string(GMSLAB_SOURCE_DIR) + "/../shared";
}

// A scenario driving the GMS reference set (no micro-damping) by a displacement signal.
inline Scenario gms_displacement_scenario(const Signal& x, double duration, double dt = 1e-3) {
  Scenario s;
  s.name = "test";
  s.friction = GmsParams::reference(false).to_params();
  s.drive.kind = Drive::Kind::Displacement;
  s.drive.signal = x;
  s.run.dt = dt;
  s.run.duration = duration;
  return s;
}

// Value of a trace column at time t (nearest sample).
inline double at_time(const Trace& tr, const std::vector<double>& col, double t) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < tr.size(); ++k)
    if (std::abs(tr.t[k] - t) < std::abs(tr.t[best] - t)) best = k;
  return col[best];
}

// Every sample column of a equals b's, value for value (element columns included).
inline void expect_same_samples(const Trace& a, const Trace& b) {
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.friction, b.friction);
  EXPECT_EQ(a.applied, b.applied);
  EXPECT_EQ(a.element_force, b.element_force);
  EXPECT_EQ(a.element_slip, b.element_slip);
}

}  // namespace gmslab::test_util
