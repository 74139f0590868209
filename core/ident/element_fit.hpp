// gmslab identification: the base fit of multi-element models by variable projection over a grid
// of element stiffnesses (GMS and Maxwell-slip).
//
// A GMS element with weight alpha_i and stiffness k_i carries F_i = alpha_i f(kappa_i), where f is
// a unit element (slip level S(v) / Fc, attraction C / Fc) of normalised stiffness
// kappa_i = k_i / (alpha_i Fc) = 1 / (break-away displacement at Fc) [1/m]; the same holds for a
// Maxwell-slip element with W_i in place of alpha_i Fc. So for a fixed Stribeck shape and C the
// friction force is a non-negative combination of unit-element responses:
//
//   F(t) = sum_j c_j f(kappa_j; t) + sigma2 v + effects,   c_j = Fc alpha_j >= 0
//
// Stage 1 (grid): kappa_j on a log grid spanning the break-away displacements the record can
// show (from below the encoder resolution to beyond the largest reversal swing); c and sigma2 by
// non-negative least squares (nnls_gram) inside every cost evaluation; only the shape
// (Fs/Fc, Vs, delta, C/Fc for GMS; none for Maxwell-slip) is searched (multi-start BOBYQA).
// Stage 2 (reduction): the active grid points are grouped (neighbours on the grid first, then the
// closest in log kappa) into at most the requested element count; each group becomes one element
// at the weighted geometric mean of its kappas.
// Stage 3 (free knots): shape and the N log kappa_i are refined together (BOBYQA), weights still
// by NNLS. The result is returned in the standard Parameterization of fit.hpp, with the element
// count actually found (fewer than requested when the data shows fewer).
#pragma once

#include <Eigen/Dense>
#include <chrono>
#include <string_view>
#include <vector>

#include "core/ident/fit.hpp"

namespace gmslab::ident {

// Whether the model's element weights enter linearly (the grid fit applies).
bool has_linear_elements(std::string_view model);

// Non-negative least squares on the normal equations: minimises t' G t - 2 b' t subject to
// t_j >= 0 where nonneg[j] (others free). Lawson-Hanson active set; G symmetric positive
// semi-definite (a tiny ridge is added for rank deficiency). Returns t.
Eigen::VectorXd nnls_gram(const Eigen::MatrixXd& G, const Eigen::VectorXd& b,
                          const std::vector<bool>& nonneg);

// One element found by the grid fit (per unit Fc: kappa [1/m], weight c [N]).
struct GridElement {
  double kappa = 0;  // normalised stiffness [1/m] = 1 / break-away displacement at Fc
  double weight = 0; // c = Fc alpha [N] (GMS) or W [N] (Maxwell-slip)
};

// The shared grid stage (stage 1), reusable for several element counts (--elements auto).
struct GridSolution {
  std::string model;
  std::vector<double> shape;           // unit-box coordinates of the scalar shape parameters
  std::vector<double> kappa;           // the grid [1/m]
  std::vector<double> weight;          // NNLS weights on the grid [N]
  std::vector<GridElement> active;     // grouped by grid neighbours, heaviest first
  double rms = 0;                      // training RMS at the grid solution [N]
  int evaluations = 0;
  int budget = 0;                      // evaluation budget of the whole fit (progress)
  std::chrono::steady_clock::time_point started;  // FitOptions::max_seconds counts from here
};

// Grid starts: min(o.starts, 3) BOBYQA runs from the best design points; shape_hint (unit-box
// scalar shape, e.g. of the previous stage) joins the design.
GridSolution fit_grid(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                      const FitOptions& o, const std::vector<double>* shape_hint = nullptr);
// Stages 2 and 3 for `elements` elements; a FitResult in the standard parameterization.
FitResult reduce_and_polish(const GridSolution& g, const FitSpec& spec, const Dataset& train,
                            const EffectContext& c, const FitOptions& o);
// Stage 3 alone from a fit of the same spec (unit-box shape `warm`, standard parameterization):
// the refit after an effect was added. Budget 2 max_evaluations + 1.
FitResult polish_elements(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                          const FitOptions& o, const std::vector<double>& warm);
// Stages 1-3 again with the warm start's shape among the design points: after an effect was
// added the shape and element table can leave what they had bent into to mimic it.
FitResult regrid_elements(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                          const FitOptions& o, const std::vector<double>& warm);
// The evaluation budget of fit_elements (what FitProgress::budget reports).
int element_fit_budget(const FitSpec& spec, const EffectContext& c, const FitOptions& o);
// fit_grid + reduce_and_polish.
// The grid stage's cost [N RMS] at the shape of `warm` (a FitResult::u of spec's
// parameterization): the unit elements of c's whole grid, weights by NNLS. Comparing it under two
// contexts tells whether a wider element range would explain more.
double grid_cost_at(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                    const std::vector<double>& warm);

// The shape of f with one element more, as unit-box coordinates of the model with
// f.spec.elements + 1 elements (the warm start of "one more element in place of an effect",
// ablation.hpp): f's scalar shape, its elements, and one more where it lowers the training cost
// most at f's shape (weights by NNLS, with spec's effects): an element split in two (1.6x or 3x
// either side in stiffness), one between two neighbours, or one beyond either end (4x). Empty
// for a model without linear element weights.
std::vector<double> shape_with_element(const FitResult& f, const FitSpec& spec,
                                       const Dataset& train, const EffectContext& c);

FitResult fit_elements(const FitSpec& spec, const Dataset& train, const EffectContext& c,
                       const FitOptions& o);

// --elements auto: the grid stage once, then stages 2-3 for 1..max_elements elements (at most
// the groups the grid found); the smallest count whose validation RMS is within 2 % of the best.
FitResult fit_elements_auto(const FitSpec& spec, const Dataset& train, const Dataset& validation,
                            const EffectContext& c, const FitOptions& o,
                            std::size_t max_elements = 8);

// The range of break-away displacements [m] the grid covers for this record.
std::pair<double, double> grid_range(const EffectContext& c);

}  // namespace gmslab::ident
