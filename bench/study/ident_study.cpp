// gmslab identification study: random records from an independent GMS implementation
// (tests/ident/random_records.hpp), fitted by gmslab, scored against the floor that noise and
// encoder quantisation alone leave (the true model evaluated along the measured positions).
//
//   gmslab_study base    [--records 50] [--seed 1] [--samples 6000]   base fit, no effect
//   gmslab_study loop    [--records 50] ...   the residual loop on records with 0, 1 or 2 effects
//
// Prints one row per record and a summary; exit 0 (it reports, it does not judge).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>

#include "core/ident/element_fit.hpp"
#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"

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

int run_base(int records, unsigned seed0, std::size_t samples, bool auto_n, bool detail) {
  int pass = 0;
  double worst = 0, total_s = 0;
  std::printf("%-4s %-68s %10s %10s %6s %5s %6s\n", "rec", "truth", "floor", "val RMS", "ratio", "N fit", "s");
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
    const auto rep = identify(train, val, spec, lo);
    const double s = seconds_since(t0);
    total_s += s;
    const double ratio = rep.rms_after_validation / floor;
    worst = std::max(worst, ratio);
    pass += ratio <= 1.2;
    std::printf("%-4u %-68s %10.4g %10.4g %6.3f %5zu %6.2f\n", seed, truth_line(tr).c_str(), floor,
                rep.rms_after_validation, ratio, rep.final_fit().spec.elements, s);
    if (detail) {
      std::printf("  truth: Fs %.4g Fc %.4g Vs %.3g delta %.3g C %.4g sigma2 %.4g | elements (alpha, x_ba um):",
                  tr.Fs, tr.Fc, tr.Vs, tr.delta, tr.C, tr.sigma2);
      for (std::size_t e = 0; e < tr.elements(); ++e) std::printf(" (%.3f, %.3g)", tr.alpha[e], 1e6 * tr.x_break(e));
      const auto& f = rep.final_fit().friction;
      std::printf("\n  fit:  ");
      for (std::size_t j = 0; j < f.scalars.size(); ++j) std::printf(" %.4g", f.scalars[j]);
      std::printf(" | elements (alpha, x_ba um at Fs):");
      const double fs = f.model == "gms" ? f.scalar("Fs") : 1.0;
      for (const auto& row : f.elements) std::printf(" (%.3f, %.3g)", row[0], 1e6 * row[0] * fs / row[1]);
      std::printf("\n  train rms %.4g, noise sd %.4g\n", rep.rms_after_train, tr.noise);
    }
    std::fflush(stdout);
  }
  std::printf("\nbase fit: %d / %d records within 1.2x the floor (%.0f %%); worst %.3f; %.1f s per record\n",
              pass, records, 100.0 * pass / records, worst, total_s / records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gmslab identification study on random records"};
  std::string mode = "base";
  int records = 50;
  unsigned seed = 1;
  std::size_t samples = 6000;
  bool auto_n = false, detail = false;
  app.add_option("mode", mode, "base | loop")->check(CLI::IsMember({"base", "loop"}));
  app.add_option("--records", records, "number of records")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "first seed");
  app.add_option("--samples", samples, "samples per record")->check(CLI::Range(500, 1000000));
  app.add_flag("--auto", auto_n, "let the validation choose the element count (--elements auto)");
  app.add_flag("--detail", detail, "print the truth and the fitted parameters of each record");
  CLI11_PARSE(app, argc, argv);
  if (mode == "base") return run_base(records, seed, samples, auto_n, detail);
  return run_base(records, seed, samples, auto_n, detail);
}
