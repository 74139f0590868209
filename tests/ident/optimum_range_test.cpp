// The break-away ratio's search range and the optimum test on GMS records (gmslab's own trace of
// the Fig. 2C drive, 0.5 mm at 1 Hz, every 20th sample, 0.3 % noise): the fit searches Fs/Fc in
// [1, 5] and widens the range five-fold (twice at most, to 125) where the base fit presses on its
// top. A ratio beyond 5 is then found; a ratio beyond the widest range is never a verified
// minimum, and the reason names the parameter and the end it is pinned at or stopped short of;
// a ratio inside the first range is not called pinned and does not widen it. Parameters drawn at
// random (fixed seeds), the base fit only (max_rounds 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/ident/loop.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"
#include "tests/ident/own_trace.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

Scenario gms_scenario(double ratio, std::mt19937& rng) {
  Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2c_periodic_1hz.json");
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double Fc = std::pow(3.0, U(rng));
  sc.friction.set_scalar("Fc", Fc);
  sc.friction.set_scalar("Fs", ratio * Fc);
  sc.friction.set_scalar("Vs", 1e-3 * std::pow(2.0, U(rng)));
  sc.friction.set_scalar("C", 200.0 * Fc * std::pow(3.0, U(rng)));
  sc.friction.set_scalar("sigma2", 0.4 * Fc * std::pow(3.0, U(rng)));
  return sc;
}

IdentReport identify_gms_record(double ratio, unsigned seed) {
  std::mt19937 rng(seed);
  const Scenario sc = gms_scenario(ratio, rng);
  return own::identify_own_trace(sc, rng, "optimum_range_test").report;
}

// The largest friction force of the scenario's trace (the noise's scale in own_records).
double largest_friction(const Scenario& sc) {
  AssemblySimulation sim = one_body_simulation(sc);
  sim.run_to_end();
  double fmax = 0;
  for (double f : sim.one_body_trace().friction) fmax = std::max(fmax, std::abs(f));
  return fmax;
}

}  // namespace

TEST(OptimumRange, ABreakAwayRatioBeyondTheWidestRangeIsNotAVerifiedMinimum) {
  // Never a verified minimum (the truth is out of reach); where the fit ends at the range's end
  // (fitted Fs/Fc within 0.5 % of 125), the reason names the pinned parameter, and where it
  // stopped short of it, the reason says so.
  int at_end = 0, said = 0, n = 0;
  for (unsigned seed : {3101u, 3102u, 3103u}) {
    std::mt19937 rng(seed);
    const double ratio = std::uniform_real_distribution<double>(200.0, 300.0)(rng);
    const IdentReport r = identify_gms_record(ratio, seed);
    ++n;
    const ModelParams& m = r.final_fit().friction;
    const double fitted = m.scalar("Fs") / m.scalar("Fc");
    const bool end = fitted > 125.0 * 0.995;
    const bool names =
        r.optimum.reason.find("Fs/Fc is pinned at the upper end") != std::string::npos ||
        r.optimum.reason.find("at the top of the widest range") != std::string::npos ||
        r.optimum.reason.find("Fs/Fc stopped at") != std::string::npos;
    at_end += end;
    said += names;
    EXPECT_TRUE(r.break_away_range_widened) << "seed " << seed << " Fs/Fc " << ratio;
    EXPECT_FALSE(r.optimum.verified)
        << "seed " << seed << " Fs/Fc " << ratio << " fitted " << fitted;
    if (end) {
      EXPECT_TRUE(names) << "seed " << seed << " fitted Fs/Fc " << fitted << ": "
                         << r.optimum.reason;
    }
    if (!r.optimum.verified) {
      for (const auto& p : r.parameters) {
        EXPECT_FALSE(std::isfinite(p.std_error)) << p.effect << "." << p.name;
      }
    }
  }
  std::printf("Fs/Fc beyond the widest range: %d / %d fits end at its end, Fs/Fc named in %d\n",
              at_end, n, said);
  EXPECT_GE(said, 1) << "no reason named Fs/Fc: the test shows nothing";
}

TEST(OptimumRange, ABreakAwayRatioBeyondTheFirstRangeIsFound) {
  // Fs/Fc of 6 to 15 lies beyond the first range [1, 5]: the range is widened and the ratio
  // found, the validation RMS is that of the generator's noise (within 1.2x), and nothing is
  // named.
  for (unsigned seed : {3321u, 3322u, 3323u, 3324u, 3325u, 3326u}) {
    std::mt19937 rng(seed);
    const double ratio = std::uniform_real_distribution<double>(6.0, 15.0)(rng);
    Scenario sc = gms_scenario(ratio, rng);
    const own::OwnTraceFit fit = [&] {
      std::mt19937 noise(seed);
      return own::identify_own_trace(sc, noise, "optimum_range_test");
    }();
    const IdentReport& r = fit.report;
    const ModelParams& m = r.final_fit().friction;
    const double fitted = m.scalar("Fs") / m.scalar("Fc");
    const double sigma = 0.003 * largest_friction(sc);
    std::string notes;
    for (const auto& n : r.notes) notes += "\n  " + n;
    EXPECT_TRUE(r.break_away_range_widened) << "seed " << seed << " Fs/Fc " << ratio << notes;
    // Within 10 %: on seeds 3301-3310 the fitted ratio was 0.3-7.2 % off (Fs is a shape parameter
    // that the presliding and the low-speed branch settle, Fc the sliding level; where the record
    // does not reach the speeds that settle the Stribeck curve, Fc is an extrapolation and the
    // report gives it no standard error).
    const ParameterEstimate* fc = nullptr;
    for (const auto& p : r.parameters)
      if (p.effect == "base" && p.name == "Fc") fc = &p;
    ASSERT_NE(fc, nullptr);
    EXPECT_NEAR(fitted / ratio, 1.0, 0.10) << "seed " << seed << " fitted " << fitted;
    if (!std::isfinite(fc->std_error)) {
      EXPECT_NE(fc->no_error.find("extrapolated"), std::string::npos) << fc->no_error;
    }
    EXPECT_LT(r.rms_after_validation, 1.2 * sigma)
        << "seed " << seed << " Fs/Fc " << ratio << " fitted " << fitted;
    EXPECT_TRUE(r.effects_added.empty()) << "seed " << seed;
    EXPECT_EQ(r.optimum.reason.find("Fs/Fc is pinned"), std::string::npos)
        << "seed " << seed << ": " << r.optimum.reason;
    const double se = fc->std_error;
    std::printf(
        "seed %u: Fs/Fc %.3f fitted %.3f, Fc %.4g fitted %.4g se %.3g, validation %.3g N against "
        "the noise %.3g N, %s\n",
        seed, ratio, fitted, sc.friction.scalar("Fc"), m.scalar("Fc"), se, r.rms_after_validation,
        sigma, r.optimum.verified ? "verified" : r.optimum.reason.c_str());
  }
}

TEST(OptimumRange, ABreakAwayRatioInsideTheRangeIsNotCalledPinned) {
  for (unsigned seed : {3201u, 3202u, 3203u}) {
    std::mt19937 rng(seed);
    const double ratio = std::uniform_real_distribution<double>(1.2, 3.0)(rng);
    const IdentReport r = identify_gms_record(ratio, seed);
    EXPECT_EQ(r.optimum.reason.find("Fs/Fc is pinned"), std::string::npos)
        << "seed " << seed << " Fs/Fc " << ratio << ": " << r.optimum.reason;
    EXPECT_FALSE(r.break_away_range_widened) << "seed " << seed << " Fs/Fc " << ratio;
  }
}
