#include "core/control/design_plant_json.hpp"

namespace gmslab::control {

nlohmann::json plant_json(const DesignPlant& p, const std::string& source, double velocity) {
  const LinearPlant& lp = p.linear;
  nlohmann::json j = {{"source", p.source == PlantSource::Typed ? std::string("coefficients") : source},
                      {"plant_source", to_string(p.source)},
                      {"label", p.label}};
  if (p.source == PlantSource::Scenario)
    j.update({{"regime", to_string(lp.regime)}, {"mass_kg", lp.mass}, {"stiffness_N_per_m", lp.stiffness},
              {"damping_N_s_per_m", lp.damping}, {"velocity_m_per_s", lp.velocity}});
  if (p.source == PlantSource::Assembly)
    j.update({{"regime", to_string(lp.regime)}, {"drive", p.port.drive_name}, {"output", p.port.output},
              {"velocity_m_per_s", velocity}});
  j["num"] = lp.g.num.descending_coeffs();
  j["den"] = lp.g.den.descending_coeffs();
  return j;
}

}  // namespace gmslab::control
