// The CI records of the residual-loop study (effects_study_test.cpp) as a list, so that other tests
// (stability_test.cpp) run the loop on the same records: seeds, scales and effect sizes chosen
// exactly as the study chooses them, records whose floor exceeds twice the noise drawn again.
#pragma once

#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/ident/ablation.hpp"
#include "core/ident/fit.hpp"
#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"

namespace gmslab::study {

// Scales cycled through by the seed: Fs and break-away displacements at the ends of their ranges.
inline records::DrawRanges ranges(unsigned seed) {
  records::DrawRanges r;
  switch (seed % 4) {
    case 0: r.fs_lo = 0.1, r.fs_hi = 0.3, r.xba_lo = 0.5e-6, r.xba_hi = 5e-6; break;
    case 1: r.fs_lo = 300, r.fs_hi = 1000, r.xba_lo = 20e-6, r.xba_hi = 200e-6; break;
    case 2: r.fs_lo = 0.1, r.fs_hi = 1000, r.xba_lo = 0.5e-6, r.xba_hi = 200e-6; break;
    default: r.fs_lo = 3, r.fs_hi = 30, r.xba_lo = 2e-6, r.xba_hi = 50e-6; break;
  }
  r.n_hi = 4;  // the base fit is asked for 4 elements
  return r;
}

struct Case {
  unsigned seed = 0;
  std::vector<records::EffectSpec> effects;
  bool rests = false;  // a rest after every stroke (records::Truth::dwell_rests)
};

struct Record {
  records::Truth truth;
  records::Generated train, validation;
  double floor = 0;  // generator's floor_rms on validation [N]
};

inline Record make_record(const Case& k) {
  Record r;
  r.truth = records::draw_truth(k.seed, ranges(k.seed));
  r.truth.effects = k.effects;
  r.truth.dwell_rests = k.rests;
  auto [tg, vg] = records::synthesize_pair(r.truth, k.seed, 3000);
  r.train = std::move(tg), r.validation = std::move(vg);
  r.floor = records::floor_rms(r.truth, r.validation);
  return r;
}

// The options every study record is identified with.
inline ident::LoopOptions study_options() {
  ident::LoopOptions o;
  o.base.starts = 2;
  return o;
}

// One effect at 2..10 x the noise (size from the seed); the first five kinds in CI.
inline double one_effect_size(unsigned seed) { return 2.0 + 8.0 * ((seed * 37u) % 100) / 100.0; }

// The truth of record i of the loop study (`gmslab_study loop`; seed = first seed + i): the random
// truth of `seed` with no effect (i % 3 == 0), one (1) or two (2) of eight catalog kinds at
// 2..10 x the noise, the kinds cycled by i / 3; with `only`, that one kind at 1.5..50 x the noise,
// log-uniform.
inline records::Truth loop_truth(unsigned seed, int i,
                                 std::optional<records::GenEffect> only = std::nullopt) {
  using records::GenEffect;
  static constexpr GenEffect one[] = {GenEffect::Inertia,
                                      GenEffect::Offset,
                                      GenEffect::DirectionAsymmetry,
                                      GenEffect::PositionRipple,
                                      GenEffect::PositionDependent,
                                      GenEffect::TimeDrift,
                                      GenEffect::VelocityExtra,
                                      GenEffect::NormalLoad};
  constexpr int ne = sizeof one / sizeof one[0];
  records::Truth tr = records::draw_truth(seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int kind = only ? 1 : i % 3;
  if (only)
    tr.effects.push_back({*only, 1.5 * std::pow(50.0 / 1.5, U(rng))});
  else if (kind >= 1)
    tr.effects.push_back({one[(i / 3) % ne], 2.0 + 8.0 * U(rng)});
  if (kind == 2) tr.effects.push_back({one[(i / 3 + 3) % ne], 2.0 + 8.0 * U(rng)});
  return tr;
}

// The truth's friction as gmslab's GMS model (no micro-damping, sigma2 0: the viscous term is
// added on a dataset's own v by the caller).
inline ModelParams gms_params_of(const records::Truth& tr) {
  ModelParams m = model_info("gms").defaults();
  m.set_scalar("Fs", tr.Fs), m.set_scalar("Fc", tr.Fc), m.set_scalar("Vs", tr.Vs);
  m.set_scalar("delta", tr.delta), m.set_scalar("C", tr.C), m.set_scalar("sigma2", 0.0);
  m.elements.clear();
  for (std::size_t e = 0; e < tr.elements(); ++e) m.elements.push_back({tr.alpha[e], tr.k[e], 0.0});
  return m;
}

// RMS of a - b over d's used samples [N].
inline double rms_between(const ident::Dataset& d, const std::vector<double>& a,
                          const std::vector<double>& b) {
  std::vector<double> r(d.size());
  for (std::size_t k = 0; k < d.size(); ++k) r[k] = a[k] - b[k];
  return ident::rms_of(d, r);
}

// The truth's force along a dataset's path: its friction (model: built from gms_params_of) with
// the viscous term on the dataset's own v [N].
inline std::vector<double> truth_force_along(const FrictionModel& model, const records::Truth& tr,
                                             const ident::Dataset& x) {
  std::vector<double> f;
  ident::simulate_along(model, x, f);
  for (std::size_t k = 0; k < x.size(); ++k) f[k] += tr.sigma2 * x.v[k];
  return f;
}

// A record of the coverage study (`gmslab_study coverage`, coverage_test.cpp): the random truth of
// `seed` over the full draw ranges with an offset (even seeds) or an inertia (odd seeds) of
// 2..10 x the noise.
struct CoverageRecord {
  records::Truth truth;
  records::GenEffect kind;
  records::Generated train, validation;
};
inline CoverageRecord coverage_record(unsigned seed, std::size_t samples) {
  using records::GenEffect;
  CoverageRecord r;
  r.truth = records::draw_truth(seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  r.kind = seed % 2 == 0 ? GenEffect::Offset : GenEffect::Inertia;
  r.truth.effects.push_back({r.kind, 2.0 + 8.0 * U(rng)});
  auto [tg, vg] = records::synthesize_pair(r.truth, seed, samples);
  r.train = std::move(tg), r.validation = std::move(vg);
  return r;
}

// The CI subset: three effect-free records, five with one effect, three with two.
inline std::vector<Case> ci_cases() {
  using records::GenEffect;
  std::vector<Case> out;
  for (unsigned s = 1000; s < 1003; ++s) out.push_back({s, {}});
  const GenEffect one[] = {GenEffect::Offset, GenEffect::DirectionAsymmetry, GenEffect::TimeShift,
                           GenEffect::Inertia, GenEffect::PositionRipple};
  unsigned seed = 2000;
  for (GenEffect e : one)
    for (;; ++seed) {
      Case k{seed, {{e, one_effect_size(seed)}}};
      const Record r = make_record(k);
      if (r.floor <= 2.0 * r.truth.noise) {
        out.push_back(k);
        ++seed;
        break;
      }
    }
  const std::pair<GenEffect, GenEffect> two[] = {{GenEffect::Offset, GenEffect::TimeShift},
                                                 {GenEffect::Inertia, GenEffect::DirectionAsymmetry},
                                                 {GenEffect::PositionRipple, GenEffect::Offset}};
  seed = 3000;
  for (const auto& [a, b] : two)
    for (;; ++seed) {
      Case k{seed, {{a, 6.0}, {b, 6.0}}};
      const Record r = make_record(k);
      if (r.floor <= 2.0 * r.truth.noise) {
        out.push_back(k);
        ++seed;
        break;
      }
    }
  return out;
}

}  // namespace gmslab::study
