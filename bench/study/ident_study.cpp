// gmslab identification study: random records from an independent GMS implementation
// (tests/ident/random_records.hpp), fitted by gmslab, scored against the floor that noise and
// encoder quantisation alone leave (the true model evaluated along the measured positions).
//
//   gmslab_study base    [--records 50] [--seed 1] [--samples 6000]   base fit, no effect
//   gmslab_study loop    [--records 50] ...   the residual loop on records with 0, 1 or 2 effects
//                        (--effect NAME: each record with that one generated effect, 1.5-50x)
//   gmslab_study coverage [--records 100]   the standard errors: random records with an offset
//                        (even seeds) or an inertia (odd seeds), 2-10x the noise; how often the
//                        truth lies within +-2 sigma of the estimate (Fc, and the effect's F0 or
//                        M), per parameter
//   gmslab_study self    [--preset NAME]      self-consistency: gmslab's own trace of each shipped
//                        one-body preset with back-and-forth motion, at 3 sample rates, noise-free
//                        and with 0.3 % noise, identified with the generating model (nothing to
//                        name)
//   gmslab_study registry [--records 2] [--seed 1] [--samples 6000]   every registry model with
//                        random parameters (each scalar its default x 3^U(-1,1), within its range),
//                        driven like Fig. 2C (0.5 mm at 1 Hz), 0.3 % noise, identified with the
//                        generating model (self-consistency: nothing to name) and, for LuGre,
//                        Leuven, Maxwell-slip and elasto-plastic, with GMS (structure mismatch:
//                        what is named, and what remains, against the generating model's floor)
//
//   gmslab_study floor   [--records 60] [--seed 1] [--samples 3000]   the floor's estimate against
//                        the generator's on effect-free records of the loop study's truths,
//                        through the truth's own model (no fit): the quantisation and sampling
//                        shares as the loop estimates them, what the path actually leaves, and two
//                        alternative estimators (docs/identification.md, *How close the floor
//                        estimate is*)
//
//   gmslab_study cycles  [--records 240] [--seed 5000]   periodic orbits
//   (core/control/limit_cycles.hpp)
//                        of random loops (tests/control/random_loops.hpp) against their long
//                        simulation: one row per loop, the counts of false negatives / positives
//
// Prints one row per record and a summary; exit 0 (it reports, it does not judge).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <string>

#include "core/friction/model.hpp"
#include "core/ident/element_fit.hpp"
#include "core/ident/loop.hpp"
#include "core/ident/structure.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"
#include "tests/control/random_loops.hpp"
#include "tests/ident/random_records.hpp"
#include "tests/ident/study_cases.hpp"

using namespace gmslab;
using namespace gmslab::ident;
using namespace gmslab::records;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string truth_line(const Truth& t) {
  char b[256];
  std::snprintf(b, sizeof b, "N=%zu Fs=%8.3g x_ba=%7.2g..%7.2g um noise=%5.2f%% q=%5.1f nm %6.0f Hz%s",
                t.elements(), t.Fs, 1e6 * t.x_min(), 1e6 * t.x_max(), 100 * t.noise / t.Fs,
                1e9 * t.quantum, t.rate, t.jitter ? " jit" : "    ");
  return b;
}

// The truth, the fitted parameters, the estimated floor and the truth through gmslab's GMS on
// the validation record (--detail).
void print_detail(const Truth& tr, const IdentReport& rep, const Dataset& val, double floor_train) {
  std::printf(
      "  truth: Fs %.4g Fc %.4g Vs %.3g delta %.3g C %.4g sigma2 %.4g | elements (alpha, x_ba um):",
      tr.Fs, tr.Fc, tr.Vs, tr.delta, tr.C, tr.sigma2);
  for (std::size_t e = 0; e < tr.elements(); ++e)
    std::printf(" (%.3f, %.3g)", tr.alpha[e], 1e6 * tr.x_break(e));
  const auto& f = rep.final_fit().friction;
  std::printf("\n  fit:  ");
  for (std::size_t j = 0; j < f.scalars.size(); ++j) std::printf(" %.4g", f.scalars[j]);
  std::printf(" | elements (alpha, x_ba um at Fs):");
  const double fs = f.model == "gms" ? f.scalar("Fs") : 1.0;
  for (const auto& row : f.elements)
    std::printf(" (%.3f, %.3g)", row[0], 1e6 * row[0] * fs / row[1]);
  // The truth through gmslab's own GMS model along the validation record (viscous on d.v).
  std::vector<double> g;
  simulate_along(*build_model(study::gms_params_of(tr)), val, g);
  double s2 = 0, n2 = 0;
  for (std::size_t k = 0; k < val.size(); ++k)
    if (val.use[k]) {
      s2 += std::pow(val.F[k] - g[k] - tr.sigma2 * val.v[k], 2), n2 += 1;
    }
  std::printf(
      "\n  estimated floor %.4g (sigma %.4g, quantisation %.3g, sampling %.3g; the generator's on "
      "training %.4g: %.2fx), retried %d",
      rep.noise.floor(), rep.noise.sigma, rep.noise.quantisation, rep.noise.sampling, floor_train,
      rep.noise.floor() / floor_train, int(rep.base_retried));
  std::printf(
      "\n  train rms %.4g, noise sd %.4g; the truth through gmslab's GMS on validation: RMS %.4g\n",
      rep.rms_after_train, tr.noise, std::sqrt(s2 / n2));
}

int run_base(int records, unsigned seed0, std::size_t samples, bool auto_n, bool detail, std::size_t screen) {
  int pass = 0;
  double worst = 0, total_s = 0;
  std::printf("%-4s %-68s %10s %10s %6s %5s %6s %s\n", "rec", "truth", "floor", "val RMS", "ratio", "N fit", "s", "path");
  for (int i = 0; i < records; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    Truth tr = draw_truth(seed);
    auto [g_train, g_val] = synthesize_pair(tr, seed, samples);
    const Dataset train = prepare_dataset(g_train.record), val = prepare_dataset(g_val.record);
    const double floor = floor_rms(tr, g_val);
    const auto t0 = std::chrono::steady_clock::now();
    FitSpec spec;
    spec.elements = auto_n ? 0 : tr.elements();
    LoopOptions lo;
    lo.max_rounds = 0;
    lo.screen_samples = screen;
    const auto rep = identify(train, val, spec, lo);
    const double s = seconds_since(t0);
    total_s += s;
    const double ratio = rep.rms_after_validation / floor;
    worst = std::max(worst, ratio);
    pass += ratio <= 1.2;
    std::printf("%-4u %-68s %10.4g %10.4g %6.3f %5zu %6.2f %s\n", seed, truth_line(tr).c_str(), floor,
                rep.rms_after_validation, ratio, rep.final_fit().spec.elements, s, (std::string(rep.fine_path ? "fine " : "") + (rep.range_widened ? "wide " : "") + (rep.base_retried ? "retry" : "")).c_str());
    if (detail) print_detail(tr, rep, val, floor_rms(tr, g_train));
    std::fflush(stdout);
  }
  std::printf("\nbase fit: %d / %d records within 1.2x the floor (%.0f %%); worst %.3f; %.1f s per record\n",
              pass, records, 100.0 * pass / records, worst, total_s / records);
  return 0;
}

// The residual loop on records with no effect, one catalog effect (2..10 x the noise) or two.
// With `only` set, every record has that one effect instead, its size log-uniform over 1.5..50 x
// the noise, and the generator's parameter for that size is printed (random_records.hpp: a
// backlash in m, a time shift in s, ...; for dwell stiction also over Fs: the break-away rise per
// unit ln(1 + T_rest / 0.1 s)).
int run_loop(int records, unsigned seed0, std::size_t samples, int skip,
             const std::string& report_dir, std::size_t screen, std::optional<GenEffect> only,
             bool credit_bound, bool detail) {
  int n0 = 0, ok0 = 0, n1 = 0, ok1 = 0, n2 = 0, ok2 = 0, floor_ok = 0;
  double total_s = 0;
  std::printf("%-4s %-40s %-40s %8s %6s %6s\n", "rec", "generated", "added", "val/floor", "s", "every");
  for (int i = skip; i < skip + records; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    Truth tr = study::loop_truth(seed, i, only);
    const int kind = only ? 1 : i % 3;  // 0: none, 1: one effect, 2: two effects
    auto [g_train, g_val] = synthesize_pair(tr, seed, samples);
    if (only) {
      const auto& e = tr.effects.front();
      std::printf("%-4u %s of %.1fx the noise: generator parameter %.4g", seed,
                  gen_effect_name(e.kind), e.size, e.param);
      if (e.kind == GenEffect::DwellStiction) std::printf(" (%.3g Fs)", e.param / tr.Fs);
      std::printf("\n");
    }
    const Dataset train = prepare_dataset(g_train.record), val = prepare_dataset(g_val.record);
    const double floor = floor_rms(tr, g_val);
    const auto t0 = std::chrono::steady_clock::now();
    FitSpec spec;
    spec.elements = tr.elements();
    LoopOptions lo;
    lo.screen_samples = screen;
    lo.credit_bound = credit_bound;
    const auto rep = identify(train, val, spec, lo);
    const double s = seconds_since(t0);
    total_s += s;
    if (!report_dir.empty()) {
      std::ofstream(report_dir + "/record" + std::to_string(seed) + ".json") << to_json(rep).dump(1);
    }
    std::string gen, added;
    for (const auto& e : tr.effects) gen += std::string(gen.empty() ? "" : ",") + gen_effect_name(e.kind);
    for (auto e : rep.effects_added) added += std::string(added.empty() ? "" : ",") + std::string(effect_name(e));
    bool right = false;
    if (kind == 0) ++n0, right = rep.effects_added.empty(), ok0 += right;
    if (kind == 1) ++n1, right = !rep.effects_added.empty() && effect_name(rep.effects_added.front()) == gen_effect_name(tr.effects[0].kind), ok1 += right;
    if (kind == 2) {
      ++n2;
      int found = 0;
      for (const auto& g : tr.effects)
        for (auto e : rep.effects_added) found += effect_name(e) == gen_effect_name(g.kind);
      right = found == 2;
      ok2 += right;
    }
    const double ratio = rep.rms_after_validation / floor;
    floor_ok += ratio <= 1.5;
    std::printf("%-4u %-40s %-40s %8.3f %6.2f %6zu %s\n", seed, gen.empty() ? "-" : gen.c_str(),
                added.empty() ? "-" : added.c_str(), ratio, s, rep.screen_every, right ? "" : "  <-- wrong");
    if (detail) print_detail(tr, rep, val, floor_rms(tr, g_train));
    std::fflush(stdout);
  }
  std::printf("\nno effect: nothing added in %d / %d; one effect: named first in %d / %d; two effects: "
              "both named in %d / %d; validation <= 1.5x floor in %d / %d; %.1f s per record\n",
              ok0, n0, ok1, n1, ok2, n2, floor_ok, records, total_s / records);
  return 0;
}

// The floor's estimate through the truth's own model on effect-free records (`floor` mode). Per
// record: the generator's floor (floor_rms), what gmslab's path leaves of the truth's force with
// and without the encoder's rounding (the records made again with quantum 0), the loop's
// quantisation share (add_quantisation) against the model along the smoothest positions within
// half an encoder step (within_encoder_step), and the loop's sampling share (add_sampling: the
// cubic less straight steps, over sqrt(3)) against what halving the rate changes, over 2 (the
// model along every 2nd sample: add_sampling_halving). The estimated floors use the generator's
// noise sd; "alt" is the credit bound's sampling share (the smaller of the two) with the encoder
// path's quantisation share.
int run_floor(int records, unsigned seed0, std::size_t samples) {
  std::printf("%-6s %9s %9s | %9s %9s | %9s %9s | %9s %9s | %6s %6s %6s\n", "rec", "noise", "floor",
              "path N", "no enc N", "quant N", "enc N", "samp N", "half N", "C h/Fs", "loop",
              "alt");
  int in_loop = 0, in_alt = 0;
  for (int i = 0; i < records; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    Truth tr = study::loop_truth(seed, i);
    tr.effects.clear();
    auto [gt, gv] = synthesize_pair(tr, seed, samples);
    Truth tq = tr;
    tq.quantum = 0;
    const auto gq = synthesize_pair(tq, seed, samples).first;
    const Dataset d = prepare_dataset(gt.record), dq = prepare_dataset(gq.record);
    const auto model = build_model(study::gms_params_of(tr));
    auto along = [&](const Dataset& x) { return study::truth_force_along(*model, tr, x); };
    const auto f = along(d), fq = along(dq);
    const double path = study::rms_between(d, f, gt.clean_base),
                 path_nq = study::rms_between(dq, fq, gq.clean_base);
    NoiseEstimate loop;
    add_quantisation(loop, d, make_context(d), f);
    add_sampling(loop, d, f, along(with_straight_steps(d)));
    const double enc =
        loop.quantum > 0
            ? study::rms_between(d, f, along(within_encoder_step(d, loop.quantum, PathRule{})))
            : 0.0;
    add_sampling_halving(loop, d, f, along(decimated(d, 2, PathRule{})));
    const double half = loop.sampling_halving;
    const double gen = floor_rms(tr, gt);
    const double est_loop = std::hypot(tr.noise, loop.quantisation, loop.sampling) / gen;
    const double est_alt = std::hypot(tr.noise, enc, std::min(loop.sampling, half)) / gen;
    in_loop += est_loop >= 1 / 1.5 && est_loop <= 1.5,
        in_alt += est_alt >= 1 / 1.5 && est_alt <= 1.5;
    std::printf("%-6u %9.3g %9.3g | %9.3g %9.3g | %9.3g %9.3g | %9.3g %9.3g | %6.2f %6.2f %6.2f\n",
                seed, tr.noise, gen, path, path_nq, loop.quantisation, enc, loop.sampling, half,
                tr.C * d.h[1] / tr.Fs, est_loop, est_alt);
    std::fflush(stdout);
  }
  std::printf(
      "\nestimated floor within 1.5x of the generator's: the loop's shares %d / %d, "
      "the alternative (encoder path, min(sampling, halving)) %d / %d\n",
      in_loop, records, in_alt, records);
  return 0;
}

// Coverage of the standard errors: is the truth within +-2 sigma of the estimate?
int run_coverage(int records, unsigned seed0, std::size_t samples, const std::string& report_dir) {
  struct Count { int n = 0, covered = 0, no_error = 0, not_found = 0; };
  std::map<std::string, Count> counts;
  double total_s = 0;
  std::printf("%-6s %-8s %-10s %12s %12s %10s %8s %6s\n", "rec", "effect", "parameter", "truth", "estimate",
              "std err", "|d|/se", "s");
  for (int i = 0; i < records; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    const study::CoverageRecord cr = study::coverage_record(seed, samples);
    const Truth& tr = cr.truth;
    const GenEffect kind = cr.kind;
    const Dataset train = prepare_dataset(cr.train.record),
                  val = prepare_dataset(cr.validation.record);
    FitSpec spec;
    spec.elements = tr.elements();
    const auto t0 = std::chrono::steady_clock::now();
    const auto rep = identify(train, val, spec, LoopOptions{});
    const double s = seconds_since(t0);
    total_s += s;
    if (!report_dir.empty())
      std::ofstream(report_dir + "/record" + std::to_string(seed) + ".json")
          << to_json(rep).dump(1);
    const std::string effect = gen_effect_name(kind);
    const auto reach = stribeck_reach(rep.final_fit().friction, train, kStribeckReachLimit);
    std::printf("%-6u reach: top speed %.3g m/s, the fitted curve %.3g x Fc above Fc there\n", seed,
                reach ? reach->v_top : 0.0, reach ? reach->excess : 0.0);
    const struct { std::string effect, name; double truth; } wanted[] = {
        {"base", "Fc", tr.Fc}, {effect, kind == GenEffect::Offset ? "F0" : "M", tr.effects[0].param}};
    for (const auto& w : wanted) {
      Count& c = counts[w.effect + "." + w.name];
      ++c.n;
      const ParameterEstimate* pe = nullptr;
      for (const auto& p : rep.parameters)
        if (p.effect == w.effect && p.name == w.name) pe = &p;
      if (!pe) {
        ++c.not_found;
        std::printf("%-6u %-8s %-10s %12.4g %12s %10s %8s %6.2f\n", seed, effect.substr(0, 8).c_str(), w.name.c_str(),
                    w.truth, "not found", "-", "-", s);
        continue;
      }
      if (!std::isfinite(pe->std_error) || !(pe->std_error > 0)) {
        ++c.no_error;
        std::printf("%-6u %-8s %-10s %12.4g %12.4g %10s %8s %6.2f  (%s)\n", seed,
                    effect.substr(0, 8).c_str(), w.name.c_str(), w.truth, pe->value, "none", "-", s,
                    pe->no_error.c_str());
        continue;
      }
      const double z = std::abs(pe->value - w.truth) / pe->std_error;
      c.covered += z <= 2.0;
      std::printf(
          "%-6u %-8s %-10s %12.4g %12.4g %10.3g %8.2f %6.2f  (path share %.3g, encoder share "
          "%.3g)%s\n",
          seed, effect.substr(0, 8).c_str(), w.name.c_str(), w.truth, pe->value, pe->std_error, z,
          s, pe->path_error, pe->encoder_error, z <= 2.0 ? "" : "  <-- outside 2 sigma");
    }
    std::fflush(stdout);
  }
  std::printf("\n%-14s %8s %12s %10s %10s %12s\n", "parameter", "records", "within 2 se", "share", "no error",
              "not found");
  for (const auto& [name, c] : counts) {
    const int with = c.n - c.no_error - c.not_found;
    std::printf("%-14s %8d %12d %9.0f%% %10d %12d\n", name.c_str(), c.n, c.covered,
                with > 0 ? 100.0 * c.covered / with : 0.0, c.no_error, c.not_found);
  }
  std::printf("%.1f s per record\n", total_s / std::max(records, 1));
  return 0;
}

// The generating model along the sampled validation path: what no fit of it can beat [N RMS].
double truth_along(const ModelParams& truth, const Dataset& val) {
  std::vector<double> g;
  simulate_along(*build_model(truth), val, g);
  double s2 = 0, n = 0;
  for (std::size_t i = 0; i < val.size(); ++i)
    if (val.use[i]) s2 += (val.F[i] - g[i]) * (val.F[i] - g[i]), n += 1;
  return n > 0 ? std::sqrt(s2 / n) : 0.0;
}

int run_self(const std::string& only, const std::string& presets_dir) {
  const char* presets[] = {"fig2a_presliding", "fig2c_periodic_1hz", "fig2c_periodic_0p1hz"};
  int n = 0, nothing = 0, base_ok = 0;
  double total_s = 0;
  std::printf("%-22s %7s %6s %11s %11s %11s %9s %-30s %6s\n", "preset", "samples", "noise", "truth N",
              "floor N", "base val N", "base/flr", "named", "s");
  for (const char* name : presets) {
    if (!only.empty() && only != name) continue;
    const Scenario sc = load_scenario(presets_dir + "/" + name + ".json");
    AssemblySimulation sim = one_body_simulation(sc);
    sim.run_to_end();
    const Trace& tr = sim.one_body_trace();
    double fmax = 0;
    for (double f : tr.friction) fmax = std::max(fmax, std::abs(f));
    for (std::size_t target : {std::size_t{1500}, std::size_t{6000}, tr.size()}) {
      const std::size_t every = std::max<std::size_t>(1, tr.size() / target);
      for (double noise : {0.0, 0.003}) {
        MeasuredRecord rec;
        rec.source = name;
        std::mt19937 rng(11);
        std::normal_distribution<double> N(0.0, 1.0);
        for (std::size_t i = 0; i < tr.size(); i += every) {
          rec.t.push_back(tr.t[i]);
          rec.x.push_back(tr.x[i]);
          rec.F.push_back(tr.friction[i] + noise * fmax * N(rng));
        }
        auto [train, val] = split_holdout(prepare_dataset(rec));
        FitSpec spec;
        spec.model = sc.friction.model;
        spec.elements = sc.friction.elements.size();
        const auto t0 = std::chrono::steady_clock::now();
        const IdentReport r = identify(train, val, spec, LoopOptions{});
        const double s = seconds_since(t0);
        total_s += s;
        std::string named;
        for (Effect e : r.effects_added) named += std::string(named.empty() ? "" : ",") + std::string(effect_name(e));
        const double ratio = r.rms_before_validation / r.ablation.floor;
        ++n;
        nothing += named.empty();
        base_ok += ratio <= 1.2;
        std::printf("%-22s %7zu %5.1f%% %11.3g %11.3g %11.3g %9.2f %-30s %6.2f\n", name, rec.t.size(), 100 * noise,
                    truth_along(sc.friction, val), r.ablation.floor, r.rms_before_validation, ratio,
                    named.empty() ? "nothing" : named.c_str(), s);
        std::fflush(stdout);
      }
    }
  }
  std::printf("\nnothing named in %d / %d; base fit within 1.2x the floor in %d / %d; %.1f s per record\n", nothing,
              n, base_ok, n, total_s / std::max(n, 1));
  return 0;
}

// A registry model with random parameters: each scalar its default times 3^U(-1, 1), kept inside
// its range; redrawn until the model's own checks pass. Element tables keep their defaults.
ModelParams draw_params(const ModelInfo& info, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int attempt = 0; attempt < 200; ++attempt) {
    ModelParams p = info.defaults();
    for (std::size_t i = 0; i < info.scalars.size(); ++i) {
      const ParamSpec& ps = info.scalars[i];
      double v = p.scalars[i];
      if (v > 0 && ps.key != "delta" && ps.key != "n" && ps.key != "a") v *= std::pow(3.0, U(rng));
      if (ps.key == "delta") v = 1.0 + 1.5 * (0.5 + 0.5 * U(rng));
      if (ps.allowed(v)) p.scalars[i] = v;
    }
    if (validate(p).empty()) return p;
  }
  return info.defaults();
}

std::string scalars_text(const ModelParams& p) {
  const ModelInfo& info = model_info(p.model);
  std::string out;
  char b[64];
  for (std::size_t i = 0; i < info.scalars.size() && i < p.scalars.size(); ++i) {
    std::snprintf(b, sizeof b, "%s%s=%.4g", out.empty() ? "" : " ",
                  std::string(info.scalars[i].key).c_str(), p.scalars[i]);
    out += b;
  }
  return out;
}

int run_registry(int records, unsigned seed0, std::size_t samples, const std::string& presets_dir,
                 bool detail, const std::string& only) {
  const Scenario base = load_scenario(presets_dir + "/fig2c_periodic_1hz.json");
  const std::vector<std::string> mismatch = {"lugre", "leuven", "maxwell_slip", "elastoplastic"};
  int n_self = 0, self_nothing = 0, self_base = 0, n_mis = 0, mis_named = 0, mis_floor = 0;
  double total_s = 0;
  std::printf("%-14s %-5s %-6s %11s %11s %9s %9s %-34s %6s\n", "model", "seed", "fit", "floor N",
              "base val N", "base/flr", "final/flr", "named", "s");
  for (const ModelInfo& info : model_registry()) {
    if (!only.empty() && only != info.tag) continue;
    for (int r = 0; r < records; ++r) {
      const unsigned seed = seed0 + static_cast<unsigned>(r);
      std::mt19937 rng(seed * 7919u + static_cast<unsigned>(info.tag.size()));
      Scenario sc = base;
      sc.friction = draw_params(info, rng);
      AssemblySimulation sim = one_body_simulation(sc);
      sim.run_to_end();
      const Trace& tr = sim.one_body_trace();
      double fmax = 0;
      for (double f : tr.friction) fmax = std::max(fmax, std::abs(f));
      const std::size_t every = std::max<std::size_t>(1, tr.size() / samples);
      MeasuredRecord rec;
      rec.source = std::string(info.tag);
      std::normal_distribution<double> N(0.0, 1.0);
      for (std::size_t i = 0; i < tr.size(); i += every) {
        rec.t.push_back(tr.t[i]);
        rec.x.push_back(tr.x[i]);
        rec.F.push_back(tr.friction[i] + 0.003 * fmax * N(rng));
      }
      auto [train, val] = split_holdout(prepare_dataset(rec));
      const double floor = truth_along(sc.friction, val);
      std::vector<std::string> fits = {std::string(info.tag)};
      if (std::find(mismatch.begin(), mismatch.end(), info.tag) != mismatch.end())
        fits.push_back("gms");
      for (const std::string& fit : fits) {
        FitSpec spec;
        spec.model = fit;
        spec.elements = fit == info.tag ? sc.friction.elements.size() : 4;
        const auto t0 = std::chrono::steady_clock::now();
        const IdentReport rep = identify(train, val, spec, LoopOptions{});
        const double s = seconds_since(t0);
        total_s += s;
        std::string named;
        for (Effect e : rep.effects_added)
          named += std::string(named.empty() ? "" : ",") + std::string(effect_name(e));
        const double base_ratio = rep.rms_before_validation / floor,
                     final_ratio = rep.rms_after_validation / floor;
        if (fit == info.tag) {
          ++n_self;
          self_nothing += named.empty();
          self_base += base_ratio <= 1.2;
        } else {
          ++n_mis;
          mis_named += !named.empty();
          mis_floor += final_ratio <= 1.5;
        }
        std::printf("%-14s %-5u %-6s %11.3g %11.3g %9.2f %9.2f %-34s %6.2f\n",
                    std::string(info.tag).c_str(), seed, fit == info.tag ? "self" : "gms", floor,
                    rep.rms_before_validation, base_ratio, final_ratio,
                    named.empty() ? "nothing" : named.c_str(), s);
        if (detail)
          std::printf("    truth  %s\n    base   %s\n    final  %s\n    optimum %s\n",
                      scalars_text(sc.friction).c_str(),
                      scalars_text(rep.stages.front().friction).c_str(),
                      scalars_text(rep.final_fit().friction).c_str(),
                      rep.optimum.verified ? "verified" : rep.optimum.reason.c_str());
        std::fflush(stdout);
      }
    }
  }
  std::printf(
      "\nself-consistency: nothing named in %d / %d, base fit within 1.2x the floor in %d / %d\n",
      self_nothing, n_self, self_base, n_self);
  std::printf(
      "structure mismatch (GMS on LuGre, Leuven, Maxwell-slip, elasto-plastic records): something "
      "named in "
      "%d / %d, final validation within 1.5x the generating model's floor in %d / %d\n",
      mis_named, n_mis, mis_floor, n_mis);
  std::printf("%.1f s per fit\n", total_s / std::max(n_self + n_mis, 1));
  return 0;
}

}  // namespace

// Periodic orbits of `records` random loops from `seed0` against their long simulations.
int run_cycles(int records, unsigned seed0) {
  cycles_study::print_header();
  int hunts = 0, rest = 0, excluded = 0, fn = 0, fp = 0, ok = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < records; ++i) {
    const unsigned seed = seed0 + static_cast<unsigned>(i);
    const cycles_study::CaseResult c = cycles_study::run_case(seed);
    cycles_study::print_case(seed, c);
    hunts += c.sim.state == cycles_study::SimState::Hunting;
    rest += c.sim.state == cycles_study::SimState::Rest;
    excluded += c.sim.state != cycles_study::SimState::Hunting &&
                c.sim.state != cycles_study::SimState::Rest;
    fn += c.false_negative, fp += c.false_positive, ok += c.agree;
    std::fflush(stdout);
  }
  std::printf(
      "loops %d: hunting %d, at rest %d, excluded (unsettled or diverged simulation) %d; agree %d, "
      "false negatives %d, false positives %d; %.1f s\n",
      records, hunts, rest, excluded, ok, fn, fp, seconds_since(t0));
  return 0;
}

int main(int argc, char** argv) {
  CLI::App app{"gmslab identification study on random records"};
  std::string mode = "base";
  int records = 50;
  unsigned seed = 1;
  std::size_t samples = 6000;
  bool auto_n = false, detail = false;
  int skip = 0;
  std::string report_dir;
  std::size_t screen = LoopOptions{}.screen_samples;
  app.add_option("mode", mode, "base | loop | self | coverage | registry | cycles | floor")
      ->check(CLI::IsMember({"base", "loop", "self", "coverage", "registry", "cycles", "floor"}));
  std::string preset;
  app.add_option("--preset", preset,
                 "self: only this preset (its name without .json); registry: only this model tag");
  app.add_option("--records", records, "number of records")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "first seed");
  app.add_option("--samples", samples, "samples per record")->check(CLI::Range(500, 1000000));
  app.add_flag("--auto", auto_n, "let the validation choose the element count (--elements auto)");
  app.add_flag("--detail", detail, "print the truth and the fitted parameters of each record");
  app.add_option("--skip", skip, "loop: start at this record index (seed + index; the index also sets the effects)")
      ->check(CLI::Range(0, 100000));
  app.add_option("--report-dir", report_dir,
                 "loop, coverage: write each record's report JSON into this folder");
  app.add_option("--screen-samples", screen,
                 "screen records of at least twice this many samples on every k-th (LoopOptions::screen_samples; 0: never)");
  bool no_bound = false;
  app.add_flag("--no-credit-bound", no_bound,
               "loop: run the rounds even where the credit bound would skip them "
               "(LoopOptions::credit_bound)");
  std::string effect;
  app.add_option(
      "--effect", effect,
      "loop: every record has this one generated effect (its catalog name, e.g. dwell_stiction), "
      "1.5-50x the noise");
  CLI11_PARSE(app, argc, argv);
  std::optional<GenEffect> only;
  if (!effect.empty()) {
    std::string names;
    for (int k = 0; k <= static_cast<int>(GenEffect::Backlash); ++k) {
      const char* name = gen_effect_name(static_cast<GenEffect>(k));
      names += std::string(names.empty() ? "" : ", ") + name;
      if (effect == name) only = static_cast<GenEffect>(k);
    }
    if (!only) {
      std::fprintf(stderr, "--effect %s: not a generated effect; one of: %s\n", effect.c_str(),
                   names.c_str());
      return 2;
    }
    if (mode != "loop") {
      std::fprintf(stderr, "--effect is for the loop mode only (mode %s)\n", mode.c_str());
      return 2;
    }
  }
  if (mode == "coverage") return run_coverage(records, seed, samples, report_dir);
  if (mode == "cycles") return run_cycles(records, seed);
  if (mode == "floor") return run_floor(records, seed, samples);
  if (mode == "self") return run_self(preset, GMSLAB_SOURCE_DIR "/presets");
  if (mode == "registry")
    return run_registry(records, seed, samples, GMSLAB_SOURCE_DIR "/presets", detail, preset);
  if (mode == "base") return run_base(records, seed, samples, auto_n, detail, screen);
  return run_loop(records, seed, samples, skip, report_dir, screen, only, !no_bound, detail);
}
