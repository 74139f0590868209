// gmslab core/control: the "plant" object of `gmslab design --json` and of gmslab.design() (Python),
// from the one plant function (design_plant.hpp), so both write the same keys.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/control/design_plant.hpp"

namespace gmslab::control {

// {"source": the preset path, or "coefficients" for a typed plant, "plant_source": scenario |
//  assembly | typed, "label": what G(s) is,
//  scenario: "regime", "mass_kg", "stiffness_N_per_m", "damping_N_s_per_m", "velocity_m_per_s";
//  assembly: "regime", "drive", "output", "velocity_m_per_s" (the v0 asked for; 0: each contact's 10 Vs);
//  "num", "den": G's coefficients, highest power first}
nlohmann::json plant_json(const DesignPlant& p, const std::string& source, double velocity);

}  // namespace gmslab::control
