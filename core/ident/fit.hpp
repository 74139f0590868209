// gmslab identification: fitting a registered friction model (plus effects) to a measured record.
//
// Model of the measured force (variable projection):
//   F_meas(t_k) = Fc g_k(p) + sigma2 v_k + sum_j theta_j c_j(t_k) + e_k
// g(p) is the friction model with unit force level simulated along the measured motion
// (prescribed motion: FrictionModel::step with v = vstep[k], h = t[k] - t[k-1], from the virgin
// state). Every parameter whose unit contains N scales with the force level, so the model output
// is exactly proportional to it: the force level Fc, the viscous sigma2 and the effect amplitudes
// theta are linear and solved by weighted least squares inside each cost evaluation; only the
// shape p is searched (cost: RMS force error on the used samples [N]).
//
// Shape parameters (generic, read from ModelInfo): the reference force scalar (Fc, or the first
// scalar in N) is fixed at 1 N; other N-valued scalars are ratios to it (Fs/Fc in [1, 5],
// widened to [1, 25] by identify where the base fit pins it at 5);
// stiffness-like parameters (N/m) per unit force are searched around 1 / x_ba (x_ba estimated from
// the data after reversals); N/s (attraction C) in [0.5, 1e5] 1/s; velocities (m/s) in
// [1e-4, 2] v_ref; lengths (m) around the default; dimensionless within their range (at most 10
// wide). Element weights "alpha" are normalised to sum 1 (first weight fixed). Micro-damping
// "sigma" columns are fixed at 0; "sigma2" is linear. Positive parameters are searched in log
// space; all are mapped to the unit box [0, 1] for the optimiser.
//
// Optimisers (NLopt, derivative-free, bounded): bobyqa (default), sbplx, neldermead (the seed's
// downhill simplex). Several starts (the data-based guess, then deterministic perturbations).
// Progress is reported through a callback; a set cancel flag stops the fit (throws Cancelled).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/friction/model.hpp"
#include "core/ident/dataset.hpp"
#include "core/ident/effects.hpp"

namespace gmslab {
struct GmsParams;
struct GmsPath;
class GmsPathRunner;
}  // namespace gmslab

namespace gmslab::ident {

// A fit stopped by its cancel flag: an Error of kind Cancelled.
class Cancelled : public Error {
 public:
  Cancelled() : Error(ErrorKind::Cancelled, "identification cancelled") {}
};

struct FitSpec {
  std::string model = "gms";     // registry tag
  std::size_t elements = 4;      // element count (ignored for models without elements)
  std::vector<Effect> effects;   // added effects, in order
};

struct FitProgress {
  std::string stage;     // e.g. "base fit, start 2/3"
  int evaluations = 0;   // cost evaluations so far in this fit
  double best_rms = 0;   // best training RMS so far [N]
  int budget = 0;        // the most evaluations this fit can take (starts x max + polish)
};

struct FitOptions {
  std::string method = "bobyqa";  // bobyqa | sbplx | neldermead
  int starts = 3;                 // multi-start count (>= 1)
  int first_start = 0;            // element grid: start from the design points ranked
                                  // [first_start, first_start + starts) (a retry takes the next ones)
  int max_evaluations = 600;      // per start
  double rel_tol = 1e-7;          // relative cost tolerance
  bool data_start = true;         // also start from the data-based guess when warm-started
  bool polish_only = false;       // warm-started: one local search from the warm start with the
                                  // polishing step and budget, nothing else (a shape found on a
                                  // screened record refined on the full one)
  double max_seconds = 0;         // wall-time budget of the whole fit [s]; 0 = none
  std::string stage = "fit";      // label shown in progress
  std::function<void(const FitProgress&)> progress;  // may be empty
  const std::atomic<bool>* cancel = nullptr;         // set -> Cancelled
  // Set -> the fit stops as a cancelled one does (throws Cancelled): for a caller that no longer
  // needs the fit's result (ablation.cpp: the fit from the data with one element less). `cancel`
  // stays the user's.
  const std::atomic<bool>* abandon = nullptr;
  bool stop_requested() const { return (cancel && cancel->load()) || (abandon && abandon->load()); }
};

// One searched shape parameter.
struct ShapeParam {
  std::string name;  // e.g. "Fs/Fc", "k[2]/Fc", "Vs"
  std::string unit;  // unit of the searched value, e.g. "1/m"
  double lo = 0, hi = 1, init = 0.5;
  bool log = false;
  int scalar = -1;   // target scalar index, or
  int row = -1, column = -1;  // target element cell
};

class Parameterization {
 public:
  Parameterization(const ModelInfo& info, std::size_t elements, const EffectContext& c);
  std::size_t size() const { return params_.size(); }
  const std::vector<ShapeParam>& params() const { return params_; }
  std::vector<double> initial() const;  // in unit-box coordinates
  // Model with unit force level and no viscous term.
  ModelParams unit_model(const std::vector<double>& u) const;
  // The physical model: force-like parameters times `level`, sigma2 = viscous (if the model has it).
  ModelParams physical(const std::vector<double>& u, double level, double viscous) const;
  bool has_viscous() const { return viscous_ >= 0; }
  double value(std::size_t i, double u) const;  // searched value of parameter i at box coord u
  double box(std::size_t i, double value) const;  // inverse of value() (clamped to the box)

 private:
  const ModelInfo& info_;
  std::size_t elements_;
  ModelParams base_;  // defaults with the fixed choices applied
  std::vector<ShapeParam> params_;
  int ref_ = -1;      // reference force scalar
  int viscous_ = -1;  // sigma2 scalar
  int alpha_ = -1;    // weight column
  int stiff_ = -1;    // stiffness column (searched as kappa = k / element level)
  int level_col_ = -1;  // the element level column (alpha, or the slip force W)
};

// Break-away displacements [m] the element stiffnesses may span on this record: from
// x_hi_factor x x_ba (20: beyond the swing the record shows after most reversals; wider when
// identify finds softer elements in the data) down to 4e-4 x_ba (below any encoder step).
std::pair<double, double> element_x_range(const EffectContext& c);

struct LinearTerm {
  std::string effect;  // "base" or a catalog name
  std::string name;    // coefficient name, e.g. "Fc", "M"
  std::string unit;
  double value = 0;
};

struct FitResult {
  FitSpec spec;
  std::vector<double> u;       // shape, unit-box coordinates
  std::vector<double> theta;   // linear coefficients, in term order
  std::vector<LinearTerm> terms;
  ModelParams friction;        // the identified physical friction model
  double rms_train = 0;        // [N]
  int evaluations = 0;
  bool time_limited = false;   // stopped by FitOptions::max_seconds before converging
};

// Simulates the friction model along the record's motion (prescribed): out[k] = force at t[k].
void simulate_along(const FrictionModel& m, const Dataset& d, std::vector<double>& out);
// The record's steps (for_each_step) as a GmsPath (core/friction/gms_path.hpp), built once per
// record for the many GMS simulations of a fit.
GmsPath gms_path(const Dataset& d);
// simulate_along for a GMS model (sigma_i, sigma2 included) through GmsPathRunner: the Stribeck
// level and relaxation of every step at once, then the elements (same output to ~1e-15).
void simulate_gms_along(const GmsParams& g, const GmsPath& p, GmsPathRunner& runner,
                        std::vector<double>& out);

// Fits spec to train. `warm` (unit-box shape of a previous fit of the same model) replaces the
// data-based first start. Throws Cancelled, InputError (model unknown / element count).
FitResult fit_model(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                    const FitOptions& o, const std::vector<double>* warm = nullptr);
// Levenberg-Marquardt from f's shape (Marquardt's diagonal scaling; the Jacobian of the residual
// by forward differences of 1e-6 in the unit box; the linear terms solved at every point, so the
// search is on the shape alone): follows a narrow curved valley of the cost that a derivative-free
// search leaves short of its minimum (the Stribeck curve of a record that stays below Vs: Fc, Vs,
// delta and the viscous term trade off). At most max_iterations Jacobians; returns f when no step
// lowers the training RMS. Throws Cancelled.
FitResult polish_least_squares(const FitResult& f, const Dataset& train, const EffectContext& c,
                               int max_iterations, const FitOptions& o);
// Re-solves only the linear coefficients for spec at a fixed shape u (screening).
FitResult refit_linear(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                       const std::vector<double>& u);
// refit_linear at many shapes of one spec on one record, the record's fixed columns built once:
// rms(u) is refit_linear(spec, train, c, u).rms_train and fit(u) its result, bit for bit. train
// and c must outlive it. One object is used by one thread at a time.
class LinearRefit {
 public:
  LinearRefit(const FitSpec& spec, const Dataset& train, const EffectContext& c);
  ~LinearRefit();
  LinearRefit(const LinearRefit&) = delete;
  LinearRefit& operator=(const LinearRefit&) = delete;
  double rms(const std::vector<double>& u);
  FitResult fit(const std::vector<double>& u);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
// The shape of f with element `row` removed (the others keep their stiffness and their share of
// the friction level), as unit-box coordinates of the model with one element less; empty when f's
// model has no element weights or a single element.
std::vector<double> shape_without_element(const FitResult& f, std::size_t row, const EffectContext& c);
// The fitted force along any record (e.g. validation); same normalisations (c) as the fit.
std::vector<double> predict(const FitResult& r, const Dataset& d, const EffectContext& c);
// The friction model's unit-force-level output g along d for the fitted shape.
std::vector<double> unit_friction(const FitResult& r, const Dataset& d, const EffectContext& c);
// What the effect columns of `spec` take as g at r's shape (Column::uses_g): the unit output, then
// the extra outputs in extra_outputs order (effects.hpp): the dwell response with a dwell_stiction
// term, the unit output along the motion tau earlier with a time_shift term, the unit output
// along the contact's motion through the dead band with a backlash term. column_input picks a
// column's part.
std::vector<double> unit_outputs(const FitResult& r, const FitSpec& spec, const Dataset& d,
                                 const EffectContext& c);
// RMS of (F - predict) over d's used samples [N].
double rms_on(const FitResult& r, const Dataset& d, const EffectContext& c);

// Weighted least squares of y on the given columns over the used samples (the static inverse
// model of the EMPS benchmark is this with columns a, v, sgn v, 1). Returns the coefficients and
// the RMS residual [units of y].
struct LinearSolution {
  std::vector<double> coef;
  double rms = 0;
};
LinearSolution least_squares(const std::vector<std::vector<double>>& columns,
                             const std::vector<double>& y, const std::vector<std::uint8_t>& use);

}  // namespace gmslab::ident
