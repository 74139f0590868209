// gmslab core: the one-body trace and the checks of a one-body scenario. A one-body scenario runs
// on the one engine, AssemblySimulation (core/sim/assembly.hpp), as its one-body assembly
// (one_body_simulation), which records this trace: t, x, v, F_f, F_applied and the contact's
// element columns.
//
// Integrator (semi-implicit / symplectic Euler with frozen-velocity friction steps), per step h:
//   1. friction: advance its state over [t, t + h] with v frozen -> F_f (exact per model)
//   2. v <- v + h (F_drive(t) - k x - c v - F_f) / m
//   3. x <- x + h v
// The friction sees the same velocity that moved it, so a stuck body has no spurious drift, and the
// stick mode (sqrt(sum k_i / m)) is integrated stably for h < 2 / omega. Prescribed-motion drives
// pass v = (x(t + h) - x(t)) / h, so hysteresis curves are exact at the sample points.
#pragma once

#include <cstdint>
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
  // Exchanges the sample columns (t .. element_slip) with o's; n_elements and revision stay.
  void swap_samples(Trace& o) noexcept;
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

// Runs a whole scenario and returns its one-body trace (one_body_simulation,
// core/sim/assembly.hpp).
Trace simulate(const Scenario& scenario);

}  // namespace gmslab
