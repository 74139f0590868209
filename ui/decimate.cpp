#include "ui/decimate.hpp"

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

void decimate_minmax(const double* x, const double* y, std::size_t n, double x0, double x1,
                     int columns, std::vector<std::size_t>& out) {
  out.clear();
  if (n == 0 || columns <= 0 || !(x1 > x0)) return;
  const std::size_t begin = static_cast<std::size_t>(std::lower_bound(x, x + n, x0) - x);
  const std::size_t end = static_cast<std::size_t>(std::upper_bound(x, x + n, x1) - x);
  if (begin > 0) out.push_back(begin - 1);
  const double scale = columns / (x1 - x0);
  long col = -1;
  std::size_t first = 0, last = 0, lo = 0, hi = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const long c = std::min<long>(columns - 1, static_cast<long>((x[i] - x0) * scale));
    if (c != col) {
      if (col >= 0) flush_column(first, last, lo, hi, out);
      col = c;
      first = last = lo = hi = i;
      continue;
    }
    last = i;
    if (y[i] < y[lo]) lo = i;
    if (y[i] > y[hi]) hi = i;
  }
  if (col >= 0) flush_column(first, last, lo, hi, out);
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
