// gmslab core/control: the design job - everything the root-locus design view shows and everything
// `gmslab design` and gmslab.design report, computed from its inputs in one call (the view calls it
// on every drag; the benchmark times it; core/control/design_report.hpp writes its JSON).
//
// plant  = design_plant(choice, regime, v0, scenario, assembly)  G(s): the scenario's one body
//          [m/N], an assembled plant's drive -> output, or typed num/den (design_plant.hpp)
// design = the lead of lead_design() for (zeta, wn, K), or the relocated / usable one, or the
//          compensator the user dragged (manual)
// lead_lag = with `lag_K`: a lag after the chosen lead reaching that error constant
//          (design_lead_lag); the lead-lag type keeps its own lead-lag here too
// locus  = root locus of the compensated loop in its gain: L(s) = (s + z) G(s) / (s + p), k = Kc
//          (the plant's own locus when there is no compensator); with `view` only
// step   = linear closed-loop unit-step response, t in [0, horizon]; with `view` only
// loops  = the same loop with the scenario's friction, one per entry of `loop_compensations`
//          (default: without compensation and with `compensation`); for an assembled plant, on the
//          assembled nonlinear plant (the controller's force through the chosen drive, measuring the
//          chosen output); none for a typed plant (no friction to simulate: `loop_note` says so)
// horizon = clamp(10 / (zeta wn), 0.01 s, 20 s) unless given. Unless `loop_timing` is given, the
// friction loops run over the horizon, or two periods of a sine reference when that is longer (with a
// constant reference and a predicted hunting cycle: 20 of its periods, at most 30 s), at a view-rate
// step dt = clamp(duration / 20000, scenario dt, 0.05 x the stability limit 2 / sqrt((k_presliding +
// Kc) / m)).
// locus view (unless given): the region around s_d, the plant's poles, its zeros within 4x the
// farthest of s_d and the poles, the compensator zero, and the compensator pole and closed-loop
// poles when they lie within 4 |s_d| (a far lead pole would otherwise shrink the interesting region
// to a dot).
// A typed failure of any stage (InputError, SimulationError: core/error.hpp) is reported in
// `error` with its kind (the first one also as raised, in `failure`) and later stages are skipped;
// a failed design (e.g. K0 <= 0) still gets the plant's locus (or the manual compensator's loop).
// Any other exception is a bug and propagates (nothing is swallowed).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/control/describing_function.hpp"
#include "core/control/design_plant.hpp"
#include "core/control/discrete.hpp"
#include "core/control/frequency.hpp"
#include "core/control/hunting.hpp"
#include "core/control/lead_design.hpp"
#include "core/control/limit_cycles.hpp"
#include "core/control/linear_response.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/control/root_locus.hpp"
#include "core/control/scenario_plant.hpp"
#include "core/error.hpp"

namespace gmslab::control {

// Which compensator the design view builds (from the design; a drag then makes it manual):
//   lead      Kc (s + z)/(s + p): lead_design() (requested K, relocation or the usable maximum)
//   lag       Kc (s + zl)/(s + pl): Kc puts a closed-loop pole where the plant's own locus crosses
//             the zeta line (gain_point); the lag zero at 0.1 |Re| of that point, pl buys K (or
//             lag_factor x Kc's own constant without a K)
//   lead_lag  the lead of the usable maximum (or the requested one when it reaches K: no lag), then
//             design_lead_lag() for K (or lag_factor x the lead's constant)
//   pi        Kc (s + zi)/s: the lag's gain point, zi = 0.1 |Re| of it
//   pid       Kc (s + z)(s + zi)/((s + p) s): the lead (its pole p is the derivative filter), then
//             an integral section with zi = 0.1 |Re s_d| (of the relocated s_d for a relocated lead)
enum class CompensatorType { Lead, Lag, LeadLag, PI, PID };
const char* to_string(CompensatorType t);  // "lead" | "lag" | "lead_lag" | "pi" | "pid"
std::optional<CompensatorType> compensator_type_from_string(const std::string& s);

// The point of G's own locus (k > 0) on the ray of damping zeta nearest |s| = wn (bisection of
// arg(-G) on a log grid of |s| in [1e-3, 1e3] wn), and the gain k = 1/|G| that puts a closed-loop
// pole there. nullopt when the locus does not cross the ray.
struct GainPoint {
  cplx s;
  double k = 0.0;
};
std::optional<GainPoint> gain_on_damping_ray(const TransferFunction& g, const DominantRoot& d);

// A lag (z > p > 0) or PI (p = 0): what it buys and what it costs. The error constant is Kc (z/p) K0
// against Kc K0 for the gain Kc alone (factor z/p; infinite for the PI: the type rises by one); the
// cost is the slow closed-loop pole the lag zero leaves behind: the closed-loop pole nearest -z
// (its time constant 1/|Re| stretches the settling tail).
struct LagCost {
  double factor = 0.0;       // z / p [-] (inf for p = 0)
  double K = 0.0;            // error constant with the lag (Kc z/p K0; inf for p = 0)
  double K_gain_only = 0.0;  // Kc K0
  cplx slow_pole;            // [rad/s]
  double time_constant = 0.0;  // 1 / |Re slow_pole| [s]
};

// Lead-lag: a lead (designed for s_d, error constant K_lead = Kc (z/p) K0) followed by a unity-DC
// lag (s + z_l)/(s + p_l) that buys the factor z_l/p_l = K_target/K_lead. The lag zero sits at
// z_l = zero_fraction x |Re s_d| (default 0.1: close to the origin against s_d, so it bends the
// locus at s_d by only its small angle arg((s_d + z_l)/(s_d + p_l))). The cost: the slow closed-loop
// pole it leaves on the real axis next to the lag zero -z_l (its branch ends there), with its time
// constant (the error's slow tail, about 1/z_l), and the shift of the dominant pair off s_d.
struct LeadLagDesign {
  LeadCompensator lead;
  double zl = 0.0, pl = 0.0;            // lag zero / pole at -zl, -pl [rad/s]
  double K_lead = 0.0, K = 0.0;         // error constants, lead alone / lead-lag (1/s^n)
  double lag_angle_deg = 0.0;           // arg((s_d + zl)/(s_d + pl)) [deg] (< 0)
  std::vector<cplx> closed_loop_poles;  // of 1 + Gc G with the lead-lag
  cplx dominant;                        // the closed-loop pole nearest s_d [rad/s]
  cplx slow_pole;                       // the closed-loop pole nearest -zl [rad/s]
  double time_constant = 0.0;           // 1/|Re slow_pole| [s]
  // Kc (s + z)(s + zl) / ((s + p)(s + pl))
  TransferFunction tf() const;
};

// How finely the describing-function predictions are computed: at the view's rate (DfOptions{400, 2},
// view_rate_hunting_options(); the hunting only for a compensator with an integrator), or as the
// reports give them (the options' defaults; the hunting always, its note saying why there is none).
enum class Accuracy { View, Report };

// The friction loops' timing when not the view's automatic one: duration [s], integration step [s]
// (0: the plant's run.dt), every record_every-th step kept.
struct LoopTiming {
  double duration = 2.0;
  double dt = 0.0;
  int record_every = 10;
};

struct DesignInputs {
  CompensatorType type = CompensatorType::Lead;
  double lag_factor = 10.0;  // lag / lead-lag without K: error constant bought [-], > 1
  Scenario scenario;
  PlantChoice plant;                        // where G(s) comes from
  std::optional<AssemblyScenario> assembly;  // the assembled plant (plant source "assembly")
  Regime regime = Regime::Sliding;
  double velocity = 0.0;            // sliding operating velocity v0 [m/s] (0: default)
  DominantRoot root{0.7, 60.0};     // desired dominant roots
  std::optional<double> K;          // desired error constant (none: the usable maximum)
  LeadOptions options;
  std::optional<LeadCompensator> manual;  // dragged compensator overrides the design
  Signal reference = Signal::constant(0.01);  // nonlinear loop reference [m]
  Compensation compensation = Compensation::Gms;  // for the "with compensation" run
  // What drives the compensated runs' feedforward: the reference velocity (default) or the measured
  // one (then each compensated loop's limit cycles are predicted with the compensated nonlinearity
  // F - F_hat).
  FeedforwardSource feedforward_source = FeedforwardSource::Reference;
  Mismatch mismatch;
  double sample_time = 0.0;  // controller sample time [s] (0: continuous)
  double horizon = 0.0;      // [s]; 0: automatic
  bool simulate = true;      // run the nonlinear loops
  // The loops with friction, in this order (empty: without compensation, then with `compensation`).
  std::vector<Compensation> loop_compensations;
  std::optional<LoopTiming> loop_timing;  // none: the view's automatic duration and step
  Accuracy accuracy = Accuracy::View;
  bool view = true;  // the drawings: root loci and the linear step (off for the JSON reports)
  // A lag after the chosen lead reaching this error constant (the report's "lead_lag"); the lag zero
  // at lag_zero_fraction x |Re s_d|, in (0, 1] (also the lead-lag type's).
  std::optional<double> lag_K;
  double lag_zero_fraction = 0.1;
  std::optional<ViewBox> locus_view;  // region the locus must resolve (auto if absent)
  std::optional<ViewBox> z_locus_view;  // same for the z-plane locus (sample time > 0)
  bool other_regime = false;  // also compute the locus of the other regime's plant (same Gc)
  bool zero_degree = false;   // also compute the 0-degree locus (k < 0) of the drawn loop
  // Periodic orbits of the loop without compensation (core/control/limit_cycles.hpp), on the same
  // loop (step, plant, controller) as its simulation; the view computes them in the background.
  bool periodic_orbits = false;
  // With periodic_orbits: the hunting map over the gain scales of this grid.
  struct GainGrid {
    double lo = 0.2, hi = 5.0;
    int n = 13;
  };
  std::optional<GainGrid> hunting_map;
};

// One loop with friction: its compensation, the describing-function prediction of its limit cycles
// (a one-body scenario: with the measured-velocity feedforward, predicted on
// compensated_friction(friction, compensation, mismatch) = F - F_hat; with the reference-velocity one
// the feedforward is 0 around a constant set point, so the loop's nonlinearity is the friction and
// this is limit_cycles again; without compensation, limit_cycles), and when simulated its trace,
// tracking_error() [m] and metrics.
struct LoopRun {
  Compensation compensation = Compensation::None;
  std::optional<LimitCycleReport> limit_cycles;
  LoopTrace trace;
  std::vector<double> error;
  LoopMetrics metrics;
};

struct DesignOutputs {
  std::string error;  // empty when every stage ran
  std::optional<ErrorKind> error_kind;  // the kind of the (last) failure, if any
  std::string failure;  // the first failure's message as raised (without its stage)
  std::optional<ErrorKind> failure_kind;
  LinearPlant plant;
  PlantSource source = PlantSource::Scenario;  // of `plant`
  std::string plant_label;                     // what G(s) is (DesignPlant::label)
  AssemblyPort port;                           // assembly: the drive and output designed for
  // Why the loops with friction (or the describing function, or the other regime's locus) were not
  // computed for this plant source; empty when they were.
  std::string loop_note;
  std::optional<LeadReport> report;
  std::optional<LeadCompensator> compensator;  // what the loops use
  std::string compensator_kind;  // "requested", "usable_maximum", "relocated:<path>", "manual"; for
                                 // the other types "lag", "pi", "lead_lag:<lead's kind>", "pid:<...>"
  std::optional<GainPoint> gain_point;  // lag / PI: where Kc alone puts the pole (the target root)
  // A lag part (lag or PI alone, or the second section of a lead-lag / PID): what it buys and costs.
  std::optional<LagCost> lag;
  // The lead-lag of the lead-lag type, or the lag after the chosen lead asked for by `lag_K`.
  std::optional<LeadLagDesign> lead_lag;
  std::vector<cplx> closed_loop_poles;  // with the compensator
  Dominance dominance;                  // of those poles, about the desired s_d
  TransferFunction loop;  // L(s) whose locus is drawn (gain Kc when compensated, else 1)
  RootLocus locus;
  std::optional<RootLocus> other_locus;  // the other regime's plant with the same compensator
  std::optional<RootLocus> zero_degree_locus;  // k < 0 branches of the drawn loop
  StepResponse step;
  // Frequency responses of the drawn loop with its gain (Kc L, or the plant alone): Bode, margins,
  // closed-loop bandwidth and peak, Nyquist (core/control/frequency.hpp).
  std::optional<FrequencyReport> frequency;
  // With a sample time T > 0: the sampled loop Kc Tustin(Gc) ZOH(G) up to the Nyquist frequency.
  std::optional<DiscreteFrequencyReport> discrete;
  // With T > 0: the root locus in z of the same sampled loop in Kc, unit circle crossings and
  // stable gain intervals (core/control/discrete.hpp); the design's Kc is sampled exactly.
  std::optional<ZLocus> z_locus;
  // Limit cycles of the loop without compensation predicted by the describing function of the
  // scenario's friction (core/control/describing_function.hpp; view-rate DF: 400 steps per period,
  // 2 periods), with the friction-free plant (m, spring, damper) and the compensator.
  std::optional<LimitCycleReport> limit_cycles;
  // The stick-slip hunting of a compensator with one integrator (PI, PID, ...) predicted by the
  // describing function of the mass with its friction and the controller's fast part
  // (core/control/hunting.hpp; view rate: 200 steps per period, 8 amplitudes, 6 shooting steps,
  // 0.9 x the stability limit, <= 4000 steps per period); none otherwise.
  std::optional<HuntingReport> hunting;
  // Periodic orbits of the loop without compensation (with periodic_orbits; a typed plant has
  // none: loop_note) and the hunting map (with hunting_map, from the stable orbit when there is
  // one).
  std::optional<OrbitReport> orbits;
  std::optional<HuntingMap> hunting_map;
  // The loops with friction in the order of the inputs' loop_compensations (none for a typed plant
  // or without a compensator); with `simulate` off, only their predictions.
  std::vector<LoopRun> loops;
  double horizon = 0.0;  // [s]
  // The view's two loops: the first without compensation, the first with one (an empty run when
  // there is none).
  const LoopRun& plain() const;
  const LoopRun& compensated() const;
};

DesignOutputs compute_design(const DesignInputs& in);

// The first failure of a design job, raised again as an Error of its kind with its message; returns
// when there was none.
void throw_failure(const DesignOutputs& out);

// The lead of a lead report that a design uses: the requested one, else the best relocation, else
// (no K asked for) the usable maximum; with its kind ("requested", "relocated:<path>",
// "usable_maximum"). nullopt when there is none.
std::optional<std::pair<std::string, LeadDesign>> chosen_lead(const LeadReport& r);

// Two sections: the lag is the second one (z2 > p2 >= 0), "gain only" is Kc and the first section
// (Kc (z1/p1) K0; Kc K0 when p1 = 0), the slow pole the one nearest -z2.
// Throws InputError unless z > p >= 0 and Kc > 0; `poles` are the loop's closed-loop poles.
LagCost lag_cost(const PlantType& type, const LeadCompensator& c, const std::vector<cplx>& poles);

// Throws InputError unless K_target > K_lead > 0, 0 < zero_fraction <= 1, the lead has z > 0,
// p > 0, Kc > 0, and the plant's K0 > 0.
LeadLagDesign design_lead_lag(const TransferFunction& g, const LeadCompensator& lead, const DominantRoot& root,
                              double K_target, double zero_fraction = 0.1);

}  // namespace gmslab::control
