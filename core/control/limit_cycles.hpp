// gmslab core/control: periodic orbits (limit cycles) of the closed loop with friction, computed on
// the loop's own stepper (LoopStepper, core/control/loop_simulation.hpp): the one simulate_loop
// runs, so an orbit and the long simulation see the same dynamics - one-body or assembled plant,
// any compensator (continuous or sampled), any registry friction model with its internal states.
//
// Poincare section: the output y (x of the output body) crossing the level c upward, c = the
// constant reference for a compensator with an integrator (its periodic state needs a zero mean
// error), else the mean of y over the seed's last cycle. Continuous controller: the crossing is
// located inside the step by linear interpolation of the whole state (slip flags taken after the
// step); the unknowns are the state's continuous entries but y itself (fixed on the section).
// Sampled controller (T > 0): the section is the first sample instant after the crossing, y is an
// unknown and the period a whole number of steps. The section map P runs the loop from a state on
// the section to its next upward crossing (after y fell below c - 0.1 (max y - c)).
// Seeds: the end of a short simulation of the loop from rest, and from rest at y = c - A_df (A_df:
// the describing function's amplitude, hunting.hpp) when one is given. From a seed: fixed-point
// iterations of P (a stick phase contracts the state strongly), then Newton on P(z) - z with the
// finite-difference Jacobian M = dP/dz (steps 1e-4 of each entry's range over the orbit); at the
// solution M's eigenvalues are the nontrivial Floquet multipliers; stable: all |mu| < 1.
// Map (hunting_map): orbits against a scale s of the controller gain Kc by pseudo-arclength
// continuation from the orbit at s = 1, down and up: predictor along the tangent of the branch in
// (u, ln s) (u: the section state's unknowns scaled by their ranges), corrector Newton on
// P(u; s) - u = 0 with the arclength constraint; a fold (the branch turning back in s: the stable
// and the unstable cycle meet, a real multiplier at +1) is passed and the unstable cycle traced.
#pragma once

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "core/control/hunting.hpp"
#include "core/control/loop_simulation.hpp"

namespace gmslab::control {

// The loop whose orbits are sought: a one-body scenario, or an assembled plant with its port; the
// config's reference must be constant.
struct ClosedLoop {
  Scenario scenario;
  std::optional<AssemblyScenario> assembly;
  AssemblyPort port;
  LoopConfig config;
};

struct OrbitOptions {
  double seed_duration = 60.0;  // longest short simulation from rest [s]
  int seed_crossings = 4;       // fewest upward crossings it runs to; then until they repeat
  double max_period = 0.0;      // longest period the map runs [s]; 0: 3 x the seed's (or 30 s)
  int fixed_point = 6;          // fixed-point iterations before Newton
  int newton = 12;              // Newton iterations
  double tolerance = 1e-5;      // scaled residual |P(z) - z|_inf / range (or the step's resolution
                                // 2 pi dt / T where Newton cannot do better)
  double fd_step = 1e-4;  // finite-difference step / each entry's range (at least 4 x 2 pi dt / T)
  bool fresh_multipliers =
      true;  // warm starts: the multipliers from a fresh finite-difference Jacobian
};

struct PeriodicOrbit {
  double gain_scale = 1.0;      // Kc x this
  double amplitude = 0.0;       // half peak-to-peak of the output over one period [m]
  double period = 0.0;          // [s]
  double mean = 0.0;            // mean of the output over the period [m]
  double stick_fraction = 0.0;  // time with |v| of the output body below 1e-4 m/s / period
  std::vector<std::complex<double>> multipliers;  // nontrivial Floquet multipliers, |mu| descending
  // Every |mu| < 1; or, where the finite differences say otherwise, the orbit displaced along the
  // dominant eigenvector does not grow over 6 returns (growth < 1.01: it attracts, or belongs to a
  // family of orbits whose never-slipping elements keep any offset)
  bool stable = false;
  double growth = 0.0;      // that displacement's growth per period (0: not iterated)
  double residual = 0.0;    // scaled |P(z) - z| at the solution
  int map_evaluations = 0;  // section-map runs this orbit took
  std::string seed;         // "simulation", "describing function" or "continuation"
  // false: the multipliers are those of the Jacobian carried from a neighbouring orbit with
  // Broyden updates (a warm start without OrbitOptions::fresh_multipliers)
  bool multipliers_fresh = true;
  double level = 0.0;  // the section level c [m]
  int returns = 1;     // upward crossings of c per period
  // Warm-start data: the state on the section, the unknown entries, their scales, the Jacobian
  // of the section map in those scaled unknowns (column-major).
  std::vector<double> section_state;
  std::vector<std::size_t> unknowns;
  std::vector<double> scale;
  std::vector<double> jacobian;
};

struct OrbitReport {
  std::vector<PeriodicOrbit> orbits;  // distinct orbits, by decreasing amplitude
  std::string method;                 // what was searched, how (always set)
  std::string not_found;              // why there is none (empty when there are orbits)
  int map_evaluations = 0;
  double dt = 0.0;                      // the loop's integration step [s]
  const PeriodicOrbit* stable() const;  // the stable orbit of largest amplitude (nullptr: none)
};

// The map: the branch of orbits through the start orbit, traced by pseudo-arclength continuation
// in (section state, ln gain scale); points in order along the branch (the gain scale need not be
// monotone: past a fold the branch turns back as the unstable cycle). Each point's orbit says
// stable or not (its multipliers, fresh finite differences at each point).
struct HuntingMapPoint {
  double gain_scale = 0.0;
  std::optional<PeriodicOrbit> orbit;
};
struct HuntingMap {
  std::vector<HuntingMapPoint> points;  // along the branch
  std::vector<double> folds;            // gain scales where the branch turns (a multiplier at +1)
  std::optional<double> fold;           // the fold nearest the start's gain (the threshold)
  std::string note;                     // how it was traced, where and why the branch ends
  int map_evaluations = 0;
};

// Orbits of the loop from the seeds above. Throws InputError for a non-constant reference or a bad
// loop (as simulate_loop), SimulationError when the loop diverges.
OrbitReport find_orbits(const ClosedLoop& loop, const OrbitOptions& opt = {},
                        const HuntingReport* df = nullptr);
// Newton from a known orbit (warm start: a neighbouring gain scale); nullopt when it does not
// converge.
std::optional<PeriodicOrbit> continue_orbit(const ClosedLoop& loop, const PeriodicOrbit& from,
                                            double gain_scale, const OrbitOptions& opt = {});
// The map over gain scales lo..hi (steps of at most ln(hi / lo) / (n - 1) in ln s), continued from
// `start` (an orbit at its gain scale, e.g. find_orbits' stable one at 1) both ways until the
// branch leaves [lo, hi] or is lost. Throws InputError for lo <= 0, hi <= lo, n < 2.
HuntingMap hunting_map(const ClosedLoop& loop, const PeriodicOrbit& start, double lo, double hi,
                       int n, const OrbitOptions& opt = {});

}  // namespace gmslab::control
