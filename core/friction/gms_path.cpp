#include "core/friction/gms_path.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/friction/gms_elements.hpp"
#include "core/simd_path.hpp"

namespace gmslab {

void GmsPath::add_step(double vj, double hj) {
  v.push_back(vj);
  h.push_back(hj);
}

void GmsPath::end_sample() {
  if (samples == 0) samples = 1;  // sample 0: the initial state
  last.push_back(static_cast<std::uint32_t>(v.size()));
  ++samples;
}

namespace {

// Open-addressing map from a 64-bit key to a dense index (keys numbered in order of appearance).
class DenseIndex {
 public:
  explicit DenseIndex(std::size_t n) {
    std::size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    slots_.assign(cap, kEmpty);
    keys_.reserve(n);
  }
  // The index of key, new ones numbered from keys().size().
  std::uint32_t operator()(std::uint64_t key) {
    const std::size_t mask = slots_.size() - 1;
    std::size_t i =
        static_cast<std::size_t>((key ^ (key >> 29)) * 0x9E3779B97F4A7C15ull >> 7) & mask;
    for (;; i = (i + 1) & mask) {
      if (slots_[i] == kEmpty) {
        slots_[i] = static_cast<std::uint32_t>(keys_.size());
        keys_.push_back(key);
        return slots_[i];
      }
      if (keys_[slots_[i]] == key) return slots_[i];
    }
  }
  std::size_t size() const { return keys_.size(); }

 private:
  static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
  std::vector<std::uint32_t> slots_;
  std::vector<std::uint64_t> keys_;
};

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

}  // namespace

void GmsPathRunner::build_index(const GmsPath& path) {
  const std::size_t m = path.v.size();
  DenseIndex speeds(m), pairs(m);
  speed_.clear(), pair_h_.clear(), pair_speed_.clear();
  step_speed_.resize(m), step_pair_.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    const double a = std::abs(path.v[j]);
    const std::uint32_t is = speeds(bits(a));
    if (is == speed_.size()) speed_.push_back(a);
    // h and the speed's index in one key: an index below 2^32 and h's bits mixed in.
    const std::uint64_t key = bits(path.h[j]) * 0xD6E8FEB86659FD93ull ^ is;
    const std::uint32_t ip = pairs(key);
    if (ip == pair_h_.size()) pair_h_.push_back(path.h[j]), pair_speed_.push_back(is);
    // A collision of two pairs in one key would share E: the pair is checked.
    if (pair_h_[ip] != path.h[j] || pair_speed_[ip] != is) {
      step_speed_.clear(), step_pair_.clear();
      index_ = Index::failed;  // two pairs in one key: step by step
      return;
    }
    step_speed_[j] = is, step_pair_[j] = ip;
  }
  // Mostly distinct speeds (a filtered velocity, a smooth path): the copies would cost more than
  // the few values computed once save.
  if (2 * pair_h_.size() > m) {
    step_speed_.clear(), step_pair_.clear();
    index_ = Index::failed;
    return;
  }
  speed_S_.resize(speed_.size());
  pair_E_.resize(pair_h_.size());
  index_ = Index::built;
}

void GmsPathRunner::prepare(const Stribeck& S, double C, const GmsPath& path) {
  const std::size_t m = path.v.size();
  // The same shape along the same path (a search moving only the elements): nothing to redo.
  const bool same_path = &path == path_ && m == steps_;
  const bool same_S = same_path && S.Fs == shape_.Fs && S.Fc == shape_.Fc && S.Vs == shape_.Vs &&
                      S.delta == shape_.delta;
  if (same_S && C == C_) return;
  bool fresh_index = false;
  if (!same_path) {
    index_ = Index::none;
  } else if (index_ == Index::none) {
    build_index(path);
    fresh_index = index_ == Index::built;
  }
  path_ = &path, steps_ = m, shape_ = S, C_ = C;
  S_.resize(m);
  E_.resize(m);
  // As GmsModel::step: beyond r_sat S is Fc exactly in doubles (no pow, no exp there).
  const double inv_vs = 1.0 / S.Vs;
  const double r_sat = gms_elements::saturation_ratio(S);
  auto level = [&](double speed) {
    const double r = speed * inv_vs;
    return r > r_sat ? S.Fc : S.at_scaled(r);
  };
  if (index_ == Index::built) {
    if (!same_S || fresh_index) {
      for (std::size_t i = 0; i < speed_.size(); ++i) speed_S_[i] = level(speed_[i]);
      for (std::size_t j = 0; j < m; ++j) S_[j] = speed_S_[step_speed_[j]];
    }
    for (std::size_t i = 0; i < pair_h_.size(); ++i)
      pair_E_[i] = exp_neg(C * pair_h_[i] / speed_S_[pair_speed_[i]]);
    for (std::size_t j = 0; j < m; ++j) E_[j] = pair_E_[step_pair_[j]];
    return;
  }
  if (!same_S)
    for (std::size_t j = 0; j < m; ++j) S_[j] = level(std::abs(path.v[j]));
  // Relaxation exp(-C h / S): consecutive steps of the same h and S (sliding beyond the Stribeck
  // region at a fixed sample step) share it.
  double last_x = -1.0, last_e = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    const double x = C * path.h[j] / S_[j];
    if (x != last_x) last_x = x, last_e = exp_neg(x);
    E_[j] = last_e;
  }
}

void GmsPathRunner::prepare_raised(const Stribeck& S, double C, const GmsPath& path,
                                   std::span<const double> fs_rise) {
  std::vector<double> step_rise(path.v.size(), 0.0);
  std::size_t j = 0;
  for (std::size_t kk = 1; kk < path.samples; ++kk)
    for (const std::size_t end = path.last[kk - 1]; j < end; ++j)
      step_rise[j] = kk < fs_rise.size() ? fs_rise[kk] : 0.0;
  prepare_raised_steps(S, C, path, step_rise);
}

void GmsPathRunner::prepare_raised_steps(const Stribeck& S, double C, const GmsPath& path,
                                         std::span<const double> step_rise) {
  const std::size_t m = path.v.size();
  path_ = nullptr, index_ = Index::none, steps_ = m, shape_ = S, C_ = C;
  S_.resize(m);
  E_.resize(m);
  const double inv_vs = 1.0 / S.Vs;
  const double r_sat0 = gms_elements::saturation_ratio(S);
  for (std::size_t j = 0; j < m; ++j) {
    Stribeck Sj = S;
    const double rise = j < step_rise.size() ? step_rise[j] : 0.0;
    Sj.Fs += rise;
    const double r_sat = rise != 0.0 ? gms_elements::saturation_ratio(Sj) : r_sat0;
    const double r = std::abs(path.v[j]) * inv_vs;
    S_[j] = r > r_sat ? Sj.Fc : Sj.at_scaled(r);
    E_[j] = exp_neg(C * path.h[j] / S_[j]);
  }
}

void GmsPathRunner::run(const GmsPath& path, std::span<const double> alpha,
                        std::span<const double> k, std::span<const double> sigma_over_k,
                        double sigma2, std::span<const long> rows, double scale,
                        double* element_rows, std::span<double> total) const {
  const std::size_t n = alpha.size();
  std::vector<double> F(n, 0.0), d(n, 0.0);
  const bool vec = n > GmsModel::kScalarElements || simd_path().vector_elements;
  if (vec && total.empty()) {  // the element forces alone: no sums
    const gms_elements::PathSteps p{S_.data(),     E_.data(),        path.v.data(),
                                    path.h.data(), path.last.data(), path.samples};
    gms_elements::vector_rows(n, F.data(), d.data(), alpha.data(), k.data(), p, rows.data(),
                              element_rows ? rows.size() : 0, scale, element_rows);
    return;
  }
  if (!total.empty()) total[0] = 0.0;
  std::size_t j = 0;
  for (std::size_t kk = 1; kk < path.samples; ++kk) {
    const std::size_t end = path.last[kk - 1];
    gms_elements::Sums sums{0.0, 0.0};
    double v = 0.0, h = 1.0;
    for (; j < end; ++j) {
      v = path.v[j];
      h = path.h[j];
      const double s = sgn(v);
      const double E = E_[j];
      sums = vec ? gms_elements::vector(n, F.data(), d.data(), alpha.data(), k.data(), sigma_over_k.data(), s,
                                        S_[j], E, v * h)
                 : gms_elements::scalar(n, F.data(), d.data(), alpha.data(), k.data(), sigma_over_k.data(), s,
                                        S_[j], [E] { return E; }, v * h);
    }
    if (!total.empty()) total[kk] = sums.force + sums.damping * (1.0 / h) + sigma2 * v;
    if (element_rows && kk < rows.size() && rows[kk] >= 0) {
      double* out = element_rows + static_cast<std::size_t>(rows[kk]) * n;
      for (std::size_t i = 0; i < n; ++i) out[i] = scale * F[i];
    }
  }
}

}  // namespace gmslab
