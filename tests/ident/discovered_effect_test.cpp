// The discovered terms as an effect of the model (Effect::Discovered, effects.hpp): each kept
// term is one column, the term as discovery fitted it (its coefficient times its library column,
// library.hpp), so the column's coefficient is the factor by which a joint fit rescales it.
//
//  - The columns: slot i is coefficient_i x library_values(column_i) on the force of the model
//    the terms were discovered on (EffectContext::discovered_force); the slots beyond the kept
//    terms are zero; no column depends on the fit's own g.
//  - A joint fit recovers a term's size: records of gmslab's synthetic GMS rig (synthetic.hpp, no
//    effect, 0.05 N noise on a 10 N Coulomb level) with a reversal transient A sgn(v) exp(-s / L)
//    added as the library computes it on the record (L 0.3-3 mm, A such that the term's RMS is
//    5-30x the noise), fitted from the data with the term at coefficient 1: the fitted factor is
//    A within 5 %, and the training RMS within 1.1x that of the same fit on the record without
//    the term (chosen on seeds 8801-8806: at most 1.5 % off, the RMS within 1.00x).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/ident/discovery.hpp"
#include "core/ident/fit.hpp"
#include "tests/ident/synthetic.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

double rms(const std::vector<double>& y) {
  double s = 0;
  for (double x : y) s += x * x;
  return std::sqrt(s / static_cast<double>(y.size()));
}

}  // namespace

TEST(DiscoveredEffect, ColumnsAreTheKeptTermsAsDiscovered) {
  synth::SynthOptions so;
  so.seed = 8701;
  const Dataset d = prepare_dataset(synth::synthesize(so));
  EffectContext c = make_context(d);
  std::mt19937 rng(8701);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  c.discovered = {{{LibraryFamily::Reversal, 1e-3 * std::pow(3.0, U(rng))}, 2.0 * U(rng)},
                  {{LibraryFamily::HistoryFv, std::pow(10.0, U(rng))}, 3.0 * U(rng)}};
  std::vector<double> f(d.size());
  for (auto& x : f) x = U(rng);
  c.discovered_force = [&](const Dataset& r) {
    EXPECT_EQ(&r, &d);
    return f;
  };
  const auto cols = effect_columns(Effect::Discovered);
  ASSERT_EQ(cols.size(), 4u);
  for (std::size_t i = 0; i < cols.size(); ++i) {
    EXPECT_FALSE(cols[i].uses_g);
    std::vector<double> out(d.size(), -1.0);
    cols[i].fill(d, c, {}, out);
    if (i >= c.discovered.size()) {
      for (double x : out) ASSERT_EQ(x, 0.0) << "slot " << i;
      continue;
    }
    const auto y = library_values(c.discovered[i].column, d, c, f);
    double worst = 0;
    for (std::size_t k = 0; k < d.size(); ++k)
      worst = std::max(worst, std::abs(out[k] - c.discovered[i].coefficient * y[k]));
    EXPECT_EQ(worst, 0.0) << "slot " << i;
    EXPECT_GT(rms(out), 0.0) << "slot " << i;
  }
}

TEST(DiscoveredEffect, AJointFitRecoversATermsSize) {
  for (unsigned seed : {8811u, 8812u, 8813u}) {
    synth::SynthOptions so;
    so.seed = seed;
    const Dataset clean = prepare_dataset(synth::synthesize(so));
    Dataset d = clean;
    EffectContext c = make_context(d);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const LibraryColumn col{LibraryFamily::Reversal, 0.3e-3 * std::pow(10.0, U(rng))};
    const auto y = library_values(col, d, c, {});
    const double A = so.noise * (5.0 + 25.0 * U(rng)) / rms(y);
    for (std::size_t k = 0; k < d.size(); ++k) d.F[k] += A * y[k];
    c.discovered = {{col, 1.0}};
    FitSpec spec;
    spec.model = "gms";
    spec.elements = 4;
    spec.effects = {Effect::Discovered};
    const FitResult f = fit_model(spec, d, c, FitOptions{});
    double factor = 0;
    for (const auto& t : f.terms)
      if (t.effect == "discovered" && t.name == "term1") factor = t.value;
    // The same model fitted on the record without the term: what the term's column may not worsen.
    FitSpec plain = spec;
    plain.effects.clear();
    const double without = fit_model(plain, clean, make_context(clean), FitOptions{}).rms_train;
    std::printf(
        "seed %u: L %.3g mm, A %.4g N, fitted %.4g N (%.2f %%), training RMS %.4g N (%.4g N for "
        "the record without the term)\n",
        seed, 1e3 * col.scale, A, factor, 100 * (factor / A - 1), f.rms_train, without);
    EXPECT_NEAR(factor / A, 1.0, 0.05) << "seed " << seed;
    EXPECT_LT(f.rms_train, 1.1 * without) << "seed " << seed;
  }
}
