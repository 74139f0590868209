// gmslab core/control: the designed position loop simulated with friction.
//
//   e = x_ref - x;  u = Gc(s) e  (continuous, or Tustin-discretised at T with zero-order hold)
//   m x'' = u + u_ff - k x - c v - F_f        (F_f from ANY registry model, scenario's plant)
// Integrator: the assembled plant's (core/sim/assembly.hpp: friction step with v frozen over h,
// then v += (f_other - F_f) h / m, x += h v); a scenario runs as its one-body assembly. The
// continuous lead state w' = -p w + e is advanced exactly over each step (e held),
// u = Kc e + Kc (z - p) w; a second section in series: the two-state cascade advanced by its exact
// zero-order-hold discretisation (matrix exponential).
// Tustin at T: u[j] = a u[j-1] + b0 e[j] + b1 e[j-1], s = (2/T)(q - 1)/(q + 1), per section in series.
// Friction compensation (feedforward u_ff [N]), driven by the velocity of `feedforward_source`:
//   reference (default) v_ref = (x_ref(t+h) - x_ref(t))/h (it cannot chatter; it does nothing
//            at standstill, so around a constant set point the loop sees the friction alone)
//   measured the plant's velocity v at the start of the step (the one the friction is stepped
//            with): the loop then sees F(v) - F_hat(v), the describing function's
//            compensated(F, F_hat) (core/control/describing_function.hpp)
//   none
//   coulomb  u_ff = Fc_hat sgn(v_ff)
//   gms      u_ff = F of a GMS model (its own state) driven by v_ff inside the controller
//            (prescribed motion)
// Mismatch: the compensator's model = the plant's friction with its force levels (Fs, Fc) times
// `force`, element stiffnesses and micro-damping times `stiffness`, Vs times `velocity`. When the
// plant's model is not GMS, the GMS compensator takes the reference set's elements with the
// plant's Fs, Fc, Vs, delta, sigma2 where the plant's model has them.
// Throws InputError for a bad config (dt, T, duration, compensator) and SimulationError on
// divergence.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/control/design_plant.hpp"
#include "core/control/linear_response.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab::control {

enum class Compensation { None, Coulomb, Gms };
const char* to_string(Compensation c);
Compensation compensation_from_string(const std::string& s);  // none | coulomb | gms

// The velocity the feedforward compensation is driven by; saved as "reference" | "measured".
enum class FeedforwardSource { Reference, Measured };
const char* to_string(FeedforwardSource f);
std::optional<FeedforwardSource> feedforward_source_from_string(const std::string& s);

struct Mismatch {
  double force = 1.0;      // compensator's Fs, Fc / plant's [-]
  double stiffness = 1.0;  // compensator's k_i, sigma_i / plant's [-]
  double velocity = 1.0;   // compensator's Vs / plant's [-]
};

struct LoopConfig {
  Signal reference;          // x_ref(t) [m]
  LeadCompensator C;         // Gc = Kc prod_i (s + z_i) / (s + p_i) (one or two sections)
  double sample_time = 0.0;  // controller sample time T [s]; 0 = continuous
  Compensation comp = Compensation::None;
  FeedforwardSource feedforward_source = FeedforwardSource::Reference;  // what drives u_ff
  Mismatch mismatch;
  double dt = 1e-5;          // integration step [s]
  double duration = 1.0;     // [s]
  int record_every = 10;     // keep every n-th step
};

struct LoopTrace {
  std::vector<double> t, r, x, v;  // time [s], reference [m], position [m], velocity [m/s]
  std::vector<double> u, ff;       // controller force, feedforward force [N]
  std::vector<double> friction;    // plant friction force [N]
};

struct LoopMetrics {
  double steady_state_error = 0.0;  // mean of e over the last 20 % of the run [m]
  double tail_max_error = 0.0;      // max |e| over the last 20 % [m]
  double rms_error = 0.0;           // sqrt(mean e^2) over the whole run [m]
  double overshoot = 0.0;           // step references: % of the step (NaN otherwise)
  double settling_time = 0.0;       // step: last exit from a 2 % band around the final value [s]
                                    // (NaN: never settles, or not a step)
  bool hunting = false;             // constant reference, x oscillates in the tail (limit cycle)
  double cycle_amplitude = 0.0;     // half peak-to-peak of x in the tail [m]
  double cycle_period = 0.0;        // mean spacing of upward mean crossings [s]
};

// The compensator's GMS model (see the mismatch rules above).
ModelParams feedforward_model(const ModelParams& plant_friction, const Mismatch& m);
// The Coulomb compensator's level Fc_hat [N]: the plant's Fc (its break-away force when the model
// has no Fc) times m.force.
double coulomb_feedforward_level(const ModelParams& plant_friction, const Mismatch& m);
// The loop on the scenario's plant (its drive replaced by the controller's force): the loop below on
// the scenario's one-body assembly (assembly_from_scenario), port drive "drive", output x.mass.
LoopTrace simulate_loop(const Scenario& s, const LoopConfig& c);
// The loop on an assembled plant (core/sim/assembly.hpp, its own integrator and contacts): the
// controller's u acts through drive port.drive (a force drive: F = u + u_ff [N]; a pull drive: u is
// the point's position x_p [m] and the feedforward adds u_ff / k_p), measuring port's output (x.BODY
// [m], or v.BODY [m/s]: a velocity loop). Every other drive keeps its signal (a disturbance). The
// compensation feeds forward the friction of every contact to ground, each driven by v_ref (a rigid
// train moves at v_ref, where contacts between two bodies do not slip), or with the measured source
// by the drive's body velocity. Trace: x = the output, v =
// the output body's velocity, friction = the sum of the contacts' forces to ground on their bodies.
// The assembly's run settings are replaced by c.dt and c.duration. Throws as the one-body loop; the
// dt limit is assembly_loop_dt_limit.
LoopTrace simulate_loop(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c);
// Largest stable step of that loop [s]: 2 / w_max with contacts stuck and the controller's
// high-frequency gain Kc as one more spring from the drive's body to ground (Kc k_p for a pull drive).
double assembly_loop_dt_limit(const Assembly& a, std::size_t drive, double Kc);
// The loop as a stepper whose whole state is one vector: the step simulate_loop takes
// (simulate_loop runs this stepper), for periodic orbits of the loop
// (core/control/limit_cycles.hpp). Built by loop_stepper (checks as simulate_loop); `horizon` [s]
// bounds the steps the plant's run allows.
class LoopStepper {
 public:
  struct Forces {
    double u = 0.0, ff = 0.0, friction = 0.0;  // controller, feedforward, friction to ground [N]
  };
  LoopStepper(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c,
              double horizon);
  ~LoopStepper();
  LoopStepper(LoopStepper&&) noexcept;
  LoopStepper& operator=(LoopStepper&&) noexcept;
  // One step of dt; throws SimulationError when the loop diverges.
  Forces step();
  double output() const;     // x (or v for a velocity loop) of the output body
  double velocity() const;   // the output body's velocity [m/s]
  double reference() const;  // x_ref at the current time
  double time() const;
  long long step_index() const { return k_; }
  double dt() const;
  // Controller sample period in steps (1: continuous).
  long long sample_every() const;
  // State: the plant's (AssemblySimulation::state_vector), the controller's, the feedforward's.
  std::vector<double> state() const;
  void state_into(std::vector<double>& z) const;  // the same into z (its capacity reused)
  // Sets the state and the step index (the time the reference and drive signals are read at; a
  // sampled controller samples at multiples of sample_every()).
  void set_state(std::span<const double> z, long long step_index);
  // Per state entry: 1 where it is a continuous quantity, 0 where it is a flag (a friction
  // element's slip flag) or a constant (the feedforward's model driven by a constant reference).
  std::vector<std::uint8_t> continuous_mask() const;
  std::size_t output_index() const;    // where output() sits in state()
  std::size_t velocity_index() const;  // where velocity() sits in state()

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
  long long k_ = 0;
};
// The stepper of the one-body loop (simulate_loop(s, c)) and of the assembled loop, configs checked
// as simulate_loop checks them.
LoopStepper loop_stepper(const Scenario& s, const LoopConfig& c, double horizon);
LoopStepper loop_stepper(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c,
                         double horizon);

LoopMetrics loop_metrics(const LoopTrace& tr);
// e = r - x at every recorded sample [m].
std::vector<double> tracking_error(const LoopTrace& tr);

}  // namespace gmslab::control
