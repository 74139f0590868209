#include "ui/plot/decimate.hpp"

#include <algorithm>
#include <cmath>

namespace gmslab::ui {

namespace {
// Appends the (up to four) kept samples of one column in index order, without duplicates.
void flush_column(std::size_t first, std::size_t last, std::size_t lo, std::size_t hi,
                  std::vector<std::size_t>& out) {
  std::size_t k[4] = {first, lo, hi, last};
  std::sort(k, k + 4);
  for (const std::size_t i : k)
    if (out.empty() || out.back() != i) out.push_back(i);
}
}  // namespace

long decimate_column(double x, double x0, double x1, int columns) {
  const long c = static_cast<long>((x - x0) * (static_cast<double>(columns) / (x1 - x0)));
  return std::clamp<long>(c, 0, columns - 1);
}

namespace {
// Index of the first smallest and of the first largest y in [i, j) (j > i). The value pass is a
// plain reduction the compiler vectorises; the index pass stops at the first match.
void extremes(const double* y, std::size_t i, std::size_t j, std::size_t& lo, std::size_t& hi) {
  // Four independent accumulators: no loop-carried dependency on one register, and the
  // compiler maps them onto SIMD min/max without -ffast-math.
  double mn[4] = {y[i], y[i], y[i], y[i]}, mx[4] = {y[i], y[i], y[i], y[i]};
  std::size_t k = i + 1;
  for (; k + 4 <= j; k += 4)
    for (int u = 0; u < 4; ++u) {
      mn[u] = y[k + u] < mn[u] ? y[k + u] : mn[u];
      mx[u] = y[k + u] > mx[u] ? y[k + u] : mx[u];
    }
  for (; k < j; ++k) {
    mn[0] = y[k] < mn[0] ? y[k] : mn[0];
    mx[0] = y[k] > mx[0] ? y[k] : mx[0];
  }
  const double lo_v = std::min({mn[0], mn[1], mn[2], mn[3]}), hi_v = std::max({mx[0], mx[1], mx[2], mx[3]});
  lo = hi = i;
  while (lo < j && !(y[lo] == lo_v)) ++lo;
  while (hi < j && !(y[hi] == hi_v)) ++hi;
  if (lo == j) lo = i;  // NaN samples: keep the first
  if (hi == j) hi = i;
}
}  // namespace

void value_range(const double* v, std::size_t n, double& lo, double& hi) {
  // NaN fails both comparisons and is skipped; four accumulators as in extremes().
  double mn[4] = {INFINITY, INFINITY, INFINITY, INFINITY}, mx[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4)
    for (int u = 0; u < 4; ++u) {
      mn[u] = v[k + u] < mn[u] ? v[k + u] : mn[u];
      mx[u] = v[k + u] > mx[u] ? v[k + u] : mx[u];
    }
  for (; k < n; ++k) {
    mn[0] = v[k] < mn[0] ? v[k] : mn[0];
    mx[0] = v[k] > mx[0] ? v[k] : mx[0];
  }
  lo = std::min({mn[0], mn[1], mn[2], mn[3]});
  hi = std::max({mx[0], mx[1], mx[2], mx[3]});
}

void decimate_minmax(const double* x, const double* y, std::size_t n, double x0, double x1,
                     int columns, std::vector<std::size_t>& out) {
  out.clear();
  if (n == 0 || columns <= 0 || !(x1 > x0)) return;
  const std::size_t begin = static_cast<std::size_t>(std::lower_bound(x, x + n, x0) - x);
  const std::size_t end = static_cast<std::size_t>(std::upper_bound(x, x + n, x1) - x);
  if (begin > 0) out.push_back(begin - 1);
  // Walk column by column: the end of each column is found by binary search (x is sorted), so
  // the per-sample work is only the min/max reduction.
  for (std::size_t i = begin; i < end;) {
    const long c = decimate_column(x[i], x0, x1, columns);
    const std::size_t j = static_cast<std::size_t>(
        std::partition_point(x + i, x + end, [&](double v) { return decimate_column(v, x0, x1, columns) <= c; }) - x);
    std::size_t lo = i, hi = i;
    extremes(y, i, j, lo, hi);
    flush_column(i, j - 1, lo, hi, out);
    i = j;
  }
  if (end < n) out.push_back(end);
}

void decimate_path(const double* x, const double* y, std::size_t n, const PlotTransform& t,
                   double min_px, std::vector<std::size_t>& out) {
  out.clear();
  if (n == 0) return;
  out.push_back(0);
  double lx = t.to_px_x(x[0]), ly = t.to_px_y(y[0]);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double px = t.to_px_x(x[i]), py = t.to_px_y(y[i]);
    if (std::fabs(px - lx) >= min_px || std::fabs(py - ly) >= min_px) {
      out.push_back(i);
      lx = px;
      ly = py;
    }
  }
  if (n > 1) out.push_back(n - 1);
}

}  // namespace gmslab::ui
