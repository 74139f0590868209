// The path between samples and the guards that keep the loop from naming what the path explains
// (core/ident/dataset.hpp PathRule, core/ident/loop.cpp identify). Records from the independent
// GMS implementation (tests/ident/random_records.hpp); expectations from the generating truth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"

using namespace gmslab;
using namespace gmslab::ident;

// Every interval's parts follow the rule: a reversal between two samples gets reversal_parts, an
// interval whose speed changes by more than speed_change (over more than an encoder step) at least
// curved_parts, every other one other_parts; the parts of an interval add up to its step and its
// travel.
TEST(IdentPath, PartsFollowTheRule) {
  for (unsigned seed : {3u, 11u, 29u}) {
    records::Truth tr = records::draw_truth(seed);
    const auto g = records::synthesize(tr, seed, 2000);
    Dataset d = prepare_dataset(g.record);
    double q = 0;
    for (std::size_t k = 1; k < d.size(); ++k) {
      const double dx = std::abs(d.x[k] - d.x[k - 1]);
      if (dx > 0 && (q == 0 || dx < q)) q = dx;
    }
    for (const PathRule& rule : {PathRule{}, kFinePath}) {
      set_path(d, rule);
      ASSERT_EQ(d.sub.size(), d.size() + 1);
      std::size_t reversals = 0, changes = 0;
      for (std::size_t k = 1; k < d.size(); ++k) {
        const std::size_t parts = d.sub[k + 1] - d.sub[k];
        const double m0 = d.v[k - 1] * d.h[k], m1 = d.v[k] * d.h[k];
        const bool reversal = d.v[k - 1] * d.v[k] < 0 && std::abs(m0) + std::abs(m1) > 0.25 * q;
        const bool change = std::abs(d.v[k] - d.v[k - 1]) > rule.speed_change * std::max(std::abs(d.v[k]), std::abs(d.v[k - 1])) &&
                            std::abs(d.x[k] - d.x[k - 1]) > q;
        if (reversal) {
          ++reversals;
          EXPECT_EQ(parts, static_cast<std::size_t>(rule.reversal_parts)) << k;
        } else if (change) {
          ++changes;
          EXPECT_EQ(parts, static_cast<std::size_t>(std::max(rule.curved_parts, rule.other_parts))) << k;
        } else if (rule.other_parts > 1) {
          EXPECT_GE(parts, static_cast<std::size_t>(rule.other_parts)) << k;
        }
        if (parts == 0) continue;
        double h = 0, dx = 0;
        for (auto j = d.sub[k]; j < d.sub[k + 1]; ++j) h += d.sh[j], dx += d.sv[j] * d.sh[j];
        EXPECT_NEAR(h, d.h[k], 1e-12 * d.h[k]);
        EXPECT_NEAR(dx, d.x[k] - d.x[k - 1], 1e-9 * std::max(q, std::abs(d.x[k] - d.x[k - 1])));
      }
      EXPECT_GT(reversals, 5u) << "the motion has presliding reversals";
      EXPECT_GT(changes, 5u);
    }
  }
}

namespace {
// The base fit (no loop rounds) of a truth on its training / validation pair; returns the report
// and the floor that noise, quantisation and sampling leave (generator's floor_rms).
std::pair<IdentReport, double> base_fit(records::Truth& tr, unsigned seed) {
  auto [tg, vg] = records::synthesize_pair(tr, seed, 3000);
  const Dataset train = prepare_dataset(tg.record), val = prepare_dataset(vg.record);
  FitSpec spec;
  spec.elements = tr.elements();
  LoopOptions lo;
  lo.max_rounds = 0;
  return {identify(train, val, spec, lo), records::floor_rms(tr, vg)};
}
}  // namespace

// A fast attraction (a slipping element relaxes within the sample step, C h / Fs from 1 to 3):
// the force at a sample follows the speed at that sample; the identification (on the fine path
// where the path matters at the noise level) reaches the floor. A slow one (C h / Fs =
// 0.002-0.01) stays on the adaptive path.
TEST(IdentPath, FastAttractionRunsOnTheFinePathAndReachesTheFloor) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (unsigned seed : {7u, 44u}) {  // study records at 1 kHz and 7 kHz
    records::Truth tr = records::draw_truth(seed);
    tr.C = tr.Fs * tr.rate * (1.0 + 2.0 * U(rng));
    const auto [rep, floor] = base_fit(tr, seed);
    EXPECT_LE(rep.rms_after_validation, 1.3 * floor)
        << "seed " << seed << (rep.fine_path ? " (fine path)" : " (adaptive path)") << ": path difference "
        << rep.path_difference << " N, noise " << rep.noise.sigma << " N";
  }
  {
    const unsigned seed = 5;
    records::Truth tr = records::draw_truth(seed);
    tr.C = tr.Fs * tr.rate * (0.002 + 0.008 * U(rng));
    const auto [rep, floor] = base_fit(tr, seed);
    EXPECT_FALSE(rep.fine_path) << "relaxation per step " << tr.C / tr.Fs / tr.rate;
    EXPECT_LE(rep.rms_after_validation, 1.3 * floor);
  }
}

// Records without any effect whose floor the path between samples dominates (study records 10
// and 58): a model lagging along the sampled path looked like a negative mass or a time shift.
// Nothing is added; a negative mass is never kept.
TEST(IdentLoopGuards, NoEffectIsNamedForWhatThePathExplains) {
  for (unsigned seed : {10u, 58u}) {
    records::Truth tr = records::draw_truth(seed);
    auto [tg, vg] = records::synthesize_pair(tr, seed, 3000);
    const Dataset train = prepare_dataset(tg.record), val = prepare_dataset(vg.record);
    FitSpec spec;
    spec.elements = tr.elements();
    const auto rep = identify(train, val, spec, LoopOptions{});
    EXPECT_TRUE(rep.effects_added.empty()) << "seed " << seed << ": " << effect_name(rep.effects_added.front());
    for (const auto& rd : rep.rounds)
      for (const auto& a : rd.attempts)
        if (a.kept && a.effect == Effect::Inertia)
          for (const auto& t : a.terms)
            if (t.name == "M") {
              EXPECT_GT(t.value, 0.0) << "seed " << seed;
            }
  }
}
