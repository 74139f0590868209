// One design job for every front end: for random designs (plants typed, a scenario's one body or
// an assembled plant; dominant roots, K, p/z bound, compensator type and sample time drawn over the
// Design tab's ranges, fixed seeds) the JSON of `gmslab design` is what the Design panel computes
// from the same settings (DesignSettings -> set_design_inputs -> compute_design): the lead report,
// the chosen compensator, the closed-loop poles, the frequency responses (continuous and sampled),
// the compensator type's sections, gain point and lag cost, the plant; and `--simulate` gives the
// metrics of the panel's own loops run over the CLI's duration and step. Python's gmslab.design
// equals the CLI's JSON (tests/python/test_gmslab.py, test_design_job_agrees_with_the_cli).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/control/design_json.hpp"
#include "core/control/design_report.hpp"
#include "core/control/design_settings.hpp"
#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/core/run_cli.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
using gmslab::test_util::run_cli;

const std::string kFig4 = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json";
const std::string kTwoMass = std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json";

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// A random plant b (polynomial of degree <= n - 1) / (s^k a(s)) with a of degree n - k, stable
// coefficients a_i > 0 over three decades: type k in {0, 1, 2}.
void random_typed_plant(std::mt19937& rng, PlantChoice& p) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto coef = [&] { return std::pow(10.0, -1.0 + 3.0 * u(rng)); };
  const int n = 1 + static_cast<int>(rng() % 3), k = static_cast<int>(rng() % 3);
  std::string den = "1", nums;
  for (int i = 0; i < n; ++i) den += " " + num(coef());
  for (int i = 0; i < k; ++i) den += " 0";
  const int m = static_cast<int>(rng() % static_cast<unsigned>(n));  // deg num < deg den
  for (int i = 0; i <= m; ++i) nums += (i ? " " : "") + num(coef());
  p.source = PlantSource::Typed;
  p.num = nums;
  p.den = den;
}

struct Draw {
  DesignSettings s;
  std::vector<std::string> cli;  // the CLI's arguments for the same design
};

Draw random_draw(std::mt19937& rng, int i) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Draw d;
  DesignSettings& s = d.s;
  const int source = i % 3;  // typed, scenario, assembly
  if (source == 0) {
    random_typed_plant(rng, s.plant);
    d.cli = {"--num", s.plant.num, "--den", s.plant.den};
  } else if (source == 1) {
    s.plant.source = PlantSource::Scenario;
    d.cli = {"--preset", kFig4};
  } else {
    s.plant.source = PlantSource::Assembly;
    s.plant.output = u(rng) < 0.5 ? "x.motor" : "x.load";
    d.cli = {"--preset", kTwoMass, "--output", s.plant.output};
  }
  s.regime = u(rng) < 0.5 ? "presliding" : "sliding";
  s.zeta = 0.02 + 0.96 * u(rng);
  // wn over (0, 1e5] on a log scale; near the mechanical plants' own frequencies for the presets.
  s.wn = source == 0 ? std::pow(10.0, -1.0 + 4.0 * u(rng)) : std::pow(10.0, 0.5 + 2.0 * u(rng));
  s.use_K = u(rng) < 0.5;
  s.K = std::pow(10.0, -1.0 + 5.0 * u(rng));
  s.max_ratio = 1.5 + 98.5 * u(rng);
  const CompensatorType types[] = {CompensatorType::Lead, CompensatorType::Lag, CompensatorType::LeadLag,
                                   CompensatorType::PI, CompensatorType::PID};
  s.compensator = types[rng() % 5];
  s.sample_time = u(rng) < 0.3 ? std::pow(10.0, -4.0 + 2.0 * u(rng)) : 0.0;
  d.cli.insert(d.cli.end(), {"--regime", s.regime, "--zeta", num(s.zeta), "--wn", num(s.wn), "--max-ratio",
                             num(s.max_ratio), "--sample-time", num(s.sample_time)});
  if (s.use_K) d.cli.insert(d.cli.end(), {"--K", num(s.K)});
  if (s.compensator != CompensatorType::Lead) d.cli.insert(d.cli.end(), {"--compensator", to_string(s.compensator)});
  return d;
}

// The panel's inputs for the settings, as the Design panel builds them.
DesignInputs panel_inputs(const DesignSettings& s, const Scenario& sc, const AssemblyScenario& a) {
  DesignInputs in;
  in.scenario = sc;
  in.assembly = a;
  set_design_inputs(s, in);
  return in;
}

int run_design(std::vector<std::string> args, const std::string& out) {
  std::filesystem::remove(out);
  args.insert(args.begin(), "design");
  args.insert(args.end(), {"--json", out});
  return run_cli(args);
}
}  // namespace

TEST(DesignJobAgreement, CliJsonIsThePanelsDesignForRandomDesigns) {
  const Scenario sc = load_scenario(kFig4);
  const AssemblyScenario two = load_assembly_scenario(kTwoMass);
  const std::string out = (std::filesystem::temp_directory_path() / "gmslab_design_agreement.json").string();
  std::mt19937 rng(2026);
  int compared = 0, failed = 0;
  for (int i = 0; i < 24; ++i) {
    const Draw d = random_draw(rng, i);
    const DesignInputs in = panel_inputs(d.s, sc, two);
    const DesignOutputs panel = compute_design(in);
    const int rc = run_design(d.cli, out);
    const std::string what = "draw " + std::to_string(i) + ": " + panel.error;
    if (rc != 0) {  // the CLI fails exactly where the panel's design job does, with the kind's code
      ++failed;
      ASSERT_TRUE(panel.failure_kind.has_value()) << what;
      EXPECT_EQ(rc, exit_code(*panel.failure_kind)) << what;
      continue;
    }
    ++compared;
    const nlohmann::json j = nlohmann::json::parse(read_file(out));
    // The lead report: every key of the panel's report as the CLI writes it (the chosen lead
    // overrides the design keys when it is not the requested one). The panel keeps no report when
    // its compensator type cannot be built (then the type's error below is the panel's).
    ASSERT_TRUE(panel.report.has_value() || d.s.compensator != CompensatorType::Lead) << what;
    if (panel.report) {
      const nlohmann::json r = to_json(*panel.report);
      const auto chosen = chosen_lead(*panel.report);
      for (const auto& [key, value] : r.items()) {
        const bool overridden = chosen && !panel.report->design &&
                                (key == "z" || key == "p" || key == "Kc" || key == "K" || key == "closed_loop_poles");
        if (!overridden) {
          EXPECT_EQ(j.at(key), value) << what << " key " << key;
        }
      }
    }
    EXPECT_EQ(j.at("plant").at("num"), panel.plant.g.num.descending_coeffs()) << what;
    EXPECT_EQ(j.at("plant").at("den"), panel.plant.g.den.descending_coeffs()) << what;
    EXPECT_EQ(j.at("plant").at("label"), panel.plant_label) << what;
    if (d.s.compensator == CompensatorType::Lead) {
      // The lead the panel uses is the CLI's chosen design, with the same loop's responses.
      ASSERT_EQ(j.contains("compensator"), panel.compensator.has_value()) << what;
      EXPECT_EQ(j.at("frequency").at("loop"), panel.compensator ? "compensated" : "plant") << what;
      ASSERT_TRUE(panel.frequency.has_value()) << what;
      nlohmann::json f = j.at("frequency");
      f.erase("loop");
      f.erase("discrete");
      EXPECT_EQ(f, to_json(*panel.frequency)) << what;
      if (!panel.compensator) continue;
      EXPECT_EQ(j.at("design_kind"), panel.compensator_kind) << what;
      EXPECT_EQ(j.at("compensator"), compensator_json(*panel.compensator)) << what;
      if (panel.discrete) {
        EXPECT_EQ(j.at("frequency").at("discrete"), to_json(*panel.discrete)) << what;
        EXPECT_EQ(j.at("z_locus"), to_json(*panel.z_locus, panel.compensator->Kc)) << what;
      }
    } else {
      // The compensator type: the panel's compensator, kind, closed-loop poles, gain point, lag cost.
      const nlohmann::json& t = j.at("typed_compensator");
      EXPECT_EQ(t.at("kind"), panel.compensator_kind) << what;
      // The same design failure (the panel may add a failure of a drawing the report does not make).
      const std::string terr = t.at("error").get<std::string>();
      EXPECT_EQ(panel.error.rfind(terr, 0), 0u) << what << " / " << terr;
      EXPECT_EQ(panel.error.rfind("design:", 0) == 0, terr.rfind("design:", 0) == 0) << what << " / " << terr;
      ASSERT_EQ(t.contains("compensator"), panel.compensator.has_value()) << what;
      if (panel.compensator) {
        EXPECT_EQ(t.at("compensator"), compensator_json(*panel.compensator)) << what;
        EXPECT_EQ(t.at("closed_loop_poles"), poles_json(panel.closed_loop_poles)) << what;
      }
      EXPECT_EQ(t.contains("gain_point"), panel.gain_point.has_value()) << what;
      if (panel.gain_point) {
        EXPECT_EQ(t.at("gain_point").at("Kc").get<double>(), panel.gain_point->k) << what;
      }
      EXPECT_EQ(t.contains("lag"), panel.lag.has_value()) << what;
      if (panel.lag) {
        EXPECT_EQ(t.at("lag").at("K_without_lag").get<double>(), panel.lag->K_gain_only) << what;
      }
    }
  }
  EXPECT_GE(compared, 16) << failed << " draws failed";
  std::filesystem::remove(out);
}

// --simulate runs the panel's loops: the panel's inputs for the same settings with the CLI's duration,
// step and compensations give the CLI's metrics bit for bit (and, driven by the measured velocity, the
// compensated loops' describing-function predictions at the report's accuracy).
TEST(DesignJobAgreement, CliSimulateIsThePanelsLoopOverTheCliTiming) {
  const Scenario sc = load_scenario(kFig4);
  const AssemblyScenario two = load_assembly_scenario(kTwoMass);
  const std::string out = (std::filesystem::temp_directory_path() / "gmslab_design_agreement_sim.json").string();
  std::mt19937 rng(2027);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int compared = 0;
  for (int i = 0; i < 8; ++i) {
    DesignSettings s;
    const bool assembled = i % 2;
    s.plant.source = assembled ? PlantSource::Assembly : PlantSource::Scenario;
    s.regime = "sliding";
    s.zeta = 0.5 + 0.3 * u(rng);
    s.wn = assembled ? 5.0 + 10.0 * u(rng) : 40.0 + 40.0 * u(rng);
    const CompensatorType types[] = {CompensatorType::Lead, CompensatorType::PI, CompensatorType::PID,
                                     CompensatorType::LeadLag};
    s.compensator = types[(i / 2) % 4];
    s.reference = DesignReference::Step;
    s.amplitude = 1e-3 * (1.0 + 4.0 * u(rng));
    s.feedforward_source = u(rng) < 0.5 ? FeedforwardSource::Measured : FeedforwardSource::Reference;
    s.mismatch_force = 0.8 + 0.4 * u(rng);
    const double duration = 0.2;
    std::vector<std::string> args = {"--preset", assembled ? kTwoMass : kFig4, "--regime", "sliding", "--zeta",
                                     num(s.zeta), "--wn", num(s.wn), "--simulate", "--reference", "step",
                                     "--amplitude", num(s.amplitude), "--duration", num(duration), "--feedforward",
                                     to_string(s.feedforward_source), "--mismatch-force", num(s.mismatch_force)};
    if (s.compensator != CompensatorType::Lead) args.insert(args.end(), {"--compensator", to_string(s.compensator)});
    DesignInputs in = panel_inputs(s, sc, two);
    in.loop_timing = LoopTiming{duration, 0.0, 10};
    in.loop_compensations = {Compensation::None, Compensation::Coulomb, Compensation::Gms};
    in.accuracy = Accuracy::Report;
    const DesignOutputs panel = compute_design(in);
    const int rc = run_design(args, out);
    if (!panel.compensator) {
      EXPECT_EQ(rc, 2) << i << ": " << panel.error;
      continue;
    }
    ASSERT_EQ(rc, 0) << i << ": " << panel.error;
    ASSERT_TRUE(panel.error.empty()) << i << ": " << panel.error;
    const nlohmann::json j = nlohmann::json::parse(read_file(out));
    const nlohmann::json& sim = j.at("simulation");
    ASSERT_EQ(sim.size(), panel.loops.size()) << i;
    for (std::size_t k = 0; k < sim.size(); ++k) {
      const LoopRun& run = panel.loops[k];
      EXPECT_EQ(sim[k].at("compensation"), to_string(run.compensation)) << i;
      EXPECT_FALSE(run.trace.t.empty()) << i;
      nlohmann::json metrics = sim[k];
      for (const char* key : {"compensation", "feedforward_source", "limit_cycles"}) metrics.erase(key);
      EXPECT_EQ(metrics, to_json(run.metrics)) << i << " " << to_string(run.compensation);
      if (sim[k].contains("limit_cycles")) {
        EXPECT_EQ(sim[k].at("limit_cycles"), to_json(*run.limit_cycles)) << i;
      }
      EXPECT_EQ(sim[k].contains("limit_cycles"), !assembled && run.compensation != Compensation::None &&
                                                     s.feedforward_source == FeedforwardSource::Measured)
          << i;
    }
    ++compared;
  }
  EXPECT_GE(compared, 6);
  std::filesystem::remove(out);
}
