// GmsPathRunner (core/friction/gms_path.hpp) must be GmsModel along a prescribed path: the same
// total force (GmsModel::step's return) and element forces after every sample, on random paths
// (sinusoids, reversals inside sub-stepped samples, rests, constant-speed strokes) with random
// GMS parameters (1-40 elements: the scalar and the vectorised element loops; delta 2 and others),
// against the model stepped one step at a time: bit for bit (the same operations in the same
// order), also when the runner is prepared again for only a new C or for the same shape, and on
// the paths of a quantised encoder, whose repeated speeds the runner computes once each; the
// element forces alone (no total) are the same too.
#include "core/friction/gms_path.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace gmslab {
namespace {

// A random path: a sum of two sinusoids with rests and strokes; every tenth sample in 16 parts
// around a reversal-like sign change, others in 1..3 parts. quantised: the speeds are those of
// the motion's position read by an encoder of 1/300 of the amplitude (differences of its counts).
GmsPath random_path(std::mt19937& rng, std::vector<std::pair<double, double>>& steps,
                    std::vector<std::size_t>& last, bool quantised = false) {
  std::uniform_real_distribution<double> U(0, 1);
  const double amp = std::pow(10.0, -6 + 4 * U(rng));  // 1 um .. 10 mm
  const double f1 = 0.2 + 3 * U(rng), f2 = 5 + 20 * U(rng), h = std::pow(10.0, -4 + 1.5 * U(rng));
  GmsPath p;
  p.samples = 1;
  double t = 0, x = 0, xq = 0;
  const double q = amp / 300;
  for (int k = 1; k < 1500; ++k) {
    const int parts = k % 10 == 0 ? 16 : 1 + static_cast<int>(3 * U(rng));
    for (int j = 0; j < parts; ++j) {
      const double hj = h / parts;
      double v = amp * (f1 * std::cos(f1 * t) + 0.3 * f2 * std::sin(f2 * t));
      if (k % 300 < 40) v = 0.0;                          // a rest
      if (k % 300 >= 200 && k % 300 < 240) v = amp * f1;  // a stroke
      if (quantised) {
        x += v * hj;
        const double xq_next = q * std::round(x / q);
        v = (xq_next - xq) / hj;
        xq = xq_next;
      }
      steps.push_back({v, hj});
      p.add_step(v, hj);
      t += hj;
    }
    p.end_sample();
    last.push_back(steps.size());
  }
  return p;
}

TEST(GmsPath, RunnerEqualsGmsModelStepByStep) {
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> U(0, 1);
  std::size_t slipping = 0, sticking = 0, indexed_quantised = 0;
  for (int trial = 0; trial < 24; ++trial) {
    std::vector<std::pair<double, double>> steps;
    std::vector<std::size_t> last;
    const bool quantised = trial % 2 == 1;
    const GmsPath path = random_path(rng, steps, last, quantised);
    GmsParams g;
    g.S.Fc = std::pow(10.0, -1 + 3 * U(rng));
    g.S.Fs = g.S.Fc * (1 + 1.5 * U(rng));
    g.S.Vs = std::pow(10.0, -4 + 2 * U(rng));
    g.S.delta = trial % 3 == 0 ? 2.0 : trial % 3 == 1 ? 1.0 : 0.5 + 2 * U(rng);
    g.C = g.S.Fs * std::pow(10.0, 1 + 3 * U(rng));
    g.sigma2 = trial % 2 ? 0.0 : g.S.Fc * U(rng);
    const std::size_t n = trial % 4 == 0 ? 1 + trial % 7 : 9 + static_cast<std::size_t>(30 * U(rng));
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      g.alpha.push_back(0.1 + U(rng));
      sum += g.alpha.back();
      const double x_ba = std::pow(10.0, -7 + 3.5 * U(rng));
      g.k.push_back(g.S.Fc / x_ba);
      g.sigma.push_back(trial % 2 ? 0.0 : 1e-4 * g.k.back() * U(rng));
    }
    for (auto& a : g.alpha) a /= sum;
    for (std::size_t i = 0; i < n; ++i) g.k[i] *= g.alpha[i];
    const GmsModel model(g.to_params());
    GmsPathRunner runner;
    // A stale preparation first (another shape, then another C): what prepare keeps must not leak.
    // Three orders: indexed at a new shape, indexed at a new C only, and one preparation (steps
    // one by one, no index).
    Stribeck other = g.S;
    other.Vs *= 1.7;
    const int order = trial % 3;
    if (order == 0) runner.prepare(other, g.C, path), runner.prepare(g.S, 2.0 * g.C, path);
    if (order == 1) runner.prepare(g.S, 2.0 * g.C, path);
    runner.prepare(g.S, g.C, path);
    runner.prepare(g.S, g.C, path);
    if (order == 2) {
      EXPECT_EQ(runner.distinct_speeds(), 0u) << "trial " << trial;
    } else {
      // Indexed where the distinct (h, |v|) pairs are at most half the steps (a quantised
      // encoder's speeds repeat), with every distinct speed; else step by step.
      std::set<double> speeds;
      std::set<std::pair<double, double>> pairs;
      for (std::size_t j = 0; j < path.v.size(); ++j)
        speeds.insert(std::abs(path.v[j])), pairs.insert({path.h[j], std::abs(path.v[j])});
      const bool pays = 2 * pairs.size() <= path.v.size();
      EXPECT_EQ(runner.distinct_speeds(), pays ? speeds.size() : 0u) << "trial " << trial;
      if (quantised) indexed_quantised += pays;
      if (!quantised) EXPECT_FALSE(pays) << "trial " << trial;  // smooth speeds hardly repeat
    }
    std::vector<double> sk(n);
    for (std::size_t i = 0; i < n; ++i) sk[i] = g.sigma[i] / g.k[i];
    std::vector<long> rows(path.samples);
    for (std::size_t k = 0; k < rows.size(); ++k) rows[k] = static_cast<long>(k);
    std::vector<double> elems(path.samples * n, -1.0), total(path.samples);
    runner.run(path, g.alpha, g.k, sk, g.sigma2, rows, 2.0, elems.data(), total);
    // The element forces alone (no total: the vector loop without its sums) are the same.
    std::vector<double> elems_only(path.samples * n, -1.0);
    runner.run(path, g.alpha, g.k, sk, g.sigma2, rows, 2.0, elems_only.data(), {});
    for (std::size_t i = 0; i < elems.size(); ++i)
      ASSERT_EQ(elems_only[i], elems[i]) << "trial " << trial << " row entry " << i;
    std::vector<double> state(model.state_size());
    model.reset(state);
    std::size_t j = 0;
    for (std::size_t k = 1; k < path.samples; ++k) {
      double f = 0;
      for (; j < last[k - 1]; ++j) f = model.step(state, {steps[j].first, steps[j].second, 0.0, 0.0});
      ASSERT_EQ(total[k], f) << "trial " << trial << " sample " << k;
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(elems[k * n + i], 2.0 * state[i]) << "trial " << trial << " sample " << k << " element " << i;
        (state[n + i] != 0.0 ? slipping : sticking) += 1;
      }
    }
  }
  EXPECT_GT(slipping, 1000u);
  EXPECT_GT(sticking, 1000u);
  EXPECT_EQ(indexed_quantised, 8u);  // every quantised path prepared twice
}

// prepare_raised (the break-away level raised per sample, dwell stiction's model) is GmsModel
// stepped with Fs + rise[k] on the steps of sample k, bit for bit: random paths and shapes, the
// rise zero on some samples and a piecewise level of up to 3 Fs on others; a zero rise everywhere
// is the plain preparation, and a preparation after it starts afresh.
TEST(GmsPath, RaisedLevelIsTheModelWithThatBreakAwayLevelPerSample) {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> U(0, 1);
  std::size_t raised_steps = 0;
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<std::pair<double, double>> steps;
    std::vector<std::size_t> last;
    const GmsPath path = random_path(rng, steps, last, trial % 2 == 1);
    GmsParams g;
    g.S.Fc = std::pow(10.0, -1 + 3 * U(rng));
    g.S.Fs = g.S.Fc * (1 + 1.5 * U(rng));
    g.S.Vs = std::pow(10.0, -4 + 2 * U(rng));
    g.S.delta = trial % 2 == 0 ? 2.0 : 0.5 + 2 * U(rng);
    g.C = g.S.Fs * std::pow(10.0, 1 + 3 * U(rng));
    g.sigma2 = g.S.Fc * U(rng);
    const std::size_t n = trial % 3 == 0 ? 12 : 1 + static_cast<std::size_t>(7 * U(rng));
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      g.alpha.push_back(0.1 + U(rng));
      sum += g.alpha.back();
      g.k.push_back(g.S.Fc / std::pow(10.0, -7 + 3.5 * U(rng)));
      g.sigma.push_back(1e-4 * g.k.back() * U(rng));
    }
    for (auto& a : g.alpha) a /= sum;
    for (std::size_t i = 0; i < n; ++i) g.k[i] *= g.alpha[i];
    std::vector<double> rise(path.samples, 0.0);
    double level = 0.0;
    for (std::size_t k = 1; k < path.samples; ++k) {
      if (k % 97 == 0) level = U(rng) < 0.3 ? 0.0 : 3.0 * g.S.Fs * U(rng);
      rise[k] = level;
    }
    std::vector<double> sk(n);
    for (std::size_t i = 0; i < n; ++i) sk[i] = g.sigma[i] / g.k[i];
    GmsPathRunner runner;
    runner.prepare_raised(g.S, g.C, path, rise);
    std::vector<double> total(path.samples);
    runner.run(path, g.alpha, g.k, sk, g.sigma2, {}, 1.0, nullptr, total);
    std::vector<double> state(GmsModel(g.to_params()).state_size(), 0.0);
    GmsModel(g.to_params()).reset(state);
    std::size_t j = 0;
    for (std::size_t k = 1; k < path.samples; ++k) {
      GmsParams gk = g;
      gk.S.Fs += rise[k];
      const GmsModel model(gk.to_params());
      double f = 0;
      for (; j < last[k - 1]; ++j)
        f = model.step(state, {steps[j].first, steps[j].second, 0.0, 0.0});
      ASSERT_EQ(total[k], f) << "trial " << trial << " sample " << k;
      raised_steps += rise[k] > 0.0 ? last[k - 1] - (k > 1 ? last[k - 2] : 0) : 0;
    }
    // No rise: the plain preparation; a plain preparation after a raised one starts afresh.
    std::vector<double> zero(path.samples, 0.0), a(path.samples), b(path.samples);
    runner.prepare_raised(g.S, g.C, path, zero);
    runner.run(path, g.alpha, g.k, sk, g.sigma2, {}, 1.0, nullptr, a);
    GmsPathRunner plain;
    plain.prepare(g.S, g.C, path);
    plain.run(path, g.alpha, g.k, sk, g.sigma2, {}, 1.0, nullptr, b);
    runner.prepare_raised(g.S, g.C, path, rise);
    runner.prepare(g.S, g.C, path);
    std::vector<double> again(path.samples);
    runner.run(path, g.alpha, g.k, sk, g.sigma2, {}, 1.0, nullptr, again);
    for (std::size_t k = 0; k < path.samples; ++k) {
      ASSERT_EQ(a[k], b[k]) << "trial " << trial << " sample " << k;
      ASSERT_EQ(again[k], b[k]) << "trial " << trial << " sample " << k;
    }
  }
  EXPECT_GT(raised_steps, 10000u);
}

}  // namespace
}  // namespace gmslab
