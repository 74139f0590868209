// gmslab ui: decimation of long traces for drawing (pure; no ImGui).
//
// A plot column is one pixel wide, so drawing more than a few samples per column only costs time.
// decimate_minmax keeps, for every pixel column, the first, the last, the smallest-y and the
// largest-y sample (in index order, duplicates removed): the drawn envelope is exactly that of
// the full trace, and a 10^6-sample trace becomes at most 4 * columns + 2 points.
// decimate_path serves traces whose x is not monotonic (hysteresis loops): it keeps a sample
// when it is at least `min_px` pixels away from the last kept one.
#pragma once

#include <cstddef>
#include <vector>

#include "ui/plot/plot_transform.hpp"

namespace gmslab::ui {

// The pixel column of x: floor((x - x0) * columns / (x1 - x0)) clamped to [0, columns - 1].
long decimate_column(double x, double x0, double x1, int columns);

// Smallest and largest non-NaN value of v[0..n) (lo = +inf, hi = -inf when there is none).
void value_range(const double* v, std::size_t n, double& lo, double& hi);

// x must be non-decreasing. Column c (decimate_column) covers [x0 + c w, x0 + (c + 1) w), w = (x1 - x0) / columns.
// Samples outside [x0, x1] are dropped, except the last one before x0 and the first one after
// x1 (so the line reaches the plot edges). Writes sample indices, increasing, into `out`.
void decimate_minmax(const double* x, const double* y, std::size_t n, double x0, double x1,
                     int columns, std::vector<std::size_t>& out);

// Any x. Keeps the first and last sample and every sample at least min_px pixels (in x or y,
// through `t`) from the previously kept one. Writes increasing sample indices into `out`.
void decimate_path(const double* x, const double* y, std::size_t n, const PlotTransform& t,
                   double min_px, std::vector<std::size_t>& out);

}  // namespace gmslab::ui
