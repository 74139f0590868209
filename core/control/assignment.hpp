// gmslab core/control: optimal assignment (the Hungarian method, shortest augmenting paths,
// O(n^3)). Used to match the roots of one gain to the next so that locus branches do not swap.
#pragma once

#include <vector>

namespace gmslab::control {

// cost: n x n row-major (cost[i * n + j] = cost of giving row i column j); NaN and +inf count as
// 1e300, -inf as -1e300.
// Returns col[i] = the column assigned to row i, minimising the total cost (a permutation).
std::vector<int> solve_assignment(const std::vector<double>& cost, int n);

}  // namespace gmslab::control
