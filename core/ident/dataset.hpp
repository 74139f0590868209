// gmslab identification: a measured record prepared for fitting.
//
// From a MeasuredRecord (t [s], x [m], F [N], optional v [m/s], Fn [N]) it derives what the fit
// needs, all on the record's own (possibly non-uniform) time grid:
//   v[k]      velocity [m/s]: the file's v, or the derivative of a local least-squares cubic in x
//             over +-3 samples
//   a[k]      acceleration [m/s^2]: second derivative of a local least-squares quartic in x over
//             +-4 samples (local_second_derivative); with a file's v, the local slope of v over +-3
//   h[k]      step t[k] - t[k-1] [s] (h[0] = 0)
//   vstep[k]  velocity frozen over the step k-1 -> k [m/s]: (x[k] - x[k-1]) / h[k], with or without
//             a velocity column (the prescribed motion of FrictionModel::step moves by the
//             measured displacement; a file's v shapes the path between samples)
//   sub, sv, sh  where the path between two samples is curved (a reversal between them: 16 parts;
//             the speed changing by more than 3 % over more than an encoder step, or the cubic
//             through the samples (Hermite: x and v at both ends) leaving the straight line by
//             more than 5 % of the step and a quarter of the encoder step: 8 parts; PathRule),
//             the step k-1 -> k is made along that cubic: velocities sv[j], durations sh[j] for
//             j in [sub[k], sub[k+1]); elsewhere the one step (vstep[k], h[k]). Models are stepped
//             through it with for_each_step.
//   use[k]    1 = the sample counts in cost and RMS; 0 = masked (time windows, the first and last
//             edge samples where derived signals carry filter edge effects, or a hold-out part)
// Masked samples are still simulated (the friction state runs through them).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/io/csv.hpp"

namespace gmslab::ident {

struct TimeWindow {
  double t0 = 0.0;  // start [s]
  double t1 = 0.0;  // end [s], > t0
};

struct Dataset {
  std::string source;
  std::vector<double> t, x, v, a, F, Fn, h, vstep;
  std::vector<std::uint32_t> sub;  // size() + 1 entries (or empty: no interval is curved)
  std::vector<double> sv, sh;      // substep velocities [m/s] and durations [s]
  std::vector<std::uint8_t> use;
  bool has_v = false;   // v came from the file
  bool has_Fn = false;  // a normal-force column exists

  std::size_t size() const { return t.size(); }
  std::size_t used() const;
};

// How the path between two samples is stepped: in `reversal_parts` along the cubic where the
// direction reverses between them (the elements stick and re-load there; at fast attraction the
// force follows the speed through zero within a fraction of the step), in `curved_parts` where the
// speed changes by more than `speed_change` (relative) over more than an encoder step or the cubic
// leaves the straight line, else in `other_parts` (1: one straight step with the secant speed).
struct PathRule {
  int reversal_parts = 16;
  int curved_parts = 8;
  double speed_change = 0.03;
  int other_parts = 1;
};
// The fine path: every interval along the cubic (what a fast attraction, C h >> 1, needs: the force
// at a sample follows the speed at that sample, not the step's mean speed).
inline constexpr PathRule kFinePath{16, 8, 0.03, 4};
// Sets d's sub, sv, sh by the rule (from d.x, d.v, d.h).
void set_path(Dataset& d, const PathRule& rule);

// A copy of d stepped along straight lines between all samples (no substeps): what the path
// between samples can change is the difference (NoiseEstimate::sampling).
inline Dataset with_straight_steps(Dataset d) {
  d.sub.clear(), d.sv.clear(), d.sh.clear();
  return d;
}

// A copy of d along the smoothest positions its encoder allows: each x the local least-squares
// cubic over +-3 samples, held within q/2 of the recorded count (q: the encoder step); v (where
// it came from x) and a derived again, the step velocities and the path made again by `rule`. The
// difference of a model along it and along d is what the encoder's rounding can change.
Dataset within_encoder_step(const Dataset& d, double q, const PathRule& rule);

// Calls step(v, h) for each part of the step k-1 -> k (k >= 1): the substeps where the path is
// curved, else once with (vstep[k], h[k]).
template <class Step>
inline void for_each_step(const Dataset& d, std::size_t k, Step&& step) {
  if (!d.sub.empty() && d.sub[k + 1] > d.sub[k]) {
    for (std::uint32_t j = d.sub[k]; j < d.sub[k + 1]; ++j) step(d.sv[j], d.sh[j]);
  } else {
    step(d.vstep[k], d.h[k]);
  }
}

// Every `every`-th sample of d (from the first), the derived signals (v, a) kept as computed at the
// full rate; steps, step velocities and the path between the kept samples made again by `rule`.
// What the residual loop screens long records on (LoopOptions::screen_samples).
Dataset decimated(const Dataset& d, std::size_t every, const PathRule& rule);

// Parses "t0:t1,t0:t1,..." [s]; throws InputError naming `what` (the option or field) and the bad
// item (t1 must exceed t0).
std::vector<TimeWindow> parse_masks(std::string_view spec, std::string_view what = "--mask");
// Windows [-before, +after] around every change of value of `code` (e.g. EMPS pulse_code edges).
std::vector<TimeWindow> edge_windows(const std::vector<double>& t, const std::vector<double>& code,
                                     double before, double after);

// "COLUMN:BEFORE:AFTER" [s, s]: edge_windows around every change of the record's extra column
// COLUMN (e.g. "pulse_code:0.005:0.060"). Empty spec: none. Throws InputError naming `what` on a
// malformed spec or negative times. When the record has no such column nothing is masked and
// *note (if given) says so, listing the columns it has.
std::vector<TimeWindow> parse_edge_masks(std::string_view spec, const MeasuredRecord& r,
                                         std::string_view what = "--mask-edges",
                                         std::string* note = nullptr);

// What a user gives for one record: the CSV, its column map, the force, time windows and edge masks.
struct RecordSpec {
  std::string path;
  std::string columns;     // "t=t_s,x=x_m,F=F_N"; empty = found by name
  std::string mask;        // "t0:t1,..." [s]
  std::string mask_edges;  // "COLUMN:BEFORE:AFTER" [s]
  std::string mask_what = "--mask", edges_what = "--mask-edges";  // names used in errors
  std::string force{};     // which force of a simulation trace is F: "" (friction), "friction", "applied"
};
// Loads and prepares one record (load_measured_csv, parse_masks, parse_edge_masks,
// prepare_dataset). Throws InputError naming the file, line, column or option.
Dataset load_dataset(const RecordSpec& spec, std::string* note = nullptr);

// Prepares a record. `edge` samples at each end are masked (derived-signal edge effects).
Dataset prepare_dataset(const MeasuredRecord& r, const std::vector<TimeWindow>& masks = {},
                        std::size_t edge = 10);
// A hold-out split of one record: every `period`-th block of `block` seconds goes to validation.
// Returns {train, validation}: the same samples with complementary use[] masks. Throws
// InputError when either part would have fewer than kMinSamples used samples.
std::pair<Dataset, Dataset> split_holdout(const Dataset& d, double fraction = 0.25, int blocks = 8);

// Throws InputError naming the record (`role`: "training", "validation") when it cannot identify
// friction: fewer than kMinSamples used samples, no motion over the used samples, or (training)
// no reversal of the direction of motion (friction is then indistinguishable from a constant
// force).
void check_identifiable(const Dataset& d, std::string_view role, bool need_reversal);

// Local least-squares slope of y(t) over +-w samples (non-uniform t); ends use one-sided windows.
std::vector<double> local_slope(const std::vector<double>& t, const std::vector<double>& y, int w);
// Derivative of y(t) from a local least-squares cubic over 2w+1 samples centred on each sample
// (shifted inwards at the ends; non-uniform t). Exact for cubics: unlike the local slope it has no
// bias from the curvature of a sine or a reversal.
std::vector<double> local_derivative(const std::vector<double>& t, const std::vector<double>& y, int w);
// Value at each sample of the local least-squares cubic over 2w+1 samples (as local_derivative).
std::vector<double> local_cubic_value(const std::vector<double>& t, const std::vector<double>& y,
                                      int w);
// Second derivative of y(t) from a local least-squares quartic over 2w+1 samples (w >= 2) centred
// on each sample (shifted inwards at the ends; non-uniform t); with fewer than 2w+1 samples, the
// local slope of local_derivative. Exact for quartics, so an acceleration pulse a dozen samples
// long keeps its peak, where the slope of a smoothed velocity flattens it (and least squares then
// reads more mass from the same force: docs/identification-credit.md, "Coverage").
std::vector<double> local_second_derivative(const std::vector<double>& t,
                                            const std::vector<double>& y, int w);

}  // namespace gmslab::ident
