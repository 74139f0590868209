// GMS stick-slip (seed Figs. 3/4): a 1 kg mass pulled through a 2 N/m spring at 0.1 m/s.
// Reference numbers from docs/references.md; the vibration frequency from sqrt(sum k_i / m).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>

#include "core/friction/gms.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

struct Phases {
  std::vector<std::size_t> slip_start;  // sample index where the mass breaks away
  std::vector<std::size_t> stick_start;  // sample index where it comes to rest
};

// Slip starts when v exceeds 1 mm/s (the pulling point moves at 100 mm/s; in stick |v| stays
// below ~1e-4 m/s); the stick starts when the sliding mass first comes to rest (v reaches 0).
Phases find_phases(const Trace& tr) {
  Phases p;
  bool moving = false;
  for (std::size_t k = 1; k < tr.size(); ++k) {
    if (!moving && tr.v[k] > 1e-3) {
      p.slip_start.push_back(k);
      moving = true;
    } else if (moving && tr.v[k] <= 0.0) {
      p.stick_start.push_back(k);
      moving = false;
    }
  }
  return p;
}

class GmsStickSlip : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scenario_ = new Scenario(load_scenario(test_util::preset_path("fig4_stick_slip.json")));
    trace_ = new Trace(simulate(*scenario_));
  }
  static void TearDownTestSuite() {
    delete trace_;
    delete scenario_;
  }
  static Scenario* scenario_;
  static Trace* trace_;
};
Scenario* GmsStickSlip::scenario_ = nullptr;
Trace* GmsStickSlip::trace_ = nullptr;

TEST_F(GmsStickSlip, SlipStartsAtReferenceTimesWithPeriod653) {
  const auto p = find_phases(*trace_);
  ASSERT_EQ(p.slip_start.size(), 3u);
  const double ref[] = {7.55, 14.08, 20.61};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(trace_->t[p.slip_start[i]], ref[i], 0.01);
  const double period = (trace_->t[p.slip_start[2]] - trace_->t[p.slip_start[0]]) / 2;
  EXPECT_NEAR(period, 6.53, 0.01);
}

TEST_F(GmsStickSlip, SlipOnsetAtStaticForceFs) {
  // Break-away happens when the spring force reaches Fs (the stuck elements' sum alpha_i S(0)).
  const auto p = find_phases(*trace_);
  const double Fs = scenario_->friction.scalar("Fs");
  for (std::size_t k : p.slip_start) {
    // The spring force peaks just before slip; search the 50 ms before the onset.
    double peak = 0.0;
    for (std::size_t j = k - std::min<std::size_t>(k, 500); j <= k; ++j)
      peak = std::max(peak, trace_->applied[j]);
    EXPECT_NEAR(peak, Fs, 0.01 * Fs);
  }
}

TEST_F(GmsStickSlip, SlidingForceAndSpikeBeforeEachStick) {
  const auto p = find_phases(*trace_);
  ASSERT_EQ(p.stick_start.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t k = p.stick_start[i];
    // Mid-slip: the non-viscous sliding force is 1.00-1.03 N (Coulomb level, Stribeck tail).
    const double sigma2 = scenario_->friction.scalar("sigma2");
    const std::size_t mid = (p.slip_start[i] + k) / 2;
    const double sliding = trace_->friction[mid] - sigma2 * trace_->v[mid];
    EXPECT_GE(sliding, 1.00 - 1e-3);
    EXPECT_LE(sliding, 1.03);
    // Spike to about 1.19 N in the last ms (10 samples of 0.1 ms) before the stick (Stribeck rise as v -> 0).
    double spike = 0.0;
    for (std::size_t j = k - 10; j <= k; ++j) spike = std::max(spike, trace_->friction[j]);
    EXPECT_NEAR(spike, 1.19, 0.03) << "stick " << i;
  }
}

TEST_F(GmsStickSlip, StickVibratesAtElementStiffnessFrequency) {
  // After the stick the mass rings on the stuck elements: f = sqrt((sum k_i + k_pull) / m) / 2 pi.
  const auto p = find_phases(*trace_);
  const auto k = scenario_->friction.column("k");
  const double ktot = std::accumulate(k.begin(), k.end(), 0.0) + scenario_->drive.pull_spring;
  const double f_expected = std::sqrt(ktot / scenario_->plant.mass) / (2 * std::numbers::pi);
  const std::size_t k0 = p.stick_start[0];
  // Count velocity zero crossings over the first 100 ms of the stick.
  std::vector<double> crossings;
  for (std::size_t j = k0 + 1; trace_->t[j] < trace_->t[k0] + 0.1; ++j)
    if ((trace_->v[j - 1] < 0) != (trace_->v[j] < 0)) crossings.push_back(trace_->t[j]);
  ASSERT_GE(crossings.size(), 6u);
  const double f_measured =
      (crossings.size() - 1) / (2 * (crossings.back() - crossings.front()));
  EXPECT_NEAR(f_measured, f_expected, 0.03 * f_expected);
  EXPECT_NEAR(f_expected, 72.9, 0.5);  // docs/references.md: about 72 Hz
}

TEST_F(GmsStickSlip, MicroDampingDampsTheStickVibration) {
  // With micro-damping the ringing decays within the stick; without it, it barely decays.
  auto amplitude_ratio = [](const Trace& tr) {
    const auto p = find_phases(tr);
    const std::size_t k0 = p.stick_start.at(0);
    auto peak_v = [&](double from, double to) {
      double m = 0.0;
      for (std::size_t j = k0; j < tr.size() && tr.t[j] < tr.t[k0] + to; ++j)
        if (tr.t[j] >= tr.t[k0] + from) m = std::max(m, std::abs(tr.v[j]));
      return m;
    };
    return peak_v(0.2, 0.3) / peak_v(0.0, 0.1);
  };
  Scenario undamped = *scenario_;
  undamped.friction = GmsParams::reference(false).to_params();
  undamped.run.duration = 12.0;
  const double damped_ratio = amplitude_ratio(*trace_);
  const double undamped_ratio = amplitude_ratio(simulate(undamped));
  EXPECT_LT(damped_ratio, 0.01);
  EXPECT_GT(undamped_ratio, 0.3);
}

}  // namespace
}  // namespace gmslab
