// gmslab core: a 1-D lumped plant assembled from parts (schema version 2 presets).
//
// Up to kMaxBodies bodies (mass > 0) on one axis; springs and dampers between two bodies or a body
// and ground; friction contacts between a body and ground or two bodies, each with its own registry
// model and parameters, acting on the relative velocity v_a - v_b (force F on a, -F on b); drives:
//   force         F(t) on a body
//   displacement  the body's position x(t) is prescribed
//   velocity      the body's velocity v(t) is prescribed, x integrated
//   pull          a drive point x_p(t) pulls the body through a spring k_p and damper c_p (seed
//   Fig. 3);
//                 with point_velocity the signal is the point's velocity v_p(t), x_p integrated.
// Ground is body index kGround (-1). AssemblySimulation is the one engine: a v1 Scenario runs as
// its one-body assembly (assembly_from_scenario, one_body_simulation), recording the one-body trace
// (core/sim/simulation.hpp), with a fast path per drive kind.
//
// Integrator (AssemblySimulation), per step of length h, the one-body contract per contact:
//   1. prescribed bodies: x(t + h), and the velocity over the step that their contacts see
//   2. non-friction forces on every body (drives, springs, dampers) at (x, v)
//   3. each contact in turn: its exact step with its relative velocity frozen -> F_j, given the
//      effective mass m_a m_b / (m_a + m_b) of its free bodies and the non-friction relative
//      force (stick band models); F_j on a, -F_j on b
//   4. free bodies: v <- v + h f / m, x <- x + h v (symplectic Euler)
// Internal forces (springs, dampers, contacts between bodies) act equal and opposite, so the total
// momentum of the free bodies changes only by the external forces.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/signal.hpp"
#include "core/sim/simulation.hpp"  // TraceOptions

namespace gmslab {

inline constexpr int kGround = -1;
inline constexpr std::size_t kMaxBodies = 8;

struct Body {
  std::string name;
  double mass = 1.0;  // [kg], > 0
  bool operator==(const Body&) const = default;
};

struct SpringPart {
  std::string name;
  int a = 0, b = kGround;  // body indices (kGround = ground)
  double stiffness = 0.0;  // k [N/m], >= 0; force on a: -k (x_a - x_b)
  bool operator==(const SpringPart&) const = default;
};

struct DamperPart {
  std::string name;
  int a = 0, b = kGround;
  double damping = 0.0;  // c [N s/m], >= 0; force on a: -c (v_a - v_b)
  bool operator==(const DamperPart&) const = default;
};

struct ContactPart {
  std::string name;
  int a = 0, b = kGround;  // friction acts on v_a - v_b
  ModelParams friction;
  bool operator==(const ContactPart&) const = default;
};

struct DrivePart {
  enum class Kind { Force, Displacement, Velocity, Pull };
  std::string name;
  Kind kind = Kind::Force;
  int body = 0;
  Signal signal;               // F [N], x [m], v [m/s], or x_p [m] (v_p [m/s] with point_velocity)
  double pull_spring = 0.0;    // k_p [N/m] (pull)
  double pull_damper = 0.0;    // c_p [N s/m] (pull)
  bool point_velocity = false; // pull: the signal is the drive point's velocity
  bool operator==(const DrivePart&) const = default;
};

struct Assembly {
  std::vector<Body> bodies;
  std::vector<SpringPart> springs;
  std::vector<DamperPart> dampers;
  std::vector<ContactPart> contacts;
  std::vector<DrivePart> drives;
  bool operator==(const Assembly&) const = default;
};

struct AssemblyScenario {
  std::string name;
  std::string description;
  Assembly plant;
  RunSettings run;
  bool operator==(const AssemblyScenario&) const = default;
};

const char* to_string(DrivePart::Kind k);

// Every problem of the plant's structure and values, each naming its key path (e.g.
// "plant.springs[1].b: ..."); empty when valid. Checks: 1..8 bodies, mass > 0, indices in range, no
// part between a body and itself, at most one prescribed-motion drive per body, every group of
// connected bodies reaches ground or a drive, unique non-empty names, valid friction parameters.
std::vector<std::string> validate(const Assembly& a, const std::string& where = "plant");

// The one-body v1 scenario as an assembly: body "mass", spring/damper "spring"/"damper" to ground,
// contact "friction" to ground, drive "drive".
AssemblyScenario assembly_from_scenario(const Scenario& s);
// The inverse: the one-body scenario of an assembly of exactly that shape (those names, every part
// on body 0 and ground, a drive without point_velocity); nullopt for any other assembly.
std::optional<Scenario> one_body_scenario(const AssemblyScenario& a);

// Stiffness of a contact with every element stuck: sum k_i (+ sigma0) [N/m].
double stuck_stiffness(const ModelParams& p);
// Viscous terms a contact applies explicitly: sigma1 + sigma2 + sum sigma_i [N s/m].
double contact_damping(const ModelParams& p);

// Angular frequencies [rad/s] of the free bodies' modes, ascending, with contacts stuck (their
// stuck stiffness) or free, from the generalised eigenproblem K phi = w^2 M phi (Eigen).
// Prescribed bodies and drive points are fixed (pull springs tie to them).
std::vector<double> modal_frequencies(const Assembly& a, bool contacts_stuck = true);
// Largest stable step: 2 / w_max with contacts stuck; +inf when nothing is free or stiff.
double stability_limit_dt(const Assembly& a);

// One output channel of the trace.
struct Channel {
  enum class Kind { Position, Velocity, ContactForce, SpringForce, DamperForce, DriveForce };
  Kind kind;
  int index;         // body / contact / spring / damper / drive index
  std::string name;  // e.g. "x.load", "F.motor_friction"
  std::string unit;  // "m", "m/s", "N"
};
std::vector<Channel> output_channels(const Assembly& a);

struct AssemblyTrace {
  std::vector<Channel> channels;
  std::vector<double> t;       // [s]
  std::vector<double> values;  // [sample * channels.size() + c]
  // Per contact: recorded element count, and per sample its element forces [N] and slip flags.
  std::vector<std::size_t> n_elements;
  std::vector<std::vector<double>> element_force;        // [contact][sample * n + i]
  std::vector<std::vector<std::uint8_t>> element_slip;   // same layout, 1 = slipping
  std::vector<std::vector<std::uint8_t>> contact_slip;   // [contact][sample], 1 = gross slip
  std::size_t size() const { return t.size(); }
  std::ptrdiff_t channel(const std::string& name) const;  // -1 if absent
  double at(std::size_t sample, std::size_t c) const { return values[sample * channels.size() + c]; }
  std::vector<double> series(const std::string& name) const;  // throws InputError when absent
  // Bytes one sample takes: t and every channel (8 each), per contact its element forces (8) and
  // slip flags (1) and its gross-slip flag (1).
  std::size_t sample_bytes() const;
  void clear();  // drops the samples, keeps the channels and element counts
};

// Compacts `tr` in place as compact_minmax does the one-body trace: samples are grouped into
// buckets of `bucket_steps` integration steps (sample k in bucket round(t_k / dt) / bucket_steps);
// each bucket keeps, in order and without duplicates, its first and last sample and the first
// sample of the smallest and of the largest value of every channel (at most 2 + 2 channels).
// Nested bucket widths compose: compacting twice keeps every bucket extreme of the original.
void compact_minmax(AssemblyTrace& tr, double dt, std::uint64_t bucket_steps);

class AssemblySimulation {
 public:
  // A contact is in gross slip when |v_rel| exceeds this or all its elements slip [m/s] (the
  // window's default slip velocity, ViewSettings::slip_velocity).
  static constexpr double kSlipVelocity = 1e-4;
  static constexpr std::size_t kMaxRecordedElements = 64;

  // Validates (throws InputError). `trace` bounds the trace's memory: max_bytes > 0 compacts it
  // (compact_minmax, bucket widths doubling) whenever it fills, so a run of any length keeps every
  // extreme of every output within that memory; max_bytes = 0 keeps every recorded sample (a
  // consumer can take them in chunks: clear_trace()).
  explicit AssemblySimulation(const AssemblyScenario& s, TraceOptions trace = {});
  // Not copyable (the trace's channel table points into this object's arrays); movable.
  AssemblySimulation(const AssemblySimulation&) = delete;
  AssemblySimulation& operator=(const AssemblySimulation&) = delete;
  AssemblySimulation(AssemblySimulation&&) = default;
  AssemblySimulation& operator=(AssemblySimulation&&) = default;
  void reset();
  // Advances by n steps (stops at the end of the run); returns the steps done. Throws
  // SimulationError when the state turns non-finite or - one free body, no drive input - when its
  // kinetic and spring energy grows beyond its start value + the drives' work + what the contacts
  // can store elastically (checked every 1024 steps, the margin of energy_margin), naming the
  // likely cause. A one-body scenario's plant (one_body_scenario) says it in the one-body words
  // (divergence_cause).
  std::size_t advance(std::size_t n);
  void run_to_end();
  bool finished() const { return step_ >= total_steps_; }
  double time() const { return static_cast<double>(step_) * sc_.run.dt; }

  const AssemblyScenario& scenario() const { return sc_; }
  // The samples (a run of one_body_simulation: none; they go to one_body_trace()).
  const AssemblyTrace& trace() const { return trace_; }
  // A run of one_body_simulation records the one-body trace instead: t, x, v, F_f, F_applied
  // (prescribed motion: F_f) and the contact's element columns, bounded and compacted by the
  // TraceOptions (compact_minmax of a Trace). Empty for any other run.
  const Trace& one_body_trace() const { return body_trace_; }
  Trace take_one_body_trace() { return std::move(body_trace_); }
  AssemblyTrace take_trace() { return std::move(trace_); }
  void clear_trace() {  // samples taken by a streaming consumer
    trace_.clear();
    body_trace_.clear();
  }
  // The one-body samples recorded so far go to `out` (its sample columns and theirs are
  // exchanged, n_elements set) and the trace records on into out's former columns, emptied:
  // clear_trace() for a streaming consumer that reuses its chunks' memory instead of copying.
  void hand_over_one_body_trace(Trace& out) {
    out.clear();
    out.t.reserve(body_trace_.t.capacity());  // the room reserved at reset, kept chunk after chunk
    out.x.reserve(body_trace_.x.capacity());
    out.v.reserve(body_trace_.v.capacity());
    out.friction.reserve(body_trace_.friction.capacity());
    out.applied.reserve(body_trace_.applied.capacity());
    out.element_force.reserve(body_trace_.element_force.capacity());
    out.element_slip.reserve(body_trace_.element_slip.capacity());
    body_trace_.swap_samples(out);
    out.n_elements = body_trace_.n_elements;
    clear_trace();
  }
  // Integration steps per bucket of a compacted trace; 0 while every recorded sample is kept.
  std::uint64_t trace_bucket_steps() const { return bucket_steps_; }
  std::size_t trace_max_samples() const { return max_samples_; }
  std::span<const double> positions() const { return x_; }
  std::span<const double> velocities() const { return v_; }
  double momentum() const;          // sum over free bodies of m v [kg m/s]
  double kinetic_energy() const;    // [J]
  double spring_energy() const;     // springs + pull springs [J]
  const FrictionModel& contact_model(std::size_t j) const { return *models_[j]; }
  double contact_force(std::size_t j) const { return f_contact_[j]; }  // last step's F_j on a [N]
  // Feedback through a drive (core/control/loop_simulation.hpp): from now on, force or pull drive i
  // takes `u` instead of its signal - a force drive's F [N], a pull drive's point x_p [m] (moving at
  // (u - last x_p) / h over the next step). Set before each advance(1). Throws InputError for a
  // drive that is not a force or pull drive.
  void set_drive_input(std::size_t i, double u);
  std::span<const double> contact_state(std::size_t j) const { return state_[j]; }
  // The dynamic state as one vector: every body's x, then v, every drive point x_p, then each
  // contact's model state in turn (state_layout: where each part starts); the time is not part of
  // it. set_state_vector takes one of the same size (InputError otherwise) and set_step moves the
  // step counter (the time drives' signals are read at); both for a loop's periodic orbits
  // (core/control/limit_cycles.hpp).
  std::vector<double> state_vector() const;
  void state_into(std::vector<double>& z) const;  // the same into z (cleared; capacity reused)
  void set_state_vector(std::span<const double> z);
  void set_step(std::uint64_t step) { step_ = step; }
  std::uint64_t step() const { return step_; }
  // Offset of contact j's model state in state_vector().
  std::size_t contact_state_offset(std::size_t j) const;

  // Live edits, between steps: from the next step on the plant's values are `a`'s, the state (time,
  // positions, velocities, contact states, trace) kept. `a` must have the plant's structure: the
  // same bodies, parts and names, each part between the same ends, each drive of the same kind on
  // the same body (masses, coefficients, friction parameters, drive signals and pull spring and
  // damper may change). A contact whose model keeps its tag and state size keeps its state; any
  // other restarts from its virgin state, its recorded element columns re-laid (earlier samples:
  // zeros). The energy watch is rebased. Throws InputError (naming the key) for an invalid plant or
  // another structure; nothing changes then.
  void set_plant(const Assembly& a);
  // Contact j's friction model (set_plant with that one change). For a one-body run the checks of
  // a one-body scenario (check_scenario: its messages) come first.
  void set_friction(const ModelParams& p, std::size_t contact = 0);
  // A one-body run's plant (mass, spring, damper); InputError for any other run.
  void set_plant(const Plant& p);
  // The one-body scenario this run's plant is (one_body_scenario, updated by live edits); nullopt
  // for any other plant.
  const std::optional<Scenario>& one_body() const { return as_scenario_; }

 private:
  friend AssemblySimulation one_body_simulation(const Scenario& s, TraceOptions trace);
  AssemblySimulation(const AssemblyScenario& s, TraceOptions trace, bool one_body_layout);
  void record();
  void record_one_body();
  void compact_trace();
  // The parts compiled for the step loop from sc_.plant (coefficients, 1/m, fast-path choice).
  void compile();
  void set_history_limit();            // max_samples_ from the options and the trace's sample size
  void relay_elements(std::size_t j);  // contact j's recorded element columns after a model change
  bool body_layout_ = false;      // record body_trace_ (one_body_simulation)
  bool body_prescribed_ = false;  // its drive prescribes the motion
  Trace body_trace_;
  // One step of the general plant; returns a sum of the new state and forces (non-finite when
  // any of them is).
  double compute_step();
  // The case of one free body (every part then ties it to ground): compute_step's sums in the
  // same order, with x and v kept in registers across steps - a store and reload per partial
  // sum lengthens the chain v -> forces -> friction -> v that bounds a step's time.
  std::size_t advance_one_body(std::size_t n);
  // The one-body case with at most one drive (K: 0 none, 1 force, 2 pull by the point's
  // position, 3 displacement, 4 velocity), spring, damper and contact, as a v1 preset maps:
  // advance_one_body's (K <= 2) or compute_step's (K >= 3) sums with the parts' values, the step
  // counters and the outputs in locals (written back before a sample is recorded), and the drive
  // inlined: the one-body loop of the one-body presets.
  // Gms: the contact is a GmsModel of at most GmsModel::kScalarElements elements, stepped inline.
  template <int K, bool Gms>
  std::size_t advance_simple(std::size_t n);
  // Full: exactly one spring, damper and contact (known at compile time); N > 0: a GMS contact of
  // N elements (known at compile time).
  template <int K, bool Gms, bool Full, std::size_t N>
  std::size_t advance_simple_as(std::size_t n);
  int simple_ = -1;  // K of advance_simple when it applies, else -1
  bool simple_gms_ = false;
  // Throws SimulationError: "simulation diverged at t = T s (non-finite friction force | state)"
  // and the likely cause.
  [[noreturn]] void diverged(bool friction) const;
  std::string divergence_cause() const;
  // Energy watch (advance, one free body): on while watch_; the account is rebased at reset.
  static constexpr std::uint64_t kEnergyCheckEvery = 1024;  // a power of 2
  void rebase_energy();
  void check_energy() const;
  bool watch_ = false;
  double drive_work_ = 0.0;  // work of the drives since the rebase [J]
  double energy0_ = 0.0;     // kinetic + spring energy at the rebase [J]
  double storage_ = 0.0;     // largest elastic energy the contacts can hold [J]
  double dt_limit_ = 0.0;    // stability limit of the step the margin scales with [s]
  std::vector<double> drive_rate_;      // per pull drive: its point's velocity this step [m/s]
  std::optional<Scenario> as_scenario_;  // the one-body scenario this plant is, if it is one

  AssemblyScenario sc_;
  std::vector<std::unique_ptr<FrictionModel>> models_;
  std::vector<std::vector<double>> state_;
  std::vector<Channel> channels_;
  std::vector<const double*> channel_src_;  // per channel: its value in x_, v_ or a force array
  AssemblyTrace trace_;
  TraceOptions trace_opts_;
  std::size_t max_samples_ = 0;     // 0: unbounded
  std::uint64_t bucket_steps_ = 0;  // width of the compacted buckets (0: not compacted)
  std::uint64_t step_ = 0, total_steps_ = 0, until_record_ = 1;
  // Per body: position, velocity, contact velocity over the step, force, 1/m, prescribed flag.
  std::vector<double> x_, v_, cv_, f_, h_over_m_;
  std::vector<std::uint8_t> prescribed_;
  std::vector<double> xp_;  // per drive: drive point position (pull with point_velocity or an input)
  std::vector<double> input_;           // per drive: the input set by set_drive_input
  std::vector<std::uint8_t> has_input_;  // per drive: 1 once set_drive_input was called
  bool any_input_ = false;
  // Force of force / pull drive i on its body (at x, v) over the step t -> t + h; advances xp_[i].
  double drive_force(std::size_t i, double t, double h, double x, double v);
  // The parts compiled for the step loop (ground = slot nb).
  struct Link { int a, b; double c; };
  struct CompiledContact { int a, b; int mode; double ma, mb, m_eff; };  // mode: 1 a free, 2 b free, 3 both
  std::vector<Link> springs_c_, dampers_c_;
  std::vector<CompiledContact> contacts_c_;
  bool has_prescribed_ = false;
  bool one_body_ = false;
  // Last step's part forces (outputs).
  std::vector<double> f_contact_, f_spring_, f_damper_, f_drive_, v_rel_;
};

AssemblyTrace simulate(const AssemblyScenario& s);

// A one-body scenario on the engine: checks it as a one-body scenario (check_scenario: its
// messages), then the simulation of assembly_from_scenario(s), recording the one-body trace
// (one_body_trace()). The window's Simulation tab, the CLI, Python and the sweeps run it.
AssemblySimulation one_body_simulation(const Scenario& s, TraceOptions trace = {});

}  // namespace gmslab
