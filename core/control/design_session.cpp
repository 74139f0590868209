#include "core/control/design_session.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/friction/param_specs.hpp"

namespace gmslab::control {

const char* to_string(CompensatorType t) {
  switch (t) {
    case CompensatorType::Lead: return "lead";
    case CompensatorType::Lag: return "lag";
    case CompensatorType::LeadLag: return "lead_lag";
    case CompensatorType::PI: return "pi";
    case CompensatorType::PID: return "pid";
  }
  return "?";
}

std::optional<CompensatorType> compensator_type_from_string(const std::string& s) {
  for (CompensatorType t : {CompensatorType::Lead, CompensatorType::Lag, CompensatorType::LeadLag,
                            CompensatorType::PI, CompensatorType::PID})
    if (s == to_string(t)) return t;
  return std::nullopt;
}

std::optional<GainPoint> gain_on_damping_ray(const TransferFunction& g, const DominantRoot& d) {
  check_root(d);
  const cplx dir = d.s() / d.wn;  // unit vector at angle pi - beta
  // arg(-G(s)) is 0 on the locus; it crosses 0 continuously there (and jumps by 2 pi elsewhere).
  auto phase = [&](double r) { return std::arg(-g(r * dir)); };
  const int n = 600;
  const double l0 = std::log(1e-3 * d.wn), l1 = std::log(1e3 * d.wn);
  std::optional<GainPoint> best;
  double prev_r = std::exp(l0), prev = phase(prev_r);
  for (int i = 1; i <= n; ++i) {
    const double r = std::exp(l0 + (l1 - l0) * i / n);
    const double cur = phase(r);
    if (std::isfinite(prev) && std::isfinite(cur) && (prev > 0.0) != (cur > 0.0) &&
        std::abs(prev) < 0.5 * std::numbers::pi && std::abs(cur) < 0.5 * std::numbers::pi) {
      double lo = prev_r, hi = r, flo = prev;
      for (int k = 0; k < 80; ++k) {
        const double mid = std::sqrt(lo * hi);
        const double fm = phase(mid);
        if ((fm > 0.0) == (flo > 0.0)) lo = mid, flo = fm;
        else hi = mid;
      }
      const double rr = std::sqrt(lo * hi);
      const GainPoint gp{rr * dir, 1.0 / std::abs(g(rr * dir))};
      if (!best || std::abs(std::log(rr / d.wn)) < std::abs(std::log(std::abs(best->s) / d.wn))) best = gp;
    }
    prev_r = r, prev = cur;
  }
  return best;
}

std::optional<std::pair<std::string, LeadDesign>> chosen_lead(const LeadReport& r) {
  if (r.design) return std::pair{std::string("requested"), *r.design};
  if (const Relocation* rel = best_relocation(r)) return std::pair{"relocated:" + rel->path, rel->design};
  if (!r.K_des && r.usable_design) return std::pair{std::string("usable_maximum"), *r.usable_design};
  return std::nullopt;
}

namespace {
// The lead of the chosen design (requested, relocated, usable maximum) and its kind.
std::optional<std::pair<LeadCompensator, std::string>> lead_choice(const LeadReport& r) {
  const auto c = chosen_lead(r);
  if (!c) return std::nullopt;
  return std::pair{LeadCompensator{c->second.Kc, c->second.z, c->second.p}, c->first};
}

void choose(const DesignInputs& in, DesignOutputs& out) {
  // Lag / PI: the gain point stays the view's focus (and the horizon's) while handles are dragged.
  if (in.type == CompensatorType::Lag || in.type == CompensatorType::PI)
    out.gain_point = gain_on_damping_ray(out.plant.g, in.root);
  if (in.manual) {
    out.compensator = in.manual;
    out.compensator_kind = "manual";
    return;
  }
  const LeadReport& r = *out.report;
  const double K0 = r.type.K0;
  switch (in.type) {
    case CompensatorType::Lead:
      if (auto c = lead_choice(r)) out.compensator = c->first, out.compensator_kind = c->second;
      return;
    case CompensatorType::LeadLag: {
      // The lead reaches K by itself: no lag needed.
      if (r.design && r.within_max_ratio) {
        out.compensator = LeadCompensator{r.design->Kc, r.design->z, r.design->p};
        out.compensator_kind = "lead_lag:requested (the lead alone reaches K)";
        return;
      }
      if (!r.usable_design) throw InputError("lead-lag: no lead with p/z <= max_ratio places s_d");
      const LeadDesign& u = *r.usable_design;
      const LeadCompensator lead{u.Kc, u.z, u.p};
      const double K_lead = u.Kc * u.z / u.p * K0;
      const double target = in.K ? *in.K : in.lag_factor * K_lead;
      const LeadLagDesign ll = design_lead_lag(out.plant.g, lead, in.root, target, in.lag_zero_fraction);
      out.lead_lag = ll;
      LeadCompensator c = lead;
      c.second = Section{ll.zl, ll.pl};
      out.compensator = c;
      out.compensator_kind = "lead_lag:usable_maximum";
      return;
    }
    case CompensatorType::PID: {
      auto l = lead_choice(r);
      if (!l) return;
      LeadCompensator c = l->first;
      const Relocation* rel = l->second.rfind("relocated:", 0) == 0 ? best_relocation(r) : nullptr;
      const DominantRoot root = rel ? rel->root : in.root;  // the integral zero sits under the lead's s_d
      c.second = Section{0.1 * std::abs(root.s().real()), 0.0};
      out.compensator = c;
      out.compensator_kind = "pid:" + l->second;
      return;
    }
    case CompensatorType::Lag:
    case CompensatorType::PI: {
      const auto& gp = out.gain_point;
      if (!gp)
        throw InputError("lag / PI: the plant's own locus does not cross the zeta = " + std::to_string(in.root.zeta).substr(0, 5) +
                         " line, so no gain alone gives that damping (use a lead or lead-lag)");
      const double zl = 0.1 * std::abs(gp->s.real());
      if (in.type == CompensatorType::PI) {
        out.compensator = LeadCompensator{gp->k, zl, 0.0};
        out.compensator_kind = "pi";
        return;
      }
      const double K_gain = gp->k * K0;
      double factor = in.K ? *in.K / K_gain : in.lag_factor;
      if (!(factor > 1.0)) factor = 1.0;  // the gain alone reaches K: a unity "lag"
      out.compensator = LeadCompensator{gp->k, zl, zl / factor};
      out.compensator_kind = "lag";
      return;
    }
  }
}
}  // namespace

LagCost lag_cost(const PlantType& type, const LeadCompensator& c, const std::vector<cplx>& poles) {
  const Section lag = c.section(c.sections() - 1);
  if (!(c.Kc > 0.0) || !(lag.p >= 0.0) || !(lag.z > lag.p))
    throw InputError("lag: need Kc > 0 and z > p >= 0 rad/s (a lag or a PI)");
  LagCost r;
  r.factor = lag.p > 0.0 ? lag.z / lag.p : std::numeric_limits<double>::infinity();
  r.K_gain_only = c.Kc * type.K0;
  if (c.second) r.K_gain_only *= c.p > 0.0 ? c.z / c.p : 1.0;
  r.K = r.K_gain_only * r.factor;
  double best = std::numeric_limits<double>::infinity();
  for (const cplx& s : poles)
    if (std::isfinite(s.real()) && std::abs(s + lag.z) < best) best = std::abs(s + lag.z), r.slow_pole = s;
  r.time_constant = 1.0 / std::abs(r.slow_pole.real());
  return r;
}

TransferFunction LeadLagDesign::tf() const {
  return {Poly({lead.Kc * lead.z, lead.Kc}) * Poly({zl, 1.0}), Poly({lead.p, 1.0}) * Poly({pl, 1.0})};
}

LeadLagDesign design_lead_lag(const TransferFunction& g, const LeadCompensator& lead, const DominantRoot& root,
                              double K_target, double zero_fraction) {
  const PlantType type = plant_type(g);
  if (!(lead.Kc > 0.0) || !(lead.z > 0.0) || !(lead.p > 0.0) || !(type.K0 > 0.0))
    throw InputError("lead-lag: need a lead with Kc > 0, z > 0, p > 0 rad/s and a plant with K0 > 0");
  LeadLagDesign d;
  d.lead = lead;
  d.K_lead = lead.Kc * lead.z / lead.p * type.K0;
  if (!(K_target > d.K_lead) || !std::isfinite(K_target))
    throw InputError("lead-lag: the target error constant " + specs::num(K_target) +
                     " must exceed the lead's own " + specs::num(d.K_lead) +
                     " (else no lag is needed)");
  if (!(zero_fraction > 0.0 && zero_fraction <= 1.0))
    throw InputError("lead-lag: the lag zero fraction of |Re s_d| must be in (0, 1]");
  const cplx sd = root.s();
  d.zl = zero_fraction * std::abs(sd.real());
  d.pl = d.zl * d.K_lead / K_target;
  d.K = d.K_lead * d.zl / d.pl;
  d.lag_angle_deg = std::arg((sd + d.zl) / (sd + d.pl)) * 180.0 / std::numbers::pi;
  const TransferFunction c = d.tf();
  d.closed_loop_poles = (c.den * g.den + c.num * g.num).roots();
  double best_d = std::numeric_limits<double>::infinity(), best_s = best_d;
  for (const cplx& s : d.closed_loop_poles) {
    if (std::abs(s - sd) < best_d) best_d = std::abs(s - sd), d.dominant = s;
    if (std::abs(s + d.zl) < best_s) best_s = std::abs(s + d.zl), d.slow_pole = s;
  }
  d.time_constant = 1.0 / std::abs(d.slow_pole.real());
  return d;
}

const LoopRun& DesignOutputs::plain() const {
  static const LoopRun none;
  for (const LoopRun& r : loops)
    if (r.compensation == Compensation::None) return r;
  return none;
}

const LoopRun& DesignOutputs::compensated() const {
  static const LoopRun none;
  for (const LoopRun& r : loops)
    if (r.compensation != Compensation::None) return r;
  return none;
}

void throw_failure(const DesignOutputs& out) {
  if (out.failure_kind) throw_error(*out.failure_kind, out.failure);
}

namespace {
void record_failure(DesignOutputs& out, const std::string& stage, const Error& e) {
  out.error += (out.error.empty() ? "" : "\n") + stage + ": " + e.what();
  out.error_kind = e.kind();
  if (!out.failure_kind) out.failure = e.what(), out.failure_kind = e.kind();
}

// The plant G(s), its source and label.
void plant_stage(const DesignInputs& in, DesignOutputs& out) {
  const Assembly* assembly = in.assembly ? &in.assembly->plant : nullptr;
  const DesignPlant dp = design_plant(in.plant, in.regime, in.velocity, &in.scenario, assembly);
  out.plant = dp.linear;
  out.source = dp.source;
  out.plant_label = dp.label;
  out.port = dp.port;
  if (out.source == PlantSource::Typed)
    out.loop_note = "typed plant: no friction and no scenario to simulate, so no loop with friction and no "
                    "describing function; the linear closed-loop step is the typed plant's with the compensator";
}

// The lead report and the compensator of the chosen type; with lag_K, the lag after the chosen lead.
void design_stage(const DesignInputs& in, DesignOutputs& out) {
  out.report = lead_design(out.plant.g, in.root, in.K, in.options);
  choose(in, out);
  if (!in.lag_K) return;
  const auto lead = chosen_lead(*out.report);
  if (!lead) return;  // nothing to add a lag to: the report says why
  const LeadDesign& ld = lead->second;
  out.lead_lag = design_lead_lag(out.plant.g, {ld.Kc, ld.z, ld.p}, in.root, *in.lag_K, in.lag_zero_fraction);
}

// The closed-loop poles, dominance and lag cost of the compensator, and the points the locus view
// must show.
std::vector<cplx> closed_loop_stage(const DesignInputs& in, DesignOutputs& out, LocusOptions& lo) {
  const cplx focus = out.gain_point ? out.gain_point->s : in.root.s();  // lag / PI: where Kc alone puts the pole
  std::vector<cplx> pts = {focus, 2.0 * focus.real()};
  auto near = [&](cplx s) { return std::abs(s) <= 4.0 * std::abs(focus); };
  double reach = std::abs(focus);
  for (const cplx& s : out.plant.g.poles()) pts.push_back(s), reach = std::max(reach, std::abs(s));
  // A plant zero far beyond s_d and every pole (an assembled train's damper zero -k/c) would
  // shrink the region where the locus bends to a dot: left to the user's zoom.
  for (const cplx& s : out.plant.g.zeros())
    if (std::abs(s) <= 4.0 * reach) pts.push_back(s);
  out.loop = out.plant.g;
  if (!out.compensator) return pts;
  const LeadCompensator& c = *out.compensator;
  out.loop = {out.plant.g.num * c.num_poly(), out.plant.g.den * c.den_poly()};
  lo.extra_gains = {c.Kc};
  out.closed_loop_poles = closed_loop_poles(out.loop, c.Kc);
  const Relocation* rel = out.report ? best_relocation(*out.report) : nullptr;
  DominantRoot target = out.compensator_kind.find("relocated:") != std::string::npos && rel ? rel->root : in.root;
  if (out.gain_point) target.wn = std::abs(out.gain_point->s);
  if (out.report) out.dominance = check_dominance(out.plant.g, target, c, out.closed_loop_poles);
  if (out.gain_point) {  // a lag zero sits near the origin on purpose: its cost is out.lag's slow pole
    auto& n = out.dominance.notes;
    n.erase(std::remove_if(n.begin(), n.end(),
                           [](const std::string& t) { return t.rfind("the compensator zero", 0) == 0; }),
            n.end());
  }
  if (out.gain_point && !in.manual) {
    const double w = std::abs(out.gain_point->s);
    if (w < 0.5 * in.root.wn || w > 2.0 * in.root.wn)
      out.dominance.notes.insert(out.dominance.notes.begin(),
                                 "the gain alone reaches zeta = " + std::to_string(in.root.zeta).substr(0, 4) +
                                     " only at wn = " + std::to_string(w).substr(0, 7) + " rad/s (desired " +
                                     std::to_string(in.root.wn).substr(0, 7) +
                                     "): a lag or PI cannot move the poles there; a lead or lead-lag can");
  }
  for (double z : c.zeros()) pts.emplace_back(-z, 0.0);
  for (double p : c.poles())
    if (near(-p)) pts.emplace_back(-p, 0.0);
  for (const cplx& p : out.closed_loop_poles)
    if (near(p)) pts.push_back(p);
  const Section last = c.section(c.sections() - 1);
  if (last.z > last.p && out.report) out.lag = lag_cost(out.report->type, c, out.closed_loop_poles);
  return pts;
}

// The drawn loci: the loop's, the 0-degree one, the other regime's.
void locus_stage(const DesignInputs& in, DesignOutputs& out, LocusOptions lo, const std::vector<cplx>& pts) {
  // Refine over a box 2.5x the shown one (the canvas widens it to its aspect), 0.5 % steps.
  const ViewBox shown = in.locus_view ? *in.locus_view : view_around(pts);
  const double cx = 0.5 * (shown.re_min + shown.re_max), hw = 1.25 * shown.width();
  const double cy = 0.5 * (shown.im_min + shown.im_max), hh = 1.25 * shown.height();
  lo.view = ViewBox{cx - hw, cx + hw, cy - hh, cy + hh};
  lo.max_jump = 0.005;
  out.locus = root_locus(out.loop, lo);
  out.locus.view = shown;
  if (in.zero_degree) {
    LocusOptions neg = lo;
    neg.negative = true;
    neg.extra_gains.clear();
    out.zero_degree_locus = root_locus(out.loop, neg);
  }
  if (in.other_regime && out.source != PlantSource::Typed) {  // a typed plant has no regimes
    const Regime other = in.regime == Regime::Presliding ? Regime::Sliding : Regime::Presliding;
    const Assembly* assembly = in.assembly ? &in.assembly->plant : nullptr;
    const TransferFunction g2 = design_plant(in.plant, other, in.velocity, &in.scenario, assembly).linear.g;
    TransferFunction L2 = g2;
    if (out.compensator) L2 = {g2.num * out.compensator->num_poly(), g2.den * out.compensator->den_poly()};
    out.other_locus = root_locus(L2, lo);
  }
}

std::vector<Compensation> loop_compensations(const DesignInputs& in) {
  if (!in.loop_compensations.empty()) return in.loop_compensations;
  return {Compensation::None, in.compensation};
}

// The describing-function predictions of a one-body scenario's loops: without compensation, for
// each loop, and the stick-slip hunting.
void describing_function_stage(const DesignInputs& in, DesignOutputs& out) {
  const bool view = in.accuracy == Accuracy::View;
  const DfOptions df = view ? DfOptions{400, 2} : DfOptions{};
  const LeadCompensator& C = *out.compensator;
  const auto fm = build_model(in.scenario.friction);
  out.limit_cycles = predict_limit_cycles(stepped(*fm), in.scenario.plant, C, 1e-6, 10.0, df);
  for (LoopRun& run : out.loops)
    run.limit_cycles = run.compensation != Compensation::None && in.feedforward_source == FeedforwardSource::Measured
                           ? predict_limit_cycles(compensated_friction(in.scenario.friction, run.compensation,
                                                                       in.mismatch),
                                                  in.scenario.plant, C, 1e-6, 10.0, df)
                           : out.limit_cycles;
  if (!view)
    out.hunting = predict_hunting(in.scenario.plant, in.scenario.friction, C);
  else if (integral_split(C))
    out.hunting = predict_hunting(in.scenario.plant, in.scenario.friction, C, view_rate_hunting_options());
}

// The loop's configuration but for its compensation: the given timing, or a view-rate step of 20000
// steps over the run, never coarser than 5 % of the stability limit of the stiffest mode (stuck
// elements + springs + Kc), never finer than the plant's dt.
LoopConfig loop_config(const DesignInputs& in, const DesignOutputs& out) {
  LoopConfig cfg;
  cfg.reference = in.reference;
  cfg.C = *out.compensator;
  cfg.sample_time = in.sample_time;
  cfg.mismatch = in.mismatch;
  cfg.feedforward_source = in.feedforward_source;
  const bool assembled = out.source == PlantSource::Assembly;
  const double dt0 = assembled ? in.assembly->run.dt : in.scenario.run.dt;
  if (in.loop_timing) {
    cfg.duration = in.loop_timing->duration;
    cfg.dt = in.loop_timing->dt > 0.0 ? in.loop_timing->dt : dt0;
    cfg.record_every = in.loop_timing->record_every;
    return cfg;
  }
  double limit = 0.0;
  if (assembled) {
    limit = assembly_loop_dt_limit(in.assembly->plant, out.port.drive, cfg.C.Kc);
  } else {
    const double k_eq = linear_plant(in.scenario, Regime::Presliding).stiffness + cfg.C.Kc;
    limit = 2.0 / std::sqrt(k_eq / in.scenario.plant.mass);
  }
  cfg.duration = out.horizon;
  if (in.reference.kind == Signal::Kind::Sine && in.reference.frequency > 0.0)
    cfg.duration = std::max(cfg.duration, 2.0 / in.reference.frequency);
  // A predicted hunting cycle is slower than the dominant roots: a constant reference runs long
  // enough to show it (20 predicted periods, at most 30 s: the metrics tail holds 4), so the table
  // compares like with like.
  if (in.reference.kind == Signal::Kind::Constant && out.hunting && out.hunting->hunting() && in.horizon == 0.0)
    cfg.duration = std::max(cfg.duration, std::min(30.0, 20.0 * out.hunting->hunting()->period));
  // Periodic orbits around a set point: hunting is slower than the dominant roots; 30 s at least,
  // so that the step is the stability limit's (the orbits and the simulation take the same step).
  if (in.periodic_orbits && in.reference.kind == Signal::Kind::Constant && in.horizon == 0.0)
    cfg.duration = std::max(cfg.duration, 30.0);
  cfg.dt = std::clamp(cfg.duration / 20000.0, dt0, std::max(dt0, 0.05 * limit));
  cfg.record_every = std::max(1, static_cast<int>(cfg.duration / cfg.dt / 1000));
  return cfg;
}

// The closed loop of a design (its plant, the compensator, the loop's step) for the orbit solver.
ClosedLoop closed_loop_of(const DesignInputs& in, const DesignOutputs& out, const LoopConfig& cfg) {
  ClosedLoop L;
  L.scenario = in.scenario;
  if (out.source == PlantSource::Assembly) L.assembly = *in.assembly, L.port = out.port;
  L.config = cfg;
  L.config.comp = Compensation::None;
  return L;
}

// Periodic orbits of the loop without compensation (seeded by its hunting prediction when there is
// one), and the hunting map from the stable orbit.
void orbit_stage(const DesignInputs& in, DesignOutputs& out, const LoopConfig& cfg) {
  OrbitReport& rep = out.orbits.emplace();
  if (in.reference.kind != Signal::Kind::Constant) {
    rep.method = "none";
    rep.not_found = "periodic orbits: not computed for a " +
                    std::string(to_string(in.reference.kind)) +
                    " reference (the orbits are the loop's around a constant set point)";
    return;
  }
  const ClosedLoop L = closed_loop_of(in, out, cfg);
  rep = find_orbits(L, OrbitOptions{}, out.hunting ? &*out.hunting : nullptr);
  if (!in.hunting_map) return;
  const auto& grid = *in.hunting_map;
  std::optional<PeriodicOrbit> start;
  if (rep.stable()) start = *rep.stable();
  // No cycle at the design's gain: the same search at the ends of the map's range (a cycle that
  // exists only below or above a threshold gain), the map continued from the first found.
  std::string searched = "at gain scale 1";
  for (double g : {grid.lo, grid.hi}) {
    if (start) break;
    ClosedLoop Lg = L;
    Lg.config.C.Kc *= g;
    std::ostringstream label;
    label << g;
    searched += ", " + label.str();
    try {
      const OrbitReport rg = find_orbits(Lg);
      if (rg.stable()) start = *rg.stable(), start->gain_scale = g;
    } catch (const Error&) {  // a diverging loop or a step too coarse for that gain: none there
    }
  }
  if (!start) {
    HuntingMap& m = out.hunting_map.emplace();
    m.note = "hunting map: no stable orbit found " + searched + " to continue from (" +
             rep.not_found + ")";
    return;
  }
  out.hunting_map = hunting_map(L, *start, grid.lo, grid.hi, grid.n);
}

// Each loop with friction, on the scenario's one body or the assembled plant.
void simulation_stage(const DesignInputs& in, DesignOutputs& out, LoopConfig cfg) {
  // A stable orbit slower than the run: long enough for 20 of its periods (at most 60 s; the same
  // step, so the simulation and the orbit see the same loop).
  const PeriodicOrbit* orbit = out.orbits ? out.orbits->stable() : nullptr;
  if (orbit && out.orbits->dt != cfg.dt) orbit = nullptr;
  if (orbit && !in.loop_timing && in.horizon == 0.0 &&
      in.reference.kind == Signal::Kind::Constant &&
      cfg.duration < std::min(60.0, 20.0 * orbit->period)) {
    cfg.duration = std::min(60.0, 20.0 * orbit->period);
    cfg.record_every = std::max(1, static_cast<int>(cfg.duration / cfg.dt / 1000));
  }
  for (LoopRun& run : out.loops) {
    cfg.comp = run.compensation;
    run.trace = out.source == PlantSource::Assembly ? simulate_loop(*in.assembly, out.port, cfg)
                                                    : simulate_loop(in.scenario, cfg);
    run.metrics = loop_metrics(run.trace);
    run.error = tracking_error(run.trace);
  }
}
}  // namespace

DesignOutputs compute_design(const DesignInputs& in) {
  DesignOutputs out;
  std::string stage = "plant";
  try {
    plant_stage(in, out);
    try {  // a failed design still leaves the plant's own locus to draw
      design_stage(in, out);
    } catch (const Error& e) {  // typed (bad design inputs): reported; anything else is a bug
      record_failure(out, "design", e);
      out.report.reset();
      out.lead_lag.reset();
      if (in.manual) out.compensator = in.manual, out.compensator_kind = "manual";
    }
    // Lag / PI: the loop's speed is the gain point's (Kc alone), not s_d's.
    const double sigma = out.gain_point ? std::abs(out.gain_point->s.real()) : in.root.zeta * in.root.wn;
    out.horizon = in.horizon > 0.0 ? in.horizon : std::clamp(10.0 / sigma, 0.01, 20.0);
    stage = "root locus";
    LocusOptions lo;
    const std::vector<cplx> pts = closed_loop_stage(in, out, lo);
    if (in.view) locus_stage(in, out, lo, pts);
    stage = "frequency response";
    {
      const double k = out.compensator ? out.compensator->Kc : 1.0;
      out.frequency = frequency_response({out.loop.num * k, out.loop.den});
    }
    if (in.sample_time > 0.0 && out.compensator) {
      stage = "discrete frequency response";
      const LeadCompensator& c = *out.compensator;
      const TransferFunction Lz = sampled_loop(out.plant.g, c, in.sample_time);
      out.discrete = discrete_frequency_response({Lz.num * c.Kc, Lz.den}, in.sample_time);
      stage = "z-plane root locus";
      LocusOptions zo;
      zo.extra_gains = {c.Kc};
      zo.view = in.z_locus_view;
      out.z_locus = z_root_locus(Lz, in.sample_time, zo);
    }
    if (!out.compensator) return out;
    if (in.view) {
      stage = "step response";
      out.step = step_response(closed_loop(out.plant.g, *out.compensator), out.horizon, 400);
    }
    if (out.source == PlantSource::Typed) return out;
    for (Compensation c : loop_compensations(in)) out.loops.push_back(LoopRun{c, {}, {}, {}, {}});
    stage = "describing function";
    if (out.source == PlantSource::Assembly)
      out.loop_note = "DF: not predicted for an assembled plant (the describing function here is for one "
                      "body and one contact); the loops run on the assembled nonlinear plant";
    else
      describing_function_stage(in, out);
    if (!in.simulate && !in.periodic_orbits) return out;
    const LoopConfig cfg = loop_config(in, out);
    if (in.periodic_orbits) {
      stage = "periodic orbits";
      // A given timing without its own step (the plant's run.dt, often far finer than the loop
      // needs): the orbits at the automatic step; with a given step, at that one.
      if (in.loop_timing && in.loop_timing->dt == 0.0) {
        DesignInputs automatic = in;
        automatic.loop_timing.reset();
        orbit_stage(in, out, loop_config(automatic, out));
      } else {
        orbit_stage(in, out, cfg);
      }
    }
    if (!in.simulate) return out;
    stage = "nonlinear simulation";
    simulation_stage(in, out, cfg);
  } catch (const Error& e) {  // typed: bad input, a diverging loop
    record_failure(out, stage, e);
  }
  return out;
}

}  // namespace gmslab::control
