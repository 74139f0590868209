// gmslab core: deterministic fixed-step simulation of a scenario.
//
// Integrator (semi-implicit / symplectic Euler with frozen-velocity friction steps):
//   1. friction: advance its state over [t, t + h] with v frozen -> F_f (exact per model)
//   2. v <- v + h (F_drive(t) - k x - c v - F_f) / m
//   3. x <- x + h v
// The friction sees the same velocity that moved it, so a stuck body has no spurious drift, and the
// stick mode (sqrt(sum k_i / m)) is integrated stably for h < 2 / omega. Prescribed-motion drives
// pass v = (x(t + h) - x(t)) / h, so hysteresis curves are exact at the sample points.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/sim/scenario.hpp"

namespace gmslab {

struct Trace {
  std::size_t n_elements = 0;         // elements recorded per sample (0 if not recorded)
  std::vector<double> t;              // time [s]
  std::vector<double> x;              // position of the body [m]
  std::vector<double> v;              // velocity of the body [m/s]
  std::vector<double> friction;       // friction force F_f [N]
  std::vector<double> applied;        // drive force on the body [N] (prescribed motion: F_f)
  std::vector<double> element_force;  // [sample * n_elements + i], F_i [N]
  std::vector<std::uint8_t> element_slip;  // same layout, 1 = slipping
  // Bumped whenever samples already recorded change (clear, compaction, re-laid element
  // columns); appending samples keeps it. Derived series (core/sim/phases.hpp) key on it.
  std::uint64_t revision = 0;

  std::size_t size() const { return t.size(); }
  void clear();
};

// How a simulation keeps its trace.
struct TraceOptions {
  // Largest memory the trace may take [bytes]; 0 = unbounded, every recorded sample is kept. When
  // a bounded trace fills up it is compacted (compact_minmax) into time buckets of a power-of-two
  // number of recorded samples, aligned at t = 0, until at most half of it is used: each bucket
  // keeps its first and last sample and the samples of the smallest and largest x, v, F_f and
  // F_applied, so the plots still show every extreme. A sample takes 40 + 9 n_elements bytes.
  std::size_t max_bytes = 0;
  // Samples reserved at reset (at most the run's sample count; at most max_bytes' worth). A
  // consumer that takes the samples as they come (clear_trace()) reserves one chunk.
  std::size_t reserve_samples = static_cast<std::size_t>(-1);
};

// Bytes one trace sample takes with n recorded elements (t, x, v, F_f, F_applied, F_i, slip_i).
constexpr std::size_t trace_sample_bytes(std::size_t n_elements) { return 5 * sizeof(double) + n_elements * 9; }

// Compacts `tr` in place: samples are grouped into buckets of `bucket_steps` integration steps
// (sample k in bucket round(t_k / dt) / bucket_steps); each bucket keeps, in order and without
// duplicates, its first and last sample and the first sample of the smallest and of the largest
// x, v, friction and applied force (at most 10 samples). Buckets of nested widths (multiples of
// each other) compose: compacting twice keeps every bucket extreme of the original trace.
void compact_minmax(Trace& tr, double dt, std::uint64_t bucket_steps);
// Compacts tr (a Trace or an AssemblyTrace: compact_minmax of its own kind) to at most half of
// max_samples: the current bucket width first (`bucket_steps`, 0 = none yet: the samples since the
// last compaction are raw, taken every `record_every` steps), then doubled until half the room is
// free, so the buckets stay nested. Returns the new width. Ends when one bucket keeps fewer
// samples than max_samples / 2.
template <class T>
std::uint64_t compact_to_half(T& tr, double dt, std::uint64_t bucket_steps, std::uint64_t record_every,
                              std::size_t max_samples) {
  std::uint64_t w = bucket_steps ? bucket_steps : record_every;
  if (bucket_steps) compact_minmax(tr, dt, w);
  while (tr.size() > max_samples / 2) {
    w *= 2;
    compact_minmax(tr, dt, w);
  }
  return w;
}

class Simulation {
 public:
  // Up to this many elements are recorded per sample in the trace.
  static constexpr std::size_t kMaxRecordedElements = 64;

  explicit Simulation(const Scenario& scenario, TraceOptions trace = {});  // validates; throws InputError
  void reset();
  // Advance by n steps of scenario.run.dt (stops early at the end of the run). Returns steps done.
  // Throws SimulationError, naming the likely cause (step vs stiffness / damping limits), when the
  // state turns non-finite or, for force and pull drives, the energy of the mass and springs grows
  // beyond what the drive put in (checked every 1024 steps). The trace keeps the finite samples
  // before that; reset() or a live edit makes the simulation usable again.
  std::size_t advance(std::size_t n);
  void run_to_end();
  bool finished() const { return step_ >= total_steps_; }

  // Live edits: take effect from the next step. A friction model of the same kind and element
  // count keeps its state; anything else restarts the friction from its virgin state.
  void set_friction(const ModelParams& p);
  void set_plant(const Plant& p);

  const Scenario& scenario() const { return sc_; }
  const FrictionModel& model() const { return *model_; }
  const Trace& trace() const { return trace_; }
  // Drops the recorded samples (a streaming consumer has taken them); the run goes on.
  void clear_trace();
  // Integration steps per bucket of a compacted trace (TraceOptions::max_bytes); 0 while every
  // recorded sample is kept.
  std::uint64_t trace_bucket_steps() const { return bucket_steps_; }
  std::size_t trace_max_samples() const { return max_samples_; }
  // Moves the trace out (no copy of a long run); reset() before advancing again.
  Trace take_trace() { return std::move(trace_); }
  double time() const { return static_cast<double>(step_) * sc_.run.dt; }
  double position() const { return x_; }
  double velocity() const { return v_; }
  std::span<const double> friction_state() const { return state_; }

 private:
  void record(double ff, double fapp);
  void set_history_limit();  // max_samples_ from the options and the recorded element count
  void compact_trace();
  template <Drive::Kind K>
  std::size_t advance_as(std::size_t n);
  [[noreturn]] void diverged(double ff) const;
  // Divergence watch for mass-driven plants, every kEnergyCheckEvery steps (hardening): throws
  // SimulationError naming the likely cause when the energy of the mass and springs exceeds its
  // start value + the drive's work + the friction's elastic storage by a margin.
  static constexpr std::uint64_t kEnergyCheckEvery = 1024;  // a power of 2
  double mechanical_energy() const;  // 1/2 m v^2 + 1/2 k x^2 (+ 1/2 k_p (x_p - x)^2) [J]
  void rebase_energy();              // at reset and after live edits
  void check_energy() const;

  Scenario sc_;
  std::unique_ptr<FrictionModel> model_;
  std::vector<double> state_;
  Trace trace_;
  TraceOptions trace_opts_;
  std::size_t max_samples_ = 0;     // 0: unbounded
  std::uint64_t bucket_steps_ = 0;  // current compaction bucket width (0: none yet)
  std::uint64_t step_ = 0;
  std::uint64_t total_steps_ = 0;
  std::uint64_t until_record_ = 1;  // steps until the next trace sample
  double x_ = 0.0, v_ = 0.0;
  double drive_work_ = 0.0;  // work done by the drive since the last rebase [J]
  double energy0_ = 0.0;     // mechanical energy at the last rebase [J]
  double storage_ = 0.0;     // largest elastic energy the friction can hold [J]
};

// Throws InputError listing every problem of the scenario (friction parameters, plant, run, the
// step against the stiffest mode for force and pull drives), each naming its key.
void check_scenario(const Scenario& s);
// "Likely cause: ..." of a diverged one-body run, with the numbers: the step against the stiffness
// and damping limits (2 / sqrt(sum k / m), 2 m / sum c).
std::string divergence_cause(const Scenario& s);
// Largest energy a friction model can store elastically [J]: Fb^2 / (2 k_min) over its
// stiffnesses (element k_i, bristle sigma0); 0 for a model without stiffness.
double friction_storage(const FrictionModel& m, const ModelParams& p);
// The energy watch's tolerance [J] above the budget (start energy + |drive work| + friction
// storage): symplectic Euler's energy wobbles by up to 1 / (1 - dt / dt_limit) around a conserved
// value, so (4 + 4 r / (1 - r)) budget with r = min(dt / dt_limit, 0.99), + 1e-12 J.
double energy_margin(double budget, double dt, double dt_limit);
// "simulation diverged at t = T s: the energy of the mass and springs grew to ... - the integration
// creates energy. " (the cause follows).
std::string energy_growth_message(double t, double e, double e0, double work, double storage);

// Runs a whole scenario and returns its trace: on the assembled plant's engine
// (one_body_simulation, core/sim/assembly.hpp), the samples as Simulation records them.
Trace simulate(const Scenario& scenario);

}  // namespace gmslab
