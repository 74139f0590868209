// gmslab core: GMS driven along a prescribed motion, many times over (identification).
//
// Along a prescribed path of steps (v_j, h_j) - the motion does not depend on the force - the
// Stribeck level S_j = S(v_j) and a slipping element's relaxation E_j = exp(-C h_j / S_j) depend
// on the shape (Fs, Fc, Vs, delta, C) and the path only, not on the elements. GmsPathRunner
// computes them once per shape for all steps (and keeps them while only the elements change),
// then runs the element recursion with no transcendental function in it and no virtual call per
// step. Every operation is GmsModel::step's, in its order: the results are bit-identical to
// stepping a GmsModel (tests/core/gms_path_test.cpp), so a fit takes the same path as before.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/friction/gms.hpp"

namespace gmslab {

// A prescribed path: the steps of sample k >= 1 are [last[k - 2], last[k - 1]) (from 0 for k = 1;
// sample 0 has none: it is the initial state). Shape-independent, built once per record.
struct GmsPath {
  std::vector<double> v, h;        // per step [m/s], [s]
  std::vector<std::uint32_t> last; // per sample k >= 1: one past its last step (size samples - 1)
  std::size_t samples = 0;

  // Appends the steps of the next sample (call once per sample k = 1, 2, ...).
  void add_step(double vj, double hj);
  void end_sample();
};

class GmsPathRunner {
 public:
  // S_j and E_j for every step of `path` (the shape S, attraction C [N/s]). Kept from the last
  // call when the path (same object, same steps) and the shape are the same: S_j also when only
  // C changed. A path changed in place must be prepared by a fresh runner.
  // A path prepared a second time is indexed by its distinct speeds |v_j| and distinct pairs
  // (h_j, |v_j|): where there are fewer pairs than half the steps (a quantised encoder's
  // velocities repeat: a third of the steps on gmslab's fig2c trace), S and E are then computed
  // once per distinct value and copied to the steps, with the same operands and so the same
  // values; otherwise step by step.
  void prepare(const Stribeck& S, double C, const GmsPath& path);
  // As prepare, with Fs raised by fs_rise[k] [N] on the steps of sample k (a break-away level
  // that changes along the path: dwell stiction), every step computed; what it prepares is not
  // kept for a later prepare.
  void prepare_raised(const Stribeck& S, double C, const GmsPath& path,
                      std::span<const double> fs_rise);
  // As prepare_raised, with Fs raised by step_rise[j] [N] on step j of the path (one value per
  // step: a level that changes within a sample's steps).
  void prepare_raised_steps(const Stribeck& S, double C, const GmsPath& path,
                            std::span<const double> step_rise);

  // Runs elements (alpha_i, k_i [N/m], sigma_i / k_i [s]) from rest along the prepared path.
  // After each sample k >= 1: when rows[k] >= 0, the element forces times `scale` go to
  // element_rows[rows[k] * n .. + n) (row-major, n = alpha.size()); when total is non-empty,
  // total[k] = sum F_i + sum (sigma_i / k_i) dF_i / h + sigma2 v of the sample's last step (the
  // value GmsModel::step returns); total[0] = 0.
  // The distinct speeds the index holds (0: not indexed).
  std::size_t distinct_speeds() const { return index_ == Index::built ? speed_.size() : 0; }

  void run(const GmsPath& path, std::span<const double> alpha, std::span<const double> k,
           std::span<const double> sigma_over_k, double sigma2, std::span<const long> rows,
           double scale, double* element_rows, std::span<double> total) const;

 private:
  void build_index(const GmsPath& path);

  std::vector<double> S_, E_;
  // The index of path_ (built at its second prepare): distinct speeds and their S, distinct
  // (h, speed) pairs and their E, and each step's entries.
  std::vector<double> speed_, speed_S_, pair_h_, pair_E_;
  std::vector<std::uint32_t> pair_speed_, step_speed_, step_pair_;
  enum class Index { none, built, failed } index_ = Index::none;
  const GmsPath* path_ = nullptr;  // what S_ and E_ were computed for
  std::size_t steps_ = 0;
  Stribeck shape_;
  double C_ = 0.0;
};

}  // namespace gmslab
