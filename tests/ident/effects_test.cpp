// The ripple search, the measurement effects (time_shift, sensor_filter, backlash), the level
// asymmetry, the noise estimate, the parameters' standard errors and the remaining-structure test,
// on records of tests/ident/synthetic.hpp whose generating values the expectations come from.
#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>
#include <random>

#include "core/ident/loop.hpp"
#include "core/ident/structure.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

double param(const IdentReport& r, std::string_view effect, std::string_view name) {
  for (const auto& p : r.parameters)
    if (p.effect == effect && p.name == name) return p.value;
  ADD_FAILURE() << "no parameter " << effect << "." << name;
  return 0.0;
}

const ParameterEstimate* estimate(const IdentReport& r, std::string_view effect, std::string_view name) {
  for (const auto& p : r.parameters)
    if (p.effect == effect && p.name == name) return &p;
  return nullptr;
}

struct Run {
  IdentReport rep;
  Dataset train, val;
};

Run run(synth::SynthOptions so, const std::vector<Effect>& candidates = effect_catalog()) {
  so.seed = 11;
  auto train = prepare_dataset(synth::synthesize(so));
  so.seed = 23;
  auto val = prepare_dataset(synth::synthesize(so));
  LoopOptions o;
  o.base.starts = 2;
  o.candidates = candidates;
  auto rep = identify(train, val, FitSpec{}, o);
  std::printf("val %.4g -> %.4g (noise %.4g), added:", rep.rms_before_validation, rep.rms_after_validation,
              so.noise * so.level);
  for (auto e : rep.effects_added) std::printf(" %s", std::string(effect_name(e)).c_str());
  std::printf("\n  %s\n", rep.remaining.summary.c_str());
  for (const auto& rd : rep.rounds)
    for (const auto& a : rd.attempts)
      std::printf("  try %-20s val %.4g size %.3g bic %.1f: %s\n", std::string(effect_name(a.effect)).c_str(),
                  a.rms_validation, a.size, a.bic_change, a.verdict.c_str());
  return {std::move(rep), std::move(train), std::move(val)};
}

// A residual with two ripples (additive 1.3 mm; friction-level 0.47 mm), a presliding-like
// transient after every reversal (the kind of misfit that once gave a 39 um "ripple") and noise.
std::vector<double> ripple_residual(const Dataset& d, double noise, unsigned seed, double a1, double a2) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, noise);
  EffectContext c = make_context(d);
  const auto travel = travel_since_reversal(d, c);
  std::vector<double> r(d.size());
  for (std::size_t k = 0; k < d.size(); ++k) {
    const double s = (d.v[k] > 0) - (d.v[k] < 0);
    r[k] = a1 * std::sin(2 * std::numbers::pi * d.x[k] / 1.3e-3 + 0.2) +
           a2 * s * std::sin(2 * std::numbers::pi * d.x[k] / 0.47e-3 + 1.0) +
           8 * noise * s * std::exp(-travel[k] / 20e-6) + N(rng);
  }
  return r;
}

}  // namespace

TEST(IdentRipple, FindsTwoRipplesWithTheirWavelengthsAndIgnoresTheReversalTransient) {
  for (double level : {0.01, 1.0, 100.0}) {
    synth::SynthOptions so;
    so.seed = 5;
    so.moves = 16;
    const Dataset d = prepare_dataset(synth::synthesize(so));
    const EffectContext c = make_context(d);
    const double noise = 0.05 * level;
    const auto r = ripple_residual(d, noise, 3, 2 * noise, 1.5 * noise);
    const RippleSearch s = ripple_search(d, c, r, {});
    ASSERT_EQ(s.peaks.size(), 2u) << "level " << level;
    EXPECT_NEAR(s.peaks[0].wavelength, 1.3e-3, 0.01 * 1.3e-3);
    EXPECT_NEAR(s.peaks[1].wavelength, 0.47e-3, 0.01 * 0.47e-3);
    EXPECT_NEAR(s.peaks[0].additive, 2 * noise, 0.2 * noise);
    EXPECT_NEAR(s.peaks[1].modulation, 1.5 * noise, 0.2 * noise);
    EXPECT_LT(s.peaks[0].false_alarm, 1e-6);
    EXPECT_LT(s.lmin, 0.2e-3);
    EXPECT_GT(s.lmax, 3e-3);
  }
}

TEST(IdentRipple, NoiseAloneGivesNoRipple) {
  synth::SynthOptions so;
  so.moves = 16;
  int found = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    so.seed = seed;
    const Dataset d = prepare_dataset(synth::synthesize(so));
    const auto r = ripple_residual(d, 0.05, seed, 0.0, 0.0);
    found += static_cast<int>(ripple_search(d, make_context(d), r, {}).peaks.size());
  }
  EXPECT_EQ(found, 0);  // false-alarm level 1e-3 per search: 10 searches, none expected
}

// The case: a 12 % friction ripple with a 1.3 mm wavelength, found by the loop at 1.3 mm.
TEST(IdentRipple, LoopFindsTheTwelvePercentRippleAtItsWavelength) {
  synth::SynthOptions so;
  so.ripple_rel = 0.12;
  so.ripple_L = 1.3e-3;
  so.moves = 16;
  // Candidates: the ripple and the effects a ripple's residual could be mistaken for.
  const auto r = run(so, {Effect::Offset, Effect::DirectionAsymmetry, Effect::PositionPeriodic,
                          Effect::PositionDependent});
  ASSERT_FALSE(r.rep.effects_added.empty());
  EXPECT_EQ(r.rep.effects_added.front(), Effect::PositionPeriodic);
  ASSERT_FALSE(r.rep.ripples.peaks.empty());
  EXPECT_NEAR(r.rep.ripples.peaks.front().wavelength, 1.3e-3, 0.02 * 1.3e-3);
  ASSERT_FALSE(r.rep.context.wavelengths.empty());
  EXPECT_NEAR(r.rep.context.wavelengths.front(), 1.3e-3, 0.02 * 1.3e-3);
  // The ripple (0.12 x 10 N friction, about 0.85 N RMS) is gone: within 2x the noise.
  EXPECT_LT(r.rep.rms_after_validation, 2.0 * so.noise);
  const auto* L = estimate(r.rep, "position_periodic", "L1");
  ASSERT_NE(L, nullptr);
  EXPECT_GT(L->std_error, 0.0);
  EXPECT_LT(L->std_error, 0.01 * 1.3e-3);
}

TEST(IdentNoise, EstimatedFromRestsWithinTenPercent) {
  for (double noise : {0.01, 0.05, 0.3}) {
    synth::SynthOptions so;
    so.noise = noise;
    const Dataset d = prepare_dataset(synth::synthesize(so));
    const auto e = noise_level(d, make_context(d));
    EXPECT_TRUE(e.from_rests);
    EXPECT_NEAR(e.sigma, noise, 0.1 * noise);
  }
}

// The force channel lags by 4 ms (2 samples): named time_shift, not inertia, tau within 20 %.
TEST(IdentMeasurement, ForceChannelLagIsATimeShiftNotInertia) {
  for (double level : {0.1, 10.0}) {
    synth::SynthOptions so;
    so.time_shift = 0.004;
    so.level = level;
    // Candidates: the lag and what it could be taken for.
    const auto r = run(so, {Effect::Inertia, Effect::Offset, Effect::TimeShift, Effect::SensorFilter,
                            Effect::VelocityExtra});
    ASSERT_FALSE(r.rep.effects_added.empty());
    EXPECT_EQ(r.rep.effects_added.front(), Effect::TimeShift);
    EXPECT_NEAR(r.rep.context.time_shift, so.time_shift, 0.2 * so.time_shift);
    EXPECT_LT(r.rep.rms_after_validation, 1.5 * so.noise * level);
    const auto* tau = estimate(r.rep, "time_shift", "tau");
    ASSERT_NE(tau, nullptr);
    EXPECT_GT(tau->std_error, 0.0);
  }
}

TEST(IdentMeasurement, FirstOrderSensorFilterIsNamedWithItsTimeConstant) {
  synth::SynthOptions so;
  so.filter_T = 0.006;
  const auto r = run(so);
  ASSERT_FALSE(r.rep.effects_added.empty());
  EXPECT_EQ(r.rep.effects_added.front(), Effect::SensorFilter);
  EXPECT_NEAR(r.rep.context.filter_T, so.filter_T, 0.25 * so.filter_T);
  EXPECT_LT(r.rep.rms_after_validation, 1.5 * so.noise);
}

TEST(IdentMeasurement, LostMotionAtReversalsIsNamedBacklash) {
  synth::SynthOptions so;
  so.backlash = 10e-6;
  const auto r = run(so);
  ASSERT_FALSE(r.rep.effects_added.empty());
  EXPECT_EQ(r.rep.effects_added.front(), Effect::Backlash);
  EXPECT_NEAR(r.rep.context.backlash, so.backlash, 0.3 * so.backlash);
}

// Friction 8 % higher in one direction: direction_asymmetry, not offset.
TEST(IdentMeasurement, MultiplicativeDirectionAsymmetryIsNotAnOffset) {
  synth::SynthOptions so;
  so.dir_rel = 0.08;
  const auto r = run(so, {Effect::Offset, Effect::DirectionAsymmetry, Effect::Inertia, Effect::PositionDependent});
  ASSERT_FALSE(r.rep.effects_added.empty());
  EXPECT_EQ(r.rep.effects_added.front(), Effect::DirectionAsymmetry);
  // dF = 0.08 Fc: the level difference relative to the fitted Fc.
  EXPECT_NEAR(param(r.rep, "direction_asymmetry", "dF") / param(r.rep, "base", "Fc"), 0.08, 0.015);
}

// Without backlash in the candidates, the lost motion stays in the residual: the report says it
// remains after reversals, larger than the noise; on a clean record nothing remains.
TEST(IdentRemaining, StructureOutsideTheCandidatesIsReportedWhereItIs) {
  synth::SynthOptions so;
  so.backlash = 10e-6;
  std::vector<Effect> cands;
  for (Effect e : effect_catalog())
    if (e != Effect::Backlash) cands.push_back(e);
  const auto r = run(so, cands);
  const auto& rem = r.rep.remaining;
  EXPECT_GT(rem.rms_to_noise, 1.3);
  ASSERT_FALSE(rem.findings.empty());
  bool reversal = false;
  for (const auto& f : rem.findings) reversal |= f.where == "after_reversal" && f.size_to_noise > 0.5;
  EXPECT_TRUE(reversal) << rem.summary;
  const auto j = to_json(r.rep);
  EXPECT_EQ(j.at("remaining_structure").at("summary").get<std::string>(), rem.summary);

  const auto clean = run(synth::SynthOptions{});
  EXPECT_TRUE(clean.rep.effects_added.empty());
  EXPECT_TRUE(clean.rep.remaining.findings.empty()) << clean.rep.remaining.summary;
  EXPECT_LT(clean.rep.remaining.rms_to_noise, 1.3);
}

// Standard errors: the offset (1.5 N in the data) within 4 of its standard errors... and the
// error small against the value.
TEST(IdentUncertainty, OffsetHasAStandardErrorThatCoversTheTruth) {
  synth::SynthOptions so;
  so.effect = Effect::Offset;
  const auto r = run(so, {Effect::Offset, Effect::Inertia});
  const auto* f0 = estimate(r.rep, "offset", "F0");
  ASSERT_NE(f0, nullptr);
  EXPECT_GT(f0->std_error, 0.0);
  EXPECT_LT(f0->std_error, 0.02);
  EXPECT_NEAR(f0->value, 1.5, std::max(4 * f0->std_error, 0.02));
  const auto j = to_json(r.rep);
  bool listed = false;
  for (const auto& p : j.at("parameters")) listed |= p.at("name") == "F0" && p.at("std_error").get<double>() > 0;
  EXPECT_TRUE(listed);
}
