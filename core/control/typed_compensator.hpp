// gmslab core/control: the Design view's compensator of a type (lead, lag, lead-lag, PI, PID) as
// `gmslab design --compensator TYPE` and Python's gmslab.design(..., compensator=TYPE) report it:
// compute_design() (the view's own function, loops not simulated) and the "typed_compensator" JSON
// {type, kind, error, compensator {num, den, Kc, z, p, sections, matlab, python} (compensator_json),
// closed_loop_poles [[re, im], ...], gain_point {s [re, im], Kc} (lag / PI), lag {factor, K,
// K_without_lag, slow_pole [re, im], slow_time_constant_s} (infinite factor / K as null),
// limit_cycles (a scenario's plant: the describing-function prediction for this compensator's loop
// without compensation, as the view's; to_json(LimitCycleReport))}.
// A failed design is reported in "error" (no compensator), as the view reports it.
#pragma once

#include <nlohmann/json.hpp>

#include "core/control/design_session.hpp"

namespace gmslab::control {

// The inputs `gmslab design` and gmslab.design build: the plant choice (scenario / assembly when
// given), regime, operating velocity [m/s], desired roots, K (none: the usable maximum / 10x), the
// lead's options, the type and the controller sample time [s].
DesignInputs typed_design_inputs(const PlantChoice& choice, Regime regime, double velocity, const Scenario* scenario,
                                 const AssemblyScenario* assembly, const DominantRoot& root, std::optional<double> K,
                                 const LeadOptions& options, CompensatorType type, double sample_time);

struct TypedCompensator {
  DesignOutputs outputs;  // compute_design's, with `simulate` off
  nlohmann::json json;    // the "typed_compensator" key
};
TypedCompensator typed_compensator(DesignInputs in);

}  // namespace gmslab::control
