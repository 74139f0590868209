// Discovery beyond the catalog (core/ident/discovery.hpp).
//
//  - Effect-free random-truth records (tests/ident/random_records.hpp): nothing discovered.
//  - Records with a term outside the catalog added to the random-truth force, made here from the
//    record's own motion: a reversal transient A sgn(v) exp(-s / L) with L in [0.5, 3] mm, a
//    ripple A sin(2 pi x / lambda + phi) present only for v > 0, and a level following the recent
//    sliding A sgn(v) LP(|v| / v_max, T) with T in [0.3, 3] s. A sets the term's RMS on the
//    training record to `size` x the noise, sizes from 4x to 50x. Expectations from the truth: the
//    right family discovered (reversal: L within a factor 2), the validation RMS within 1.5x the
//    floor (the generator's floor: noise and quantisation). Every case is counted and printed.
// Seeds: GMSLAB_DISCOVERY_SEED (environment) replaces the base seed, for studies on other draws.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>

#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"
#include "tests/ident/study_cases.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

unsigned base_seed(unsigned fallback) {
  const char* s = std::getenv("GMSLAB_DISCOVERY_SEED");
  return s ? static_cast<unsigned>(std::strtoul(s, nullptr, 10)) : fallback;
}

enum class Term { Reversal, DirRipple, History };
const char* term_name(Term t) {
  switch (t) {
    case Term::Reversal:
      return "reversal transient";
    case Term::DirRipple:
      return "ripple for v > 0";
    case Term::History:
      return "sliding history";
  }
  return "?";
}

struct Drawn {
  Term term;
  double scale = 0;  // L [m], lambda [m], T [s]
  double phase = 0;
};

// The term's shape along a record (unit amplitude), from central differences of x.
std::vector<double> term_shape(const Drawn& d, const MeasuredRecord& r) {
  const std::size_t n = r.t.size();
  std::vector<double> v(n, 0.0), out(n, 0.0);
  double vmax = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k >= 2 ? k - 2 : 0, b = std::min(n - 1, k + 2);
    v[k] = (r.x[b] - r.x[a]) / (r.t[b] - r.t[a]);
    vmax = std::max(vmax, std::abs(v[k]));
  }
  const double rest = 0.02 * vmax;
  double s = 0, last = 0, lp = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double sg = std::abs(v[k]) > rest ? (v[k] > 0 ? 1.0 : -1.0) : 0.0;
    if (sg != 0 && sg != last) s = 0, last = sg;
    if (k > 0) s += std::abs(r.x[k] - r.x[k - 1]);
    if (k > 0)
      lp += (1 - std::exp(-(r.t[k] - r.t[k - 1]) / d.scale)) * (std::abs(v[k]) / vmax - lp);
    switch (d.term) {
      case Term::Reversal:
        out[k] = sg * std::exp(-s / d.scale);
        break;
      case Term::DirRipple:
        out[k] = sg > 0 ? std::sin(2 * std::numbers::pi * r.x[k] / d.scale + d.phase) : 0.0;
        break;
      case Term::History:
        out[k] = sg * lp;
        break;
    }
  }
  return out;
}

double rms(const std::vector<double>& y) {
  double s = 0;
  for (double x : y) s += x * x;
  return std::sqrt(s / static_cast<double>(y.size()));
}

records::DrawRanges ranges(unsigned seed) {
  records::DrawRanges r = study::ranges(seed);
  r.rate_lo = 500, r.rate_hi = 1000;  // records of 4-8 s: the history time constants fit in
  return r;
}

struct Outcome {
  IdentReport report;
  double floor = 0;
};

Outcome run(unsigned seed, const Drawn* d, double size) {
  records::Truth tr = records::draw_truth(seed, ranges(seed));
  auto [tg, vg] = records::synthesize_pair(tr, seed, 4000);
  Outcome o;
  o.floor = records::floor_rms(tr, vg);
  if (d) {
    const auto st = term_shape(*d, tg.record), sv = term_shape(*d, vg.record);
    const double A = size * tr.noise / rms(st);
    for (std::size_t k = 0; k < st.size(); ++k) tg.record.F[k] += A * st[k];
    for (std::size_t k = 0; k < sv.size(); ++k) vg.record.F[k] += A * sv[k];
  }
  FitSpec spec;
  o.report = identify(prepare_dataset(tg.record), prepare_dataset(vg.record), spec,
                      study::study_options());
  return o;
}

bool right_family(const Drawn& d, const Discovery& s) {
  if (!s.found) return false;
  for (const auto& t : s.terms) {
    switch (d.term) {
      case Term::Reversal:
        if (t.column.family == LibraryFamily::Reversal && t.column.scale > d.scale / 2 &&
            t.column.scale < d.scale * 2)
          return true;
        break;
      case Term::DirRipple:
        if ((t.column.family == LibraryFamily::DirRippleSin ||
             t.column.family == LibraryFamily::DirRippleCos) &&
            t.column.direction > 0 && std::abs(t.column.scale / d.scale - 1) < 0.05)
          return true;
        break;
      case Term::History:
        if (t.column.family == LibraryFamily::HistoryV ||
            t.column.family == LibraryFamily::HistoryFv)
          return true;
        break;
    }
  }
  return false;
}

TEST(Discovery, NothingOnEffectFreeRandomRecords) {
  const unsigned s0 = base_seed(7100);
  int fired = 0, n = 0;
  for (unsigned seed = s0; seed < s0 + 6; ++seed) {
    const Outcome o = run(seed, nullptr, 0);
    ++n;
    fired += o.report.discovery.found;
    std::printf("effect-free seed %u: validation %.3g N = %.2fx floor; %s\n", seed,
                o.report.rms_after_validation, o.report.rms_after_validation / o.floor,
                o.report.discovery.summary.c_str());
  }
  std::printf("effect-free: discovered on %d of %d records\n", fired, n);
  EXPECT_EQ(fired, 0);
}

// One family a test, each record about 20 s on two cores. The sliding history, whose family count
// is held, at four sizes; the reversal transient and the direction-gated ripple, whose runs check
// that a kept set lowers the validation and passed the credit test (their family counts are
// printed), at two.
class DiscoveryOutside : public ::testing::TestWithParam<Term> {};

TEST_P(DiscoveryOutside, TermsOutsideTheCatalog) {
  const Term term = GetParam();
  const unsigned s0 = base_seed(7300) + 4 * static_cast<unsigned>(term);
  const std::vector<double> sizes = term == Term::History
                                        ? std::vector<double>{4.0, 10.0, 25.0, 50.0}
                                        : std::vector<double>{10.0, 50.0};
  int cases = 0, family_ok = 0, floor_ok = 0, catalog_named = 0;
  std::printf("%-20s %6s %10s %6s | %-8s %-7s %-9s | %s\n", "term", "size", "scale", "seed",
              "family", "val/flr", "seconds", "catalog | discovery");
  {
    for (double size : sizes) {
      const unsigned seed = s0 + static_cast<unsigned>(cases);  // 7300 + 4 family + case
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> U(0.0, 1.0);
      Drawn d{term};
      if (term == Term::Reversal)
        d.scale = 0.5e-3 * std::pow(6.0, U(rng));
      else if (term == Term::DirRipple)
        d.scale = 0.3e-3 * std::pow(3.0, U(rng)), d.phase = 6.28 * U(rng);
      else
        d.scale = 0.3 * std::pow(10.0, U(rng));
      const auto t0 = std::chrono::steady_clock::now();
      const Outcome o = run(seed, &d, size);
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const Discovery& ds = o.report.discovery;
      const bool fam = right_family(d, ds);
      // Said, never silently absent; a kept set lowers the validation RMS and passed the test.
      EXPECT_TRUE(ds.summary.rfind("not run", 0) == 0 ||
                  ds.summary.rfind("nothing discovered", 0) == 0 ||
                  ds.summary.rfind("discovered", 0) == 0)
          << ds.summary;
      if (ds.found) {
        EXPECT_LT(ds.rms_validation_after, ds.rms_validation_before) << ds.summary;
        EXPECT_TRUE(ds.test.z >= ds.z_crit || ds.test.mse_difference >= ds.floor * ds.floor)
            << ds.summary;
        EXPECT_GE(ds.contribution, 0.5 * ds.floor) << ds.summary;
        EXPECT_NEAR(o.report.rms_after_validation, ds.rms_validation_after, 1e-12)
            << "the report includes the terms";
      }
      // Terms in the model: named as an effect and credited by the ablation like one.
      if (ds.joined) {
        EXPECT_TRUE(ds.found) << ds.summary;
        bool credited = false;
        for (const auto& row : o.report.ablation.rows)
          credited = credited || (row.effect == Effect::Discovered && row.credited);
        EXPECT_TRUE(credited) << ds.summary;
        EXPECT_NE(std::find(o.report.effects_added.begin(), o.report.effects_added.end(),
                            Effect::Discovered),
                  o.report.effects_added.end());
      }
      const double ratio = o.report.rms_after_validation / o.floor;
      ++cases;
      family_ok += fam;
      floor_ok += ratio <= 1.5;
      std::string named;
      for (Effect e : o.report.effects_added) {
        named += std::string(named.empty() ? "" : ",") + std::string(effect_name(e));
        catalog_named += e != Effect::Discovered;  // none of them is in the record
      }
      std::printf("%-20s %6.0f %10.3g %6u | %-8s %-7.2f %-9.1f | %s | %s\n", term_name(term), size,
                  d.scale, seed, fam ? "right" : "no", ratio, secs,
                  named.empty() ? "-" : named.c_str(), ds.summary.c_str());
    }
  }
  std::printf("%s: right family %d of %d, validation within 1.5x the floor %d of %d\n",
              term_name(term), family_ok, cases, floor_ok, cases);
  // Limits from seeds 9100-9111: the sliding history was found in 3 of 4, the reversal transient in
  // 0 of 4 and the direction-gated ripple in 1 of 4 (the catalog's shape and effects absorb much of
  // these before the residual regression sees them); only the history has a count to hold, set
  // below both seed ranges' counts (3 and 2 of 4) because a last-bit difference between machines
  // can move a fit to another stopping point (docs/identification-credit.md).
  // Catalog effects named on records that hold none: with the discovered terms fitted jointly and
  // credited again, the sliding history's stand-ins (time_drift, velocity_extra) go; on seeds
  // 9100-9111 its four records named 3 catalog effects with the terms on the residual and 0 with
  // them joined (on 7300-7311: 5 and 1).
  std::printf("%s: catalog effects named %d\n", term_name(term), catalog_named);
  if (term == Term::History) {
    EXPECT_GE(family_ok, 1);
    EXPECT_LE(catalog_named, 2);
  }
}

INSTANTIATE_TEST_SUITE_P(Families, DiscoveryOutside,
                         ::testing::Values(Term::Reversal, Term::DirRipple, Term::History),
                         [](const auto& info) {
                           switch (info.param) {
                             case Term::Reversal:
                               return std::string("ReversalTransient");
                             case Term::DirRipple:
                               return std::string("DirectionRipple");
                             case Term::History:
                               return std::string("SlidingHistory");
                           }
                           return std::string("Other");
                         });

}  // namespace
