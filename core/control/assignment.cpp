#include "core/control/assignment.hpp"

#include <cmath>
#include <limits>

namespace gmslab::control {

// Kuhn-Munkres with potentials (u, v) and shortest augmenting paths; 1-based internally.
std::vector<int> solve_assignment(const std::vector<double>& cost_in, int n) {
  const double inf = std::numeric_limits<double>::infinity();
  // Non-finite costs (NaN, +-inf) become +-1e300 so every augmenting path search terminates.
  std::vector<double> cost(cost_in);
  for (double& c : cost)
    if (!std::isfinite(c)) c = (c < 0.0) ? -1e300 : 1e300;
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);  // p[j]: row matched to column j
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<char> used(n + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = cost[(i0 - 1) * n + (j - 1)] - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j]) u[p[j]] += delta, v[j] -= delta;
        else minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col(n, 0);
  for (int j = 1; j <= n; ++j)
    if (p[j] > 0) col[p[j] - 1] = j - 1;
  return col;
}

}  // namespace gmslab::control
