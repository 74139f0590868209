// gmslab identify --data TRAIN.csv [--validate VAL.csv] [--columns ...] [--force applied] [--model gms]
//   [--elements 4] [--mask t0:t1,...] --report REPORT.json [--plot REPORT.png]
// Fits the model, runs the residual loop (core/ident/loop.hpp), writes the report JSON, the
// identified model as a scenario preset, and optionally the report figure as PNG (drawn by
// gmslab-headless from the figure's JSON). Progress goes to stderr.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <climits>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>

#include "app/cli/cli.hpp"
#include "core/error.hpp"
#include "core/ident/figure_json.hpp"
#include "core/ident/job.hpp"
#include "core/ident/loop.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"

extern char** environ;

namespace gmslab::cli {

namespace {

// The ablation table: validation RMS with all named effects and with each left out (and what
// was dropped), so a user sees why each effect is named.
void print_ablation(const ident::Ablation& a) {
  if (!a.ran) return;
  std::fprintf(stdout, "  ablation (validation RMS with all named effects %.4g N; floor %.3g N):\n",
               a.rms_validation_all, a.floor);
  auto row = [](const ident::AblationRow& r) {
    std::fprintf(stdout, "    without %-20s %11.4g N  z %7.3g  contribution %9.3g N  %s\n",
                 std::string(ident::effect_name(r.effect)).c_str(), r.rms_validation_without,
                 r.test.z, r.contribution,
                 r.credited               ? "credited"
                 : r.explained_by_element ? "dropped (alike: one more element)"
                                          : "dropped");
    if (r.more_elements > 0)
      std::fprintf(stdout, "      with %zu elements in its place     %11.4g N  z %7.3g\n",
                   r.more_elements, r.rms_validation_more_elements, r.more_elements_test.z);
  };
  for (const auto& r : a.rows) row(r);
  for (const auto& r : a.dropped) row(r);
}


// The job's own fields and defaults (core/ident/job.hpp), plus what only the CLI has.
struct IdentifyOptions {
  ident::IdentifyJob job;
  std::string columns, force, mask_edges, elements = "4", effects, compare;
  std::string report, plot, scenario, size = "1600x1000";
};

std::string self_dir() {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  const std::string self(buf, static_cast<std::size_t>(n));
  return self.substr(0, self.rfind('/') + 1);
}

// Runs gmslab-headless plot-figure FIGURE.json --out PNG --size WxH; returns its exit code.
int render_png(const std::string& figure_json, const std::string& png, const std::string& size) {
  std::string exe = self_dir() + "gmslab-headless";
  if (access(exe.c_str(), X_OK) != 0) exe = "gmslab-headless";
  std::vector<std::string> args = {exe, "plot-figure", figure_json, "--out", png, "--size", size};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = exe.find('/') != std::string::npos
                     ? posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ)
                     : posix_spawnp(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ);
  if (rc != 0) {
    std::cerr << "gmslab: cannot run " << exe << ": " << std::strerror(rc) << '\n';
    return 127;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

std::string stem_path(const std::string& path, const std::string& suffix) {
  std::filesystem::path p(path);
  p.replace_extension();
  return p.string() + suffix;
}

int run_identify(const IdentifyOptions& o) {
  ident::IdentifyJob job = o.job;
  job.train.columns = job.validation.columns = o.columns;
  job.train.force = job.validation.force = o.force;
  job.train.mask_edges = job.validation.mask_edges = o.mask_edges;
  job.validation.mask_what = "--validate-mask";
  job.spec.elements = ident::parse_element_count(o.elements);
  if (!o.compare.empty()) job.compare = ident::parse_model_list(o.compare);  // fail before the run
  std::size_t a = 0;
  while (a < o.effects.size()) {
    auto b = o.effects.find(',', a);
    if (b == std::string::npos) b = o.effects.size();
    if (b > a) job.candidates.push_back(ident::effect_from_name(o.effects.substr(a, b - a)));
    a = b + 1;
  }
  // Progress on stderr: rewritten in place (carriage returns) on a terminal; in a file or pipe,
  // one full line per stage, with the stage's last count and RMS.
  const bool tty = isatty(STDERR_FILENO) != 0;
  std::string last_stage, last_line;
  auto progress = [&](const ident::FitProgress& p) {
    char line[256];
    std::snprintf(line, sizeof line, "  %s: %zu evaluations, RMS %.6g N", p.stage.c_str(),
                  static_cast<std::size_t>(p.evaluations), p.best_rms);
    if (tty) {
      if (p.stage != last_stage) std::cerr << '\n';
      std::cerr << '\r' << line << "   " << std::flush;
    } else if (p.stage != last_stage && !last_line.empty()) {
      std::cerr << last_line << '\n';
    }
    last_stage = p.stage;
    last_line = line;
  };
  auto out = ident::run_identification(job, progress);
  if (!tty && !last_line.empty()) std::cerr << last_line << '\n';
  for (const auto& n : out.notes) std::cerr << "identify: " << n << '\n';
  const ident::Dataset& train = out.train;
  const ident::Dataset& val = out.validation;
  auto& rep = out.report;
  if (tty) std::cerr << '\n';  // ends the rewritten progress line
  if (!rep.comparison.empty()) {
    std::cout << "\nmodel comparison (each with the effects added: " << rep.effects_added.size() << ")\n";
    std::fprintf(stdout, "  %-14s %8s %8s %14s %19s %9s\n", "model", "elements", "shape", "RMS train [N]",
                 "RMS validation [N]", "time [s]");
    for (const auto& c : rep.comparison)
      std::fprintf(stdout, "  %-14s %8zu %8zu %14.4g %19.4g %9.1f%s\n", c.model.c_str(), c.elements,
                   c.shape_parameters, c.rms_train, c.rms_validation, c.seconds,
                   c.time_limited ? "  (time limit: not converged)" : "");
  }
  nlohmann::json j = to_json(rep);
  const std::string scenario = o.scenario.empty() ? stem_path(o.report, ".scenario.json") : o.scenario;
  j["scenario_file"] = scenario;
  save_scenario(ident::identified_scenario(rep, train), scenario);
  write_file_atomic(o.report, j.dump(2) + "\n");
  std::cout << "identify: " << train.source << " (" << train.used() << " samples used";
  if (rep.screen_every > 1) std::cout << "; " << ident::screen_summary(rep);
  std::cout << "), validation " << val.source << " (" << val.used() << ")\n";
  std::cout << "identify: " << rep.model << ", " << rep.final_fit().spec.elements
            << " elements; validation RMS " << rep.rms_before_validation << " -> "
            << rep.rms_after_validation << " N; ";
  if (rep.effects_added.empty())
    std::cout << ident::nothing_added(rep);
  else {
    std::cout << "effects added: " << ident::named_effects(rep.ablation, rep.effects_added);
    if (const std::string more = ident::more_elements_summary(rep.ablation); !more.empty())
      std::cout << "; " << more;
  }
  std::cout << '\n';
  print_ablation(rep.ablation);
  std::cout << "  " << rep.discovery.summary << '\n';
  if (!rep.optimum.verified)
    std::cout << "  not converged: " << rep.optimum.reason << "; no standard errors\n";
  for (const auto& p : rep.parameters) {
    if (std::isfinite(p.std_error)) {
      std::fprintf(stdout, "  %s.%s = %.4g +- %.2g %s", p.effect.c_str(), p.name.c_str(), p.value,
                   p.std_error, p.unit.c_str());
      if (p.path_error > 0 || p.encoder_error > 0)
        std::fprintf(stdout,
                     " (of which the path between samples +- %.2g, the encoder step +- %.2g)",
                     p.path_error, p.encoder_error);
      std::fputc('\n', stdout);
    } else
      std::fprintf(stdout, "  %s.%s = %.4g %s (no standard error: %s)\n", p.effect.c_str(),
                   p.name.c_str(), p.value, p.unit.c_str(), p.no_error.c_str());
  }
  for (const auto& p : rep.ripples.peaks)
    std::fprintf(stdout, "  ripple in the base residual: wavelength %.4g mm, amplitude %.3g N, false-alarm probability %.2g\n",
                 p.wavelength * 1e3, p.amplitude, p.false_alarm);
  for (const auto& n : rep.notes) std::cerr << "  note: " << n << '\n';
  std::cout << "  validation " << rep.remaining.summary << '\n';
  std::cout << "wrote " << o.report << " and " << scenario << '\n';
  if (!o.plot.empty()) {
    int w = 0, h = 0;
    parse_size(o.size, w, h);
    const std::string fig = stem_path(o.plot, ".figure.json");
    save_figure_json(ident::report_figure(rep, train, val), fig);
    const int rc = render_png(fig, o.plot, o.size);
    if (rc != 0) {
      std::cerr << "gmslab: the report figure could not be drawn (gmslab-headless plot-figure "
                   "exited with "
                << rc << "); its data is in " << fig << '\n';
      return 1;
    }
    std::cout << "wrote " << o.plot << '\n';
  }
  return 0;
}

}  // namespace

void register_identify(CLI::App& app, Action& action) {
  // Owned by the app (its callbacks hold it): each Cli has its own options.
  auto o = std::make_shared<IdentifyOptions>();
  auto* sub = app.add_subcommand(
      "identify",
      "Fit a friction model to measured data, then find the effects it lacks (residual loop)");
  sub->add_option("--data", o->job.train.path, "Training record (CSV: t, x, F [, v, Fn], units in the header)")
      ->required();
  sub->add_option("--validate", o->job.validation.path,
                  "Validation record (CSV); default: a hold-out part of --data");
  sub->add_option("--columns", o->columns, "Explicit columns: CSV header names or 1-based positions (t=1,x=2,F=4), MATLAB variables (t=time,x=q,F=force) or matrix columns (t=data:1,x=data:2,F=data:4)");
  sub->add_option("--force", o->force,
                  "Which force of a gmslab simulate trace is F: friction (F_friction_N, the default) or applied "
                  "(F_applied_N)")
      ->check(CLI::IsMember({"friction", "applied"}));
  sub->add_option("--model", o->job.spec.model, "Base friction model (registry tag)")->capture_default_str();
  sub->add_option("--elements", o->elements,
                  "Element count of multi-element models (1..64), or 'auto': the validation record "
                  "chooses (GMS, Maxwell-slip)")
      ->capture_default_str();
  sub->add_option("--mask", o->job.train.mask, "Time windows of --data to ignore, t0:t1,... [s]");
  sub->add_option("--validate-mask", o->job.validation.mask, "Time windows of --validate to ignore [s]");
  sub->add_option("--mask-edges", o->mask_edges,
                  "COLUMN:BEFORE:AFTER [s]: ignore windows around every change of COLUMN "
                  "(e.g. pulse_code:0.005:0.060)");
  sub->add_option("--holdout", o->job.holdout, "Fraction held out for validation without --validate")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 0.5));
  sub->add_option("--compare", o->compare,
                  "Also fit these models (comma-separated tags, or 'all') with the effects found, and "
                  "report their RMS (model_comparison)");
  sub->add_option("--compare-seconds", o->job.compare_seconds, "Time limit of each comparison fit [s]")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  sub->add_option("--method", o->job.method, "Optimiser: bobyqa, sbplx or neldermead")
      ->capture_default_str()
      ->check(CLI::IsMember({"bobyqa", "sbplx", "neldermead"}));
  sub->add_option("--starts", o->job.starts, "Starts of the base fit")->capture_default_str()->check(CLI::Range(1, 50));
  sub->add_option("--max-evals", o->job.max_evaluations, "Cost evaluations per start")
      ->capture_default_str()
      ->check(CLI::Range(20, 100000));
  sub->add_option("--min-gain", o->job.min_gain,
                  "Relative validation RMS drop needed to keep an effect [-]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.9));
  sub->add_option("--effects", o->effects, "Candidate effects (comma-separated; default: all)");
  sub->add_option("--report", o->report, "Report JSON to write")->required();
  sub->add_option("--scenario", o->scenario,
                  "Scenario preset of the identified model (default: REPORT stem + .scenario.json)");
  sub->add_option("--plot", o->plot, "Report figure PNG (drawn by gmslab-headless)");
  sub->add_option("--size", o->size, "PNG size WIDTHxHEIGHT")->capture_default_str();
  // Defaults again at every parse of this command (a Cli may be run many times).
  sub->preparse_callback([o](std::size_t) { *o = IdentifyOptions{}; });
  sub->callback([&action, o] { action = [o] { return run_identify(*o); }; });
}

}  // namespace gmslab::cli
