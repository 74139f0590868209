// gmslab core/control: the root locus of a loop k L(s), L = num/den (deg num <= deg den).
//
// Closed-loop characteristic equation: den(s) + k num(s) = 0.
//   180-degree locus: k from 0 to +inf (negative feedback, the usual one);
//   0-degree locus:   k from 0 to -inf (positive feedback / negative gain).
// Key points (all computed, not sampled):
//   breakaway / break-in points: roots s_b of den' num - den num' = 0 with k_b = -den/num real and
//   of the locus's sign; imaginary-axis crossings: s = j w with Im(den(jw) conj(num(jw))) = 0;
//   asymptotes (q = deg den - deg num > 0): centroid (sum poles - sum zeros) / q, angles
//   (2l + 1) pi / q (180-degree) or 2 l pi / q (0-degree);
//   equal order (q = 0): a root passes through infinity at k = -lead(den) / lead(num) when that
//   gain has the locus's sign (the root is NaN at exactly that gain).
// Gains: the key gains, a log-spaced base grid, then adaptive refinement until no branch moves
// more than max_jump x (view width) between successive gains inside the view. Branches are matched
// from one gain to the next by optimal assignment (Hungarian) on root distances.
// Units: s in rad/s; k in the units that make k L(s) dimensionless.
#pragma once

#include <optional>
#include <vector>

#include "core/control/transfer_function.hpp"

namespace gmslab::control {

struct ViewBox {
  double re_min = -1, re_max = 1, im_min = -1, im_max = 1;  // [rad/s]
  bool contains(cplx s) const {
    return s.real() >= re_min && s.real() <= re_max && s.imag() >= im_min && s.imag() <= im_max;
  }
  double width() const { return re_max - re_min; }
  double height() const { return im_max - im_min; }
};

struct LocusPoint {
  cplx s;    // point on the locus [rad/s]
  double k;  // gain there
};

struct LocusOptions {
  bool negative = false;            // true: the 0-degree locus (k <= 0)
  std::optional<ViewBox> view;      // region that must be drawn smoothly (auto if absent)
  double max_jump = 0.01;           // largest branch step inside the view, fraction of its width
  int max_samples = 6000;           // cap on gains
  std::vector<double> extra_gains;  // gains that must be sampled (e.g. a design's gain)
};

struct RootLocus {
  bool negative = false;
  std::vector<cplx> poles, zeros;  // open loop
  std::vector<double> gains;       // sampled gains, |k| increasing, sign of the locus
  std::vector<std::vector<cplx>> branches;  // [branch][sample], NaN where a root is at infinity
  double centroid = 0.0;                    // asymptote centroid [rad/s] (q > 0)
  std::vector<double> asymptote_angles;     // [rad], q of them
  std::vector<LocusPoint> breakaways;       // breakaway and break-in points
  std::vector<LocusPoint> crossings;        // imaginary-axis crossings (w >= 0)
  std::optional<double> infinite_gain;      // equal order: gain where a root passes infinity
  ViewBox view;
};

// Throws InputError when L is improper or zero.
RootLocus root_locus(const TransferFunction& L, const LocusOptions& opt = {});
// The points s = j w (w >= 0) where the locus of the given sign crosses the imaginary axis, with
// their gains (the key points root_locus() reports as `crossings`).
std::vector<LocusPoint> imaginary_axis_crossings(const TransferFunction& L, bool negative = false);
// Roots of den + k num (n of them, NaN for a root at infinity), sorted by real part.
std::vector<cplx> closed_loop_poles(const TransferFunction& L, double k);
// The gain that puts a closed-loop pole at s: k = -den(s)/num(s) (complex unless s is on a locus).
cplx gain_at(const TransferFunction& L, cplx s);
// A square-ish view centred on the real axis that contains the points, with a 30 % margin.
ViewBox view_around(const std::vector<cplx>& points);
// A view that shows poles, zeros, the key points and the centroid, with a margin.
ViewBox auto_view(const TransferFunction& L, const std::vector<cplx>& extra = {});

}  // namespace gmslab::control
