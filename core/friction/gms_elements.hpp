// gmslab core: the per-element update of one GMS step, shared by GmsModel::step (gms.cpp) and the
// path runner (gms_path.cpp), so that both give the same element forces bit for bit.
//
// Per element i with limit alpha_i S: it keeps slipping (slipping in the direction of v), slips
// when over the limit already at the start (S dropped while stuck and loaded along v), and
// otherwise sticks, a crossing inside the step ending it exactly at the target.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "core/friction/stribeck.hpp"

namespace gmslab::gms_elements {

struct Sums {
  double force;    // sum of F_i after the step [N]
  double damping;  // sum of (sigma_i / k_i) (F_i(t + h) - F_i(t)) [N s]
};

// Few elements: a scalar loop with branches. The step is then bound by the latency of one step
// (v -> force -> v), and a predicted branch cuts that chain where a select would not: while every
// element sticks, the force follows from F_i + k_i v h alone. relax() gives a slipping element's
// relaxation exp(-C h / S); it is asked for once, at the first slipping element.
template <class Relax>
[[gnu::always_inline]] inline Sums scalar(std::size_t n, double* __restrict F, double* __restrict d,
                                          const double* __restrict alpha,
                                          const double* __restrict k, const double* __restrict sk,
                                          double s, double S, Relax&& relax, double vh) {
  double E = -1.0;
  // Element i's new force; adds its damping term sigma_i / k_i (F_i(t + h) - F_i(t)) to `damp`.
  auto update = [&](std::size_t i, double& damp, bool first) __attribute__((always_inline)) {
    const double f0 = F[i];
    const double lim = alpha[i] * S;
    double f1;
    if (d[i] * s > 0.0 || s * f0 >= lim) {  // keeps slipping, or over the limit already
      if (E < 0.0) E = relax();
      const double target = s * lim;
      f1 = target + (f0 - target) * E;
      d[i] = s;
    } else {
      const double f_stick = f0 + k[i] * vh;
      if (s * f_stick >= lim) {  // breaks away inside the step: ends it at the target
        f1 = s * lim;
        d[i] = s;
      } else {
        f1 = f_stick;
        d[i] = 0.0;
      }
    }
    damp = first ? sk[i] * (f1 - f0) : damp + sk[i] * (f1 - f0);
    F[i] = f1;
    return f1;
  };
  if (n == 0) return {0.0, 0.0};
  // The sums start at the first element's terms (not at 0 + them: one add less on the step's
  // latency chain; the same values, a zero sum aside, whose sign no comparison sees).
  double sum_damp = 0.0;
  double sum_f = update(0, sum_damp, true);
  for (std::size_t i = 1; i < n; ++i) sum_f += update(i, sum_damp, false);
  return {sum_f, sum_damp};
}

// Many elements: branch-free (selects only), so the loop vectorises; compiled for AVX2 and for the
// baseline, chosen per call (gms.cpp, core/simd_path.hpp). E = exp(-C h / S). No fused multiply-add
// (-std=c++20 implies -ffp-contract=off); the reduction order depends on the vector width, so
// traces are reproducible per machine kind.
Sums vector(std::size_t n, double* __restrict F, double* __restrict d, const double* __restrict alpha,
            const double* __restrict k, const double* __restrict sk, double s, double S, double E, double vh);

// The element forces and slip directions alone (no sums) along steps [j0, j1) of a prepared path
// (S_j, E_j, v_j, h_j): the vector loop's element updates, the same operations, so the same F and
// d; after each sample k in (k0, k1] whose last step is last[k - 1] and rows[k] >= 0, the forces
// times `scale` go to element_rows[rows[k] * n ..). One call for the whole path: the loop is
// compiled with the step loop around it (AVX2 or the baseline, as vector()).
struct PathSteps {
  const double *S, *E, *v, *h;
  const std::uint32_t* last;  // per sample k >= 1: one past its last step
  std::size_t samples;
};
void vector_rows(std::size_t n, double* __restrict F, double* __restrict d,
                 const double* __restrict alpha, const double* __restrict k, const PathSteps& p,
                 const long* rows, std::size_t n_rows, double scale, double* element_rows);

// |v| / Vs beyond which (Fs - Fc) exp(-r^delta) < Fc 2^-54 <= half an ulp of Fc, so that S(v) is Fc
// exactly in doubles: pow and exp can be skipped there (sliding is the common case).
inline double saturation_ratio(const Stribeck& S) {
  const double gap = S.Fs - S.Fc;
  const double r = gap > 0.0 ? std::pow(std::log(gap / S.Fc) + 54.0 * std::log(2.0), 1.0 / S.delta) : 0.0;
  if (!(r > 0.0)) return gap > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  return r;
}

}  // namespace gmslab::gms_elements
