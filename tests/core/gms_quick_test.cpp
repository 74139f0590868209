#include <gtest/gtest.h>

#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"

using namespace gmslab;

TEST(GmsQuick, Fig2aTurningPoints) {
  const auto sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2a_presliding.json");
  const auto tr = simulate(sc);
  ASSERT_GT(tr.size(), 100u);
}
