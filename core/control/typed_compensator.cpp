#include "core/control/typed_compensator.hpp"

#include <cmath>

#include "core/control/design_json.hpp"

namespace gmslab::control {

DesignInputs typed_design_inputs(const PlantChoice& choice, Regime regime, double velocity, const Scenario* scenario,
                                 const AssemblyScenario* assembly, const DominantRoot& root, std::optional<double> K,
                                 const LeadOptions& options, CompensatorType type, double sample_time) {
  DesignInputs in;
  if (scenario) in.scenario = *scenario;
  if (assembly) in.assembly = *assembly;
  in.plant = choice;
  in.regime = regime;
  in.velocity = velocity;
  in.root = root;
  in.K = K;
  in.options = options;
  in.type = type;
  in.sample_time = sample_time;
  in.simulate = false;
  return in;
}

TypedCompensator typed_compensator(DesignInputs in) {
  in.simulate = false;
  TypedCompensator r;
  r.outputs = compute_design(in);
  const DesignOutputs& out = r.outputs;
  const auto finite_or_null = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  nlohmann::json t = {{"type", to_string(in.type)}, {"kind", out.compensator_kind}, {"error", out.error}};
  if (out.compensator) {
    t["compensator"] = compensator_json(*out.compensator);
    t["closed_loop_poles"] = poles_json(out.closed_loop_poles);
  }
  if (out.gain_point)
    t["gain_point"] = {{"s", {out.gain_point->s.real(), out.gain_point->s.imag()}}, {"Kc", out.gain_point->k}};
  if (out.lag)
    t["lag"] = {{"factor", finite_or_null(out.lag->factor)},
                {"K", finite_or_null(out.lag->K)},
                {"K_without_lag", out.lag->K_gain_only},
                {"slow_pole", {out.lag->slow_pole.real(), out.lag->slow_pole.imag()}},
                {"slow_time_constant_s", out.lag->time_constant}};
  if (out.limit_cycles) {  // this compensator's loop (view-rate DF), with its hunting prediction
    t["limit_cycles"] = to_json(*out.limit_cycles);
    if (out.hunting) t["limit_cycles"]["hunting"] = to_json(*out.hunting);
  }
  r.json = std::move(t);
  return r;
}

}  // namespace gmslab::control
