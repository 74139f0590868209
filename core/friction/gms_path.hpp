// gmslab core: GMS driven along a prescribed motion, many times over (identification).
//
// Along a prescribed path of steps (v_j, h_j) - the motion does not depend on the force - the
// Stribeck level S_j = S(v_j) and a slipping element's relaxation E_j = exp(-C h_j / S_j) depend
// on the shape (Fs, Fc, Vs, delta, C) and the path only, not on the elements. GmsPathRunner
// computes them for all steps at once, in vectorisable loops (|v|^delta as exp(delta ln|v|) with
// ln|v| taken once per path; a polynomial exp), and then runs the element recursion with no
// transcendental function in it. The element arithmetic is that of GmsModel::step (same stick,
// break-away and slip updates); S and E agree with GmsModel's to a few ulp (exp_neg_n), so the
// element forces agree to ~1e-15 relative (tests/core/gms_path_test.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/friction/gms.hpp"

namespace gmslab {

// exp(-x[i]) for x[i] >= 0 (NaN propagates): within 2 ulp of std::exp(-x) for x <= 708, 0 beyond
// (std::exp gives at most 3e-308 there). Vectorised (AVX2 clone chosen at load time).
void exp_neg_n(std::span<const double> x, std::span<double> out);

// A prescribed path: the steps of sample k (k >= 1) are [first[k - 1], first[k]) (sample 0 has
// none: it is the initial state). Shape-independent, built once per record.
struct GmsPath {
  std::vector<double> v, h;        // per step [m/s], [s]
  std::vector<double> log_abs_v;   // ln|v| per step (-inf at v = 0)
  std::vector<std::uint32_t> last; // per sample k >= 1: one past its last step (size samples - 1)
  std::size_t samples = 0;

  // Appends the steps of the next sample (call once per sample k = 1, 2, ...).
  void add_step(double vj, double hj);
  void end_sample();
};

class GmsPathRunner {
 public:
  // S_j and E_j for every step of `path` (the shape S, attraction C [N/s]).
  void prepare(const Stribeck& S, double C, const GmsPath& path);

  // Runs elements (alpha_i, k_i [N/m], sigma_i / k_i [s]) from rest along the prepared path.
  // After each sample k >= 1: when rows[k] >= 0, the element forces times `scale` go to
  // element_rows[rows[k] * n .. + n) (row-major, n = alpha.size()); when total is non-empty,
  // total[k] = sum F_i + sum (sigma_i / k_i) dF_i / h + sigma2 v of the sample's last step (the
  // value GmsModel::step returns); total[0] = 0.
  void run(const GmsPath& path, std::span<const double> alpha, std::span<const double> k,
           std::span<const double> sigma_over_k, double sigma2, std::span<const long> rows,
           double scale, double* element_rows, std::span<double> total) const;

 private:
  std::vector<double> S_, E_, tmp_;
};

}  // namespace gmslab
