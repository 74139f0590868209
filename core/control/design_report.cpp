#include "core/control/design_report.hpp"

#include <cmath>

#include "core/control/design_json.hpp"
#include "core/control/design_plant_json.hpp"
#include "core/error.hpp"

namespace gmslab::control {

namespace {
nlohmann::json finite_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }
nlohmann::json pair_json(cplx s) { return {s.real(), s.imag()}; }

// limit_cycles with the job's periodic orbits and map (created when the DF did not write it).
void add_orbits(nlohmann::json& lc_parent, const DesignOutputs& out) {
  if (!out.orbits) return;
  nlohmann::json& lc = lc_parent["limit_cycles"];
  if (lc.is_null()) lc = nlohmann::json::object();
  lc["periodic_orbits"] = to_json(*out.orbits);
  if (out.hunting_map) lc["map"] = to_json(*out.hunting_map);
}
}  // namespace

nlohmann::json to_json(const PeriodicOrbit& o) {
  nlohmann::json mu = nlohmann::json::array();
  for (const auto& m : o.multipliers)
    mu.push_back({{"re", m.real()}, {"im", m.imag()}, {"abs", std::abs(m)}});
  return {{"gain_scale", o.gain_scale},
          {"amplitude_m", o.amplitude},
          {"period_s", o.period},
          {"mean_m", o.mean},
          {"stick_fraction", o.stick_fraction},
          {"multipliers", mu},
          {"multipliers_fresh", o.multipliers_fresh},
          {"stable", o.stable},
          {"growth_per_period", o.growth},
          {"residual", o.residual},
          {"returns", o.returns},
          {"map_evaluations", o.map_evaluations},
          {"seed", o.seed}};
}

nlohmann::json to_json(const OrbitReport& r) {
  nlohmann::json orbits = nlohmann::json::array();
  for (const PeriodicOrbit& o : r.orbits) orbits.push_back(to_json(o));
  nlohmann::json j = {{"orbits", orbits},
                      {"method", r.method},
                      {"map_evaluations", r.map_evaluations},
                      {"dt_s", r.dt}};
  j["not_found"] = r.not_found.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.not_found);
  return j;
}

nlohmann::json to_json(const HuntingMap& m) {
  nlohmann::json pts = nlohmann::json::array();
  for (const HuntingMapPoint& p : m.points) {
    if (p.orbit)
      pts.push_back(to_json(*p.orbit));
    else
      pts.push_back({{"gain_scale", p.gain_scale}, {"orbit", nullptr}});
  }
  return {{"points", pts},
          {"fold_gain_scale", m.fold ? nlohmann::json(*m.fold) : nlohmann::json(nullptr)},
          {"folds_gain_scale", m.folds},
          {"note", m.note},
          {"map_evaluations", m.map_evaluations}};
}

nlohmann::json cycles_json(const DesignInputs& in, const DesignOutputs& out) {
  if (!out.orbits || !out.compensator)
    throw InternalError("cycles report: the design job has no orbits (" + out.error + ")");
  nlohmann::json j = to_json(*out.orbits);
  j["compensator"] = compensator_json(*out.compensator);
  j["sample_time_s"] = in.sample_time;
  j["reference_m"] = in.reference(0.0);
  if (!out.loops.empty() && !out.loops.front().trace.t.empty()) {
    const LoopRun& run = out.loops.front();
    const double dt = run.trace.t.size() > 1
                          ? run.trace.t.back() / static_cast<double>(run.trace.t.size() - 1)
                          : 0.0;
    j["simulation"] = {
        {"hunting", run.metrics.hunting},
        {"amplitude_m", run.metrics.hunting ? nlohmann::json(run.metrics.cycle_amplitude)
                                            : nlohmann::json(nullptr)},
        {"period_s",
         run.metrics.hunting ? nlohmann::json(run.metrics.cycle_period) : nlohmann::json(nullptr)},
        {"duration_s", run.trace.t.back()},
        {"record_step_s", dt}};
  }
  if (out.hunting_map) {
    const nlohmann::json m = to_json(*out.hunting_map);
    j["map"] = m["points"];
    j["fold_gain_scale"] = m["fold_gain_scale"];
    j["map_note"] = m["note"];
  }
  const HuntingCycle* hc = out.hunting ? out.hunting->hunting() : nullptr;
  j["describing_function"] =
      hc ? nlohmann::json{{"amplitude_m", hc->amplitude},
                          {"period_s", hc->period},
                          {"valid", hc->valid},
                          {"note", "quick estimate (hunting describing function)"}}
         : nlohmann::json(nullptr);
  return j;
}

DesignInputs design_inputs(const DesignRequest& r, std::optional<CompensatorType> typed) {
  DesignInputs in;
  if (r.scenario) in.scenario = *r.scenario;
  in.assembly = r.assembly;
  in.plant = r.plant;
  in.regime = r.regime;
  in.velocity = r.velocity;
  in.root = r.root;
  in.K = r.K;
  in.options = r.options;
  in.type = typed ? *typed : CompensatorType::Lead;
  in.sample_time = r.sample_time;
  in.accuracy = Accuracy::Report;
  in.view = false;
  in.lag_zero_fraction = r.lag_zero_fraction;
  if (!typed) in.lag_K = r.lag_K;
  // The loops with friction are the compensator type's when there is one, else the lead's.
  in.simulate = r.simulate && (r.scenario || r.assembly) && typed.has_value() == r.compensator.has_value();
  in.reference = r.reference;
  // A job that does not simulate predicts only the loop without compensation.
  in.loop_compensations = in.simulate ? r.compensations : std::vector<Compensation>{Compensation::None};
  in.feedforward_source = r.feedforward_source;
  in.mismatch = r.mismatch;
  in.loop_timing = r.timing;
  // The orbits of the loop whose compensator the report simulates (or would).
  in.periodic_orbits = r.periodic_orbits && (r.scenario || r.assembly) &&
                       typed.has_value() == r.compensator.has_value();
  return in;
}

nlohmann::json to_json(const LeadLagDesign& ll) {
  const TransferFunction c = ll.tf();
  nlohmann::json j = {{"zl", ll.zl}, {"pl", ll.pl}, {"K_lead", ll.K_lead}, {"K", ll.K},
                      {"lag_angle_deg", ll.lag_angle_deg}, {"closed_loop_poles", poles_json(ll.closed_loop_poles)},
                      {"dominant", pair_json(ll.dominant)}, {"slow_pole", pair_json(ll.slow_pole)},
                      {"slow_time_constant_s", ll.time_constant},
                      {"num", c.num.descending_coeffs()}, {"den", c.den.descending_coeffs()}};
  // The two-section compensator for export (MATLAB / python-control code, sections).
  j["compensator"] = compensator_json(LeadCompensator{ll.lead.Kc, ll.lead.z, ll.lead.p, Section{ll.zl, ll.pl}});
  return j;
}

nlohmann::json design_json(const DesignInputs& in, const DesignOutputs& out) {
  if (!out.report) throw InternalError("design report: the design job has no lead report (" + out.error + ")");
  const LeadReport& r = *out.report;
  nlohmann::json j = to_json(r);
  j["max_ratio"] = in.options.max_ratio;
  const auto chosen = chosen_lead(r);
  if (chosen) {
    j["design_kind"] = chosen->first;
    if (!r.design) {  // report the chosen design at the top level too
      const LeadDesign& d = chosen->second;
      j["z"] = d.z, j["p"] = d.p, j["Kc"] = d.Kc, j["K"] = d.K;
      j["closed_loop_poles"] = poles_json(d.closed_loop_poles);
    }
  }
  if (out.frequency) {  // of the chosen design's loop (the plant's own when there is none)
    j["frequency"] = to_json(*out.frequency);
    j["frequency"]["loop"] = out.compensator ? "compensated" : "plant";
  }
  if (out.compensator) j["compensator"] = compensator_json(*out.compensator);
  if (out.discrete) j["frequency"]["discrete"] = to_json(*out.discrete);
  if (out.z_locus && out.compensator) j["z_locus"] = to_json(*out.z_locus, out.compensator->Kc);
  if (out.limit_cycles) {
    j["limit_cycles"] = to_json(*out.limit_cycles);
    if (out.hunting) j["limit_cycles"]["hunting"] = to_json(*out.hunting);
  }
  add_orbits(j, out);
  if (out.lead_lag && in.lag_K) j["lead_lag"] = to_json(*out.lead_lag);
  return j;
}

nlohmann::json typed_compensator_json(const DesignInputs& in, const DesignOutputs& out) {
  nlohmann::json t = {{"type", to_string(in.type)}, {"kind", out.compensator_kind}, {"error", out.error}};
  if (out.compensator) {
    t["compensator"] = compensator_json(*out.compensator);
    t["closed_loop_poles"] = poles_json(out.closed_loop_poles);
  }
  if (out.gain_point) t["gain_point"] = {{"s", pair_json(out.gain_point->s)}, {"Kc", out.gain_point->k}};
  if (out.lag)
    t["lag"] = {{"factor", finite_or_null(out.lag->factor)},
                {"K", finite_or_null(out.lag->K)},
                {"K_without_lag", out.lag->K_gain_only},
                {"slow_pole", pair_json(out.lag->slow_pole)},
                {"slow_time_constant_s", out.lag->time_constant}};
  if (out.limit_cycles) {  // this compensator's loop, with its hunting prediction when it has an integrator
    t["limit_cycles"] = to_json(*out.limit_cycles);
    if (out.hunting && out.compensator && integral_split(*out.compensator))
      t["limit_cycles"]["hunting"] = to_json(*out.hunting);
  }
  add_orbits(t, out);
  return t;
}

nlohmann::json simulation_json(const DesignInputs& in, const DesignOutputs& out) {
  nlohmann::json a = nlohmann::json::array();
  for (const LoopRun& run : out.loops) {
    nlohmann::json j = to_json(run.metrics);
    j["compensation"] = to_string(run.compensation);
    if (run.compensation == Compensation::None) {
      a.push_back(j);
      continue;
    }
    j["feedforward_source"] = to_string(in.feedforward_source);
    // Driven by the measured velocity, the compensated loop's nonlinearity is F - F_hat: its
    // describing-function prediction (one-body plants).
    if (in.feedforward_source == FeedforwardSource::Measured && out.source == PlantSource::Scenario && run.limit_cycles)
      j["limit_cycles"] = to_json(*run.limit_cycles);
    a.push_back(j);
  }
  return a;
}

DesignReport design_report(const DesignRequest& r) {
  DesignReport rep;
  rep.lead_in = design_inputs(r, std::nullopt);
  rep.lead = compute_design(rep.lead_in);
  throw_failure(rep.lead);
  const LeadReport& lr = *rep.lead.report;
  nlohmann::json& j = rep.json;
  j = design_json(rep.lead_in, rep.lead);
  j["plant"] = plant_json(DesignPlant{rep.lead.source, rep.lead.plant, rep.lead.port, rep.lead.plant_label},
                          r.source, r.velocity);
  if (r.lag_K && !chosen_lead(lr))
    throw InputError("--lag-K: no lead design to add a lag to (" + lr.limits.reason + ")");
  if (r.compensator) {  // the Design view's compensator of that type
    rep.typed_in = design_inputs(r, r.compensator);
    rep.typed = compute_design(*rep.typed_in);
    j["typed_compensator"] = typed_compensator_json(*rep.typed_in, *rep.typed);
  }
  if (!r.simulate) return rep;
  if (rep.typed) {
    if (!rep.typed->compensator)
      throw InputError("--simulate: no " + std::string(to_string(*r.compensator)) + " compensator to simulate (" +
                       rep.typed->error + ")");
    throw_failure(*rep.typed);
    j["simulation"] = simulation_json(*rep.typed_in, *rep.typed);
  } else {
    if (!rep.lead.compensator) throw InputError("--simulate: no design to simulate (" + lr.limits.reason + ")");
    j["simulation"] = simulation_json(rep.lead_in, rep.lead);
  }
  return rep;
}

}  // namespace gmslab::control
