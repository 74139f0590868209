// One more element in place of an effect (core/ident/ablation.hpp, 5): an effect the residual loop
// added is not named when the model without it but with one element more fits the validation
// record as well; the report then says the data call for more elements.
//
//   - TooFewElementsNameNoEffect: gmslab's own traces of GMS with K elements (K drawn in 2..5,
//     the scalars drawn around the registry defaults, break-away displacements spread over the
//     drive's reach), driven by three back-and-forth motions, noise-free and with 0.3 % noise,
//     identified with N < K elements. No catalog effect may be named (all but one of the six);
//     where an effect passed the other tests of the credit (what the credit named without this
//     test), the report must say that more elements are called for (at least N + 1).
//   - RealEffectStillCredited: records of an independent GMS implementation
//     (tests/ident/random_records.hpp) with one backlash, offset or velocity_extra of 1.5-50x the
//     noise (log-uniform), identified with the generating element count: where the effect passes
//     the other tests of the credit, one more element in its place must not explain it (>= 95 %
//     of those), and no record may say the data call for more elements. How often the loop names
//     the effect at all is printed (the rounds can miss a small one; that is not this test's).
//   - ChosenCountTakesWhatTheDataCallFor: the records of the first test identified with the
//     count left to the fit (--elements auto). No catalog effect may be named (all but one of
//     the records); where one more element explained an effect, the model takes that count
//     (count_raised) and the report says the count went up, never "identify with N elements". How
//     often the final model's validation is within 1.5x the record's floor is printed.
// Every case is counted and printed. The rule has no threshold of its own (it reuses the credit's
// z >= 3, floor variance and 1.15x floor); the fig2c trace of the issue is where it was looked at.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/friction/model.hpp"
#include "core/ident/loop.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"
#include "tests/ident/study_cases.hpp"

using namespace gmslab;
using namespace gmslab::ident;
using records::GenEffect;

namespace {

std::string named(const IdentReport& r) {
  std::string s;
  for (Effect e : r.effects_added) s += (s.empty() ? "" : " ") + std::string(effect_name(e));
  return s.empty() ? "nothing" : s;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// GMS with K elements: Fc = 3^U(-1,1) N, Fs/Fc in [1.2, 3], Vs, C and sigma2 their defaults
// (scaled by Fc where in N) times 3^U(-1,1), delta in [1, 2.5]; break-away displacements
// alpha_i Fs / k_i log-uniform over [2, 40] um and at least 1.8x apart, weights each >= 10 %.
ModelParams draw_gms(std::size_t K, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto tri = [&] { return std::pow(3.0, 2 * U(rng) - 1); };
  ModelParams p = model_info("gms").defaults();
  const double Fc = tri(), ratio = 1.2 + 1.8 * U(rng);
  p.set_scalar("Fc", Fc);
  p.set_scalar("Fs", ratio * Fc);
  p.set_scalar("Vs", p.scalar("Vs") * tri());
  p.set_scalar("delta", 1.0 + 1.5 * U(rng));
  p.set_scalar("C", 200.0 * Fc * tri());
  p.set_scalar("sigma2", 0.4 * Fc * tri());
  std::vector<double> x(K), a(K);
  const double lo = std::log(2e-6), hi = std::log(40e-6);
  for (auto& xi : x) xi = std::exp(lo + (hi - lo) * U(rng));
  std::sort(x.begin(), x.end());
  for (std::size_t i = 1; i < K; ++i) x[i] = std::max(x[i], 1.8 * x[i - 1]);
  double sum = 0;
  for (auto& ai : a) sum += (ai = 0.4 + U(rng));
  const auto ia = static_cast<std::size_t>(model_info("gms").column_index("alpha"));
  const auto ik = static_cast<std::size_t>(model_info("gms").column_index("k"));
  std::vector<double> row = p.elements.front();
  // No element micro-damping: the identified GMS has none (sigma_i fixed at 0,
  // docs/identification.md), so the element count is the only thing the model lacks.
  row[static_cast<std::size_t>(model_info("gms").column_index("sigma"))] = 0.0;
  p.elements.assign(K, row);
  for (std::size_t i = 0; i < K; ++i) {
    p.elements[i][ia] = a[i] / sum;
    p.elements[i][ik] = a[i] / sum * ratio * Fc / x[i];
  }
  return p;
}

// The drives: Fig. 2C (0.5 mm at 1 Hz), a faster shorter sine (0.2 mm at 2 Hz), and the Fig. 2A
// turning points scaled to 3x (presliding and short slips at 30 um/s).
Scenario drive(int which, const ModelParams& friction) {
  const std::string dir = std::string(GMSLAB_SOURCE_DIR) + "/presets/";
  Scenario sc =
      load_scenario(dir + (which == 2 ? "fig2a_presliding.json" : "fig2c_periodic_1hz.json"));
  if (which == 1) {
    nlohmann::json j = to_json(sc);
    j["drive"]["signal"]["amplitude"] = 2e-4;
    j["drive"]["signal"]["frequency"] = 2.0;
    sc = scenario_from_json(j, "more_elements_test");
  } else if (which == 2) {
    nlohmann::json j = to_json(sc);
    j["drive"]["signal"]["rate"] = 3e-5;
    for (auto& pt : j["drive"]["signal"]["points"]) pt = 3.0 * pt.get<double>();
    sc = scenario_from_json(j, "more_elements_test");
  }
  sc.friction = friction;
  return sc;
}

// The scenario's trace, every k-th sample (about 3000), noise of `noise` x the largest |F|.
std::pair<Dataset, Dataset> own_records(const Scenario& sc, double noise, std::mt19937& rng) {
  AssemblySimulation sim = one_body_simulation(sc);
  sim.run_to_end();
  const Trace& tr = sim.one_body_trace();
  double fmax = 0;
  for (double f : tr.friction) fmax = std::max(fmax, std::abs(f));
  const std::size_t every = std::max<std::size_t>(1, tr.size() / 3000);
  std::normal_distribution<double> N(0.0, 1.0);
  MeasuredRecord rec;
  rec.source = "more_elements_test";
  for (std::size_t i = 0; i < tr.size(); i += every) {
    rec.t.push_back(tr.t[i]);
    rec.x.push_back(tr.x[i]);
    rec.F.push_back(tr.friction[i] + noise * fmax * N(rng));
  }
  return split_holdout(prepare_dataset(rec));
}

}  // namespace

TEST(MoreElements, TooFewElementsNameNoEffect) {
  std::mt19937 rng(9100);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int cases = 0, clean = 0, rounds_added = 0, passed_other = 0, said = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 6; ++i) {
    const std::size_t K = 2 + static_cast<std::size_t>(4 * U(rng) * 0.999999);
    const std::size_t N = 1 + static_cast<std::size_t>((K - 1) * U(rng) * 0.999999);
    const double noise = i % 2 == 0 ? 0.0 : 0.003;
    const Scenario sc = drive(i / 2, draw_gms(K, rng));
    const auto [train, val] = own_records(sc, noise, rng);
    FitSpec spec;
    spec.elements = N;
    const auto t1 = std::chrono::steady_clock::now();
    const IdentReport r = identify(train, val, spec, LoopOptions{});
    ++cases;
    bool added = false;
    for (const auto& rd : r.rounds) added |= rd.added.has_value();
    // Effects that passed the other tests of the credit (the refit without them, same count, is
    // worse): those the credit named before the one-more-element test.
    int passed = 0;
    for (const auto* rows : {&r.ablation.rows, &r.ablation.dropped})
      for (const auto& row : *rows) passed += row.more_elements > 0;
    rounds_added += added;
    passed_other += passed > 0;
    clean += r.effects_added.empty();
    const std::string more = more_elements_summary(r.ablation);
    said += !more.empty();
    std::printf(
        "drive %d, K %zu, N %zu, noise %.1f %%: named %s; rounds added %s, %d passed the other "
        "tests; %s (%.1f s)\n",
        i / 2, K, N, 100 * noise, named(r).c_str(), added ? "yes" : "no", passed,
        more.empty() ? nothing_added(r).c_str() : more.c_str(), seconds_since(t1));
    if (passed > 0) {
      EXPECT_GE(r.ablation.elements_called_for, N + 1) << "case " << i;
      EXPECT_NE(more.find("the data call for more elements"), std::string::npos) << more;
    }
  }
  std::printf(
      "too few elements: %d records, nothing named on %d, rounds added effects on %d, effects "
      "passed "
      "the other tests on %d, more elements called for on %d (%.1f s)\n",
      cases, clean, rounds_added, passed_other, said, seconds_since(t0));
  EXPECT_EQ(cases, 6);
  // 6 of 6 on this seed; one record of six allowed: on tuning seed 9201 one names sensor_filter
  // and backlash (docs/identification-credit.md, *Too few elements*).
  EXPECT_GE(clean, cases - 1);
  EXPECT_GE(said, 1) << "no record exercised the one-more-element test";
}

TEST(MoreElements, RealEffectStillCredited) {
  const GenEffect kinds[] = {GenEffect::Backlash, GenEffect::Offset, GenEffect::VelocityExtra};
  std::mt19937 rng(9300);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int cases = 0, credited = 0, called_for = 0, tested = 0, kept = 0;
  unsigned seed = 9300;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 6; ++i) {
    const GenEffect kind = kinds[i % 3];
    const double size = 1.5 * std::pow(50.0 / 1.5, U(rng));
    // A record whose floor (noise, quantisation) is within 2x the noise, as the study's CI records.
    study::Case k;
    study::Record rec;
    for (;; ++seed) {
      k = study::Case{seed, {{kind, size}}};
      rec = study::make_record(k);
      if (rec.floor <= 2.0 * rec.truth.noise) break;
    }
    ++seed;
    const Dataset train = prepare_dataset(rec.train.record),
                  val = prepare_dataset(rec.validation.record);
    FitSpec spec;
    spec.elements = rec.truth.elements();
    const auto t1 = std::chrono::steady_clock::now();
    const IdentReport r = identify(train, val, spec, study::study_options());
    ++cases;
    const std::string want = records::gen_effect_name(kind);
    bool found = false;
    for (Effect e : r.effects_added) found |= effect_name(e) == want;
    credited += found;
    called_for += r.ablation.elements_called_for > 0;
    for (const auto* rows : {&r.ablation.rows, &r.ablation.dropped})
      for (const auto& row : *rows)
        if (effect_name(row.effect) == want && row.more_elements > 0)
          ++tested, kept += !row.explained_by_element;
    std::printf("seed %u, %zu elements, %s %.1fx noise: named %s%s (%.1f s)\n", k.seed,
                spec.elements, want.c_str(), size, named(r).c_str(),
                r.ablation.elements_called_for > 0 ? "; more elements called for" : "",
                seconds_since(t1));
    for (const auto& d : r.ablation.dropped)
      std::printf("  dropped %s: %s\n", std::string(effect_name(d.effect)).c_str(),
                  d.verdict.c_str());
    EXPECT_EQ(r.ablation.elements_called_for, 0u) << "seed " << k.seed << ": the count is right";
  }
  std::printf(
      "real effect, right count: %d records, named on %d; it passed the other tests and was tested "
      "with one "
      "more element on %d, still credited on %d; more elements called for on %d (%.1f s)\n",
      cases, credited, tested, kept, called_for, seconds_since(t0));
  EXPECT_EQ(cases, 6);
  EXPECT_GE(tested, 1) << "no real effect reached the one-more-element test";
  EXPECT_GE(kept, static_cast<int>(std::ceil(0.95 * tested)));
}

TEST(MoreElements, ChosenCountTakesWhatTheDataCallFor) {
  std::mt19937 rng(9500);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int cases = 0, clean = 0, raised = 0, within = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 4; ++i) {
    const std::size_t K = 2 + static_cast<std::size_t>(4 * U(rng) * 0.999999);
    const double noise = i % 2 == 0 ? 0.0 : 0.003;
    const Scenario sc = drive(i % 3, draw_gms(K, rng));
    const auto [train, val] = own_records(sc, noise, rng);
    FitSpec spec;
    spec.elements = 0;  // --elements auto
    const auto t1 = std::chrono::steady_clock::now();
    const IdentReport r = identify(train, val, spec, LoopOptions{});
    ++cases;
    clean += r.effects_added.empty();
    const std::string more = more_elements_summary(r.ablation);
    const double ratio = r.remaining.rms_to_noise;  // validation RMS / the record's floor
    const bool near = ratio <= 1.5;
    within += near;
    std::printf(
        "drive %d, K %zu, noise %.1f %%: %zu elements, named %s; validation %.3g N = %.2fx the "
        "floor; %s (%.1f s)\n",
        i % 3, K, 100 * noise, r.elements, named(r).c_str(), r.rms_after_validation, ratio,
        more.empty() ? nothing_added(r).c_str() : more.c_str(), seconds_since(t1));
    for (const auto& nt : r.notes) std::printf("  note: %s\n", nt.c_str());
    if (r.ablation.elements_called_for > 0) {
      ++raised;
      EXPECT_TRUE(r.ablation.count_raised) << "case " << i << ": the chosen count may grow";
      EXPECT_NE(more.find("the element count went up to"), std::string::npos) << more;
      EXPECT_EQ(more.find("--elements"), std::string::npos) << more;
    }
  }
  std::printf(
      "count chosen: %d records, nothing named on %d, the count went up on %d, validation within "
      "1.5x the floor on %d (%.1f s)\n",
      cases, clean, raised, within, seconds_since(t0));
  EXPECT_EQ(cases, 4);
  EXPECT_GE(clean, cases - 1);
  EXPECT_GE(raised, 1) << "no record exercised the raised count";
  // Not asserted: the validation within 1.5x the floor holds on 3 of 4 here but on 1 of 4 on each
  // of seeds 9601 and 9602, where the chosen count stays below the generating one
  // (docs/identification-credit.md, *Too few elements*).
}
