#include "core/control/design_session.hpp"

#include <algorithm>
#include <exception>

namespace gmslab::control {

namespace {
void choose(const DesignInputs& in, DesignOutputs& out) {
  if (in.manual) {
    out.compensator = in.manual;
    out.compensator_kind = "manual";
    return;
  }
  const LeadReport& r = *out.report;
  auto use = [&](const LeadDesign& d, std::string kind) {
    out.compensator = LeadCompensator{d.Kc, d.z, d.p};
    out.compensator_kind = std::move(kind);
  };
  if (r.design) return use(*r.design, "requested");
  for (const auto& rel : r.relocations)
    if (rel.found) return use(rel.design, "relocated:" + rel.path);
  if (!r.K_des && r.usable_design) use(*r.usable_design, "usable_maximum");
}
}  // namespace

DesignOutputs compute_design(const DesignInputs& in) {
  DesignOutputs out;
  std::string stage = "plant";
  try {
    out.plant = linear_plant(in.scenario, in.regime, in.velocity);
    stage = "design";
    out.report = lead_design(out.plant.g, in.root, in.K, in.options);
    choose(in, out);
    out.horizon = in.horizon > 0.0 ? in.horizon
                                   : std::clamp(10.0 / (in.root.zeta * in.root.wn), 0.01, 20.0);
    stage = "root locus";
    LocusOptions lo;
    TransferFunction L = out.plant.g;
    std::vector<cplx> extra = {in.root.s()};
    if (out.compensator) {
      const LeadCompensator& c = *out.compensator;
      L = {out.plant.g.num * Poly({c.z, 1.0}), out.plant.g.den * Poly({c.p, 1.0})};
      lo.extra_gains = {c.Kc};
      out.closed_loop_poles = closed_loop_poles(L, c.Kc);
      extra.emplace_back(-c.z, 0.0);
      for (const cplx& p : out.closed_loop_poles) extra.push_back(p);
    }
    lo.view = auto_view(L, extra);
    out.locus = root_locus(L, lo);
    if (!out.compensator) return out;
    stage = "step response";
    out.step = step_response(closed_loop(out.plant.g, *out.compensator), out.horizon, 400);
    if (!in.simulate) return out;
    stage = "nonlinear simulation";
    LoopConfig cfg;
    cfg.reference = in.reference;
    cfg.C = *out.compensator;
    cfg.sample_time = in.sample_time;
    cfg.mismatch = in.mismatch;
    cfg.dt = in.scenario.run.dt;
    cfg.duration = out.horizon;
    cfg.record_every = std::max(1, static_cast<int>(out.horizon / cfg.dt / 1000));
    cfg.comp = Compensation::None;
    out.loop_plain = simulate_loop(in.scenario, cfg);
    out.metrics_plain = loop_metrics(out.loop_plain);
    cfg.comp = in.compensation;
    out.loop_compensated = simulate_loop(in.scenario, cfg);
    out.metrics_compensated = loop_metrics(out.loop_compensated);
  } catch (const std::exception& e) {
    out.error = stage + ": " + e.what();
  }
  return out;
}

}  // namespace gmslab::control
