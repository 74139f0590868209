// gmslab core/control: what `gmslab design` and Python's gmslab.design report - the design job
// (compute_design, core/control/design_session.hpp) run for the lead and, with a compensator type,
// for that type; the JSON is a view of the jobs' results (design_json, typed_compensator_json,
// simulation_json: pure functions of inputs and outputs).
//
// The JSON: to_json(LeadReport) (core/control/design_json.hpp) with "max_ratio", the chosen lead
// ("design_kind": requested, relocated:<path>, usable_maximum; a design that is not the requested
// one is also written at the top level: z, p, Kc, K, closed_loop_poles), "frequency" (margins,
// bandwidth, Nyquist of the chosen lead's loop, else the plant's own; "frequency.loop" says which;
// with sample_time > 0 "frequency.discrete": Tustin controller, ZOH plant) and "z_locus",
// "compensator" (exported coefficients), "plant" (plant_json), for a one-body scenario
// "limit_cycles" (the lead loop without compensation: the velocity-DF cycles with the stick-slip
// hunting under "hunting"; for a scenario or assembled plant the loop's periodic orbits under
// "periodic_orbits", core/control/limit_cycles.hpp), with lag_K "lead_lag" {zl, pl, K_lead, K,
// lag_angle_deg, closed_loop_poles, dominant, slow_pole, slow_time_constant_s, num, den,
// compensator}, with a compensator type "typed_compensator", with simulate "simulation" [one per
// compensation: the loop metrics, "compensation", "feedforward_source", and with the
// measured-velocity feedforward on a one-body scenario "limit_cycles" of F - F_hat].
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/control/design_session.hpp"

namespace gmslab::control {

struct DesignRequest {
  PlantChoice plant;  // typed num/den, a scenario's one body, or an assembled plant's drive -> output
  std::optional<Scenario> scenario;          // plant source scenario
  std::optional<AssemblyScenario> assembly;  // plant source assembly
  std::string source;                        // what "plant.source" says (the preset's path or name)
  Regime regime = Regime::Presliding;
  double velocity = 0.0;  // sliding operating velocity v0 [m/s] (0: default)
  DominantRoot root;
  std::optional<double> K;  // desired error constant (none: the usable maximum)
  LeadOptions options;
  double sample_time = 0.0;  // controller sample time [s] (0: continuous)
  std::optional<CompensatorType> compensator;  // also the Design view's compensator of this type
  std::optional<double> lag_K;                 // a lag after the chosen lead reaching this constant
  double lag_zero_fraction = 0.1;
  // The loops with friction (a scenario or assembled plant): of the compensator type's compensator
  // when there is one, else of the lead.
  bool simulate = false;
  Signal reference = Signal::constant(0.01);
  std::vector<Compensation> compensations;
  FeedforwardSource feedforward_source = FeedforwardSource::Reference;
  Mismatch mismatch;
  LoopTiming timing;
  // limit_cycles.periodic_orbits of the loop the report simulates (the compensator type's when
  // there is one, else the lead's): a scenario or assembled plant.
  bool periodic_orbits = true;
};

// The job's inputs for a request: the lead's job (typed = nullopt) or the compensator type's; report
// accuracy, no drawings; lag_K only for the lead, the loops only for the job whose compensator is
// simulated.
DesignInputs design_inputs(const DesignRequest& r, std::optional<CompensatorType> typed);

struct DesignReport {
  DesignInputs lead_in;
  DesignOutputs lead;
  std::optional<DesignInputs> typed_in;
  std::optional<DesignOutputs> typed;
  nlohmann::json json;
};
// Throws the lead job's first failure in its kind (InputError for a bad root or K, a bad plant;
// SimulationError for a diverging loop), InputError for lag_K or simulate without a design to use;
// a compensator type's failed design is reported in typed_compensator.error.
DesignReport design_report(const DesignRequest& r);

// The views. design_json: the lead job's keys (all but plant, typed_compensator, simulation); the
// job must have a lead report.
nlohmann::json design_json(const DesignInputs& in, const DesignOutputs& out);
// {"type", "kind", "error", "compensator" (compensator_json), "closed_loop_poles", "gain_point" {s,
// Kc} (lag / PI), "lag" {factor, K, K_without_lag, slow_pole, slow_time_constant_s} (infinite
// factor / K as null), "limit_cycles" (a scenario's plant: this compensator's loop without
// compensation, with "hunting" for a compensator with an integrator)}.
nlohmann::json typed_compensator_json(const DesignInputs& in, const DesignOutputs& out);
// The "simulation" array of the job's loops.
nlohmann::json simulation_json(const DesignInputs& in, const DesignOutputs& out);
// The "lead_lag" key.
nlohmann::json to_json(const LeadLagDesign& ll);
// limit_cycles.periodic_orbits: {orbits [{gain_scale, amplitude_m, period_s, mean_m,
// stick_fraction, multipliers [{re, im, abs}], multipliers_fresh, stable, residual, returns,
// map_evaluations, seed}], method, not_found (null when there are orbits), map_evaluations, dt_s
// (the loop's step: the simulation's, or the automatic one when the timing gives no step)};
// limit_cycles.map: {points [an orbit (with stable), along the branch], fold_gain_scale (the fold
// nearest the design's gain, or null), folds_gain_scale, note, map_evaluations}.
nlohmann::json to_json(const PeriodicOrbit& o);
nlohmann::json to_json(const OrbitReport& r);
nlohmann::json to_json(const HuntingMap& m);
// `gmslab cycles`: to_json(OrbitReport) with "compensator", "sample_time_s", "reference_m",
// "simulation" {hunting, amplitude_m, period_s (null without hunting), duration_s, record_step_s}
// (the job's loop without compensation, loop_metrics), "map" (the map's points), "fold_gain_scale",
// "map_note", "describing_function" {amplitude_m, period_s, valid, note} or null.
nlohmann::json cycles_json(const DesignInputs& in, const DesignOutputs& out);

}  // namespace gmslab::control
