// gmslab design --compensator TYPE --simulate: the loop simulated is the one of the chosen type
// (lag, lead-lag, PI, PID), not the lead. Frictionless assembled plants (one body, damper, spring,
// no contact): the metrics equal those of the linear closed-loop step of the exported compensator
// (core/control/linear_response, an independent computation) within a tolerance that shrinks with
// dt; with friction (Fig. 4's GMS one-body plant, every compensation, both feedforward sources) the
// CLI's metrics equal a direct call of the core loop simulation with the JSON's compensator.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "app/cli/cli.hpp"
#include "core/control/design_json.hpp"
#include "core/control/linear_response.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "tests/core/run_cli.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
using gmslab::test_util::run_cli;

std::string temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("gmslab_design_sim_" + name)).string();
}

nlohmann::json design(std::vector<std::string> args, const std::string& name) {
  const std::string out = temp(name + ".json");
  std::filesystem::remove(out);
  args.insert(args.begin(), "design");
  args.push_back("--json");
  args.push_back(out);
  EXPECT_EQ(run_cli(args), 0);
  return nlohmann::json::parse(read_file(out));
}

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// The compensator of a typed_compensator JSON: Kc and its sections.
LeadCompensator compensator_of(const nlohmann::json& t) {
  const auto& c = t.at("compensator");
  const auto& s = c.at("sections");
  LeadCompensator C{c.at("Kc").get<double>(), s[0].at("z").get<double>(), s[0].at("p").get<double>()};
  if (s.size() > 1) C.second = Section{s[1].at("z").get<double>(), s[1].at("p").get<double>()};
  return C;
}
}  // namespace

TEST(DesignCliSimulate, EachCompensatorTypeOnAFrictionlessPlantFollowsTheLinearClosedLoop) {
  std::mt19937 rng(1240);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const char* types[] = {"pi", "pid", "lag", "lead_lag"};
  for (int i = 0; i < 8; ++i) {
    const std::string type = types[i % 4];
    // k: open-loop damping ratio c / (2 sqrt(m k)) in [1.1, 2.2], so the gain alone reaches zeta = 0.6.
    const double m = 0.5 + 1.5 * u(rng), c = 10 + 30 * u(rng), k = i % 2 ? 0.0 : (0.05 + 0.15 * u(rng)) * c * c / m;
    AssemblyScenario a;
    a.name = "frictionless";
    a.plant.bodies = {{"mass", m}};
    a.plant.dampers = {{"d", 0, kGround, c}};
    if (k > 0) a.plant.springs = {{"k", 0, kGround, k}};
    a.plant.drives = {{"force", DrivePart::Kind::Force, 0, Signal::constant(0.0)}};
    const std::string preset = temp("plant" + std::to_string(i) + ".json");
    save_assembly_scenario(a, preset);
    // The damped mass's own locus crosses zeta 0.6 near c / (2 m zeta): the lag's and PI's gain point.
    const double zeta = 0.6, wn = (1.0 + u(rng)) * c / (2 * m * zeta);
    const double amp = 1e-3 * (1 + 9 * u(rng)), duration = 4.0;
    auto run = [&](double dt) {
      return design({"--preset", preset, "--zeta", num(zeta), "--wn", num(wn), "--compensator", type, "--simulate",
                     "--compensation", "none", "--reference", "step", "--amplitude", num(amp), "--duration",
                     num(duration), "--dt", num(dt)},
                    "frictionless");
    };
    const auto j1 = run(2e-5), j2 = run(1e-5);
    ASSERT_TRUE(j2.contains("typed_compensator")) << type;
    ASSERT_TRUE(j2["typed_compensator"].contains("compensator")) << type << ": " << j2["typed_compensator"]["error"];
    const LeadCompensator C = compensator_of(j2["typed_compensator"]);
    EXPECT_EQ(C.sections(), type == "pi" || type == "lag" ? 1 : 2) << type;
    if (type == "pi" || type == "pid") {
      EXPECT_EQ(C.section(C.sections() - 1).p, 0.0) << type;
    }
    // The linear loop sampled as the loop records (every 10th step of dt): its metrics.
    const TransferFunction T = closed_loop({Poly({1.0}), Poly({k, c, m})}, C);
    auto linear_metrics = [&](double dt) {
      const long long steps = std::llround(duration / dt);
      const int n = static_cast<int>(steps / 10) + 1;
      const StepResponse lin = step_response(T, duration, n);
      LoopTrace tr;
      tr.t = lin.t;
      tr.r.assign(lin.t.size(), amp);
      tr.r[0] = amp;
      for (double y : lin.y) tr.x.push_back(amp * y);
      return loop_metrics(tr);
    };
    const auto diff = [&](const nlohmann::json& j, double dt) {
      const auto& s = j["simulation"][0];
      const LoopMetrics l = linear_metrics(dt);
      EXPECT_EQ(s["compensation"], "none");
      return std::array<double, 3>{std::abs(s["rms_error_m"].get<double>() - l.rms_error) / amp,
                                   std::abs(s["overshoot_percent"].get<double>() - l.overshoot),
                                   std::abs(s["steady_state_error_m"].get<double>() - l.steady_state_error) / amp};
    };
    const auto d1 = diff(j1, 2e-5), d2 = diff(j2, 1e-5);
    // rms and overshoot: first order in dt (halving dt halves the distance); tolerance 5 dt wn.
    EXPECT_LT(d2[0], 5 * 1e-5 * wn) << type << " rms";
    EXPECT_LT(d2[1], 100 * 5 * 1e-5 * wn) << type << " overshoot [%]";
    EXPECT_LT(d2[2], 5 * 1e-5 * wn) << type << " e_ss";
    EXPECT_LT(d2[0], 0.7 * d1[0] + 1e-9) << type << ": rms distance " << d1[0] << " -> " << d2[0];
    std::filesystem::remove(preset);
  }
}

TEST(DesignCliSimulate, WithFrictionTheCliRunsTheCoreLoopWithTheTypedCompensator) {
  const std::string preset = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json";
  const Scenario sc = load_scenario(preset);
  for (const char* type : {"pi", "pid", "lead_lag", "lag"})
    for (const char* source : {"reference", "measured"}) {
      const auto j = design({"--preset", preset, "--regime", "sliding", "--zeta", "0.7", "--wn", "60",
                             "--compensator", type, "--simulate", "--reference", "step", "--amplitude", "0.002",
                             "--duration", "0.5", "--feedforward", source, "--mismatch-force", "0.9"},
                            "fig4");
      ASSERT_TRUE(j["typed_compensator"].contains("compensator")) << type << ": " << j["typed_compensator"]["error"];
      const LeadCompensator C = compensator_of(j["typed_compensator"]);
      ASSERT_EQ(j["simulation"].size(), 3u);
      for (const auto& s : j["simulation"]) {
        LoopConfig cfg;
        cfg.reference = Signal::constant(0.002);
        cfg.C = C;
        cfg.comp = compensation_from_string(s["compensation"].get<std::string>());
        cfg.feedforward_source = *feedforward_source_from_string(source);
        cfg.mismatch.force = 0.9;
        cfg.dt = sc.run.dt;
        cfg.duration = 0.5;
        nlohmann::json expect = to_json(loop_metrics(simulate_loop(sc, cfg)));
        expect["compensation"] = s["compensation"];
        if (cfg.comp != Compensation::None) expect["feedforward_source"] = source;
        // Driven by the measured velocity: the compensated loop's describing-function prediction
        // (F - F_hat) beside its simulated metrics.
        if (cfg.comp != Compensation::None && cfg.feedforward_source == FeedforwardSource::Measured)
          expect["limit_cycles"] =
              to_json(predict_limit_cycles(compensated_friction(sc.friction, cfg.comp, cfg.mismatch), sc.plant, C));
        EXPECT_EQ(s, expect) << type << " " << source;
      }
      // The compensator simulated is not the lead: its loop differs from the lead's.
      if (std::string(source) == "reference") {
        const auto lead = design({"--preset", preset, "--regime", "sliding", "--zeta", "0.7", "--wn", "60",
                                  "--simulate", "--reference", "step", "--amplitude", "0.002", "--duration", "0.5",
                                  "--compensation", "none"},
                                 "fig4lead");
        EXPECT_NE(lead["simulation"][0]["rms_error_m"], j["simulation"][0]["rms_error_m"]) << type;
      }
    }
}

TEST(DesignCliSimulate, BadFeedforwardSourceIsAnErrorWithExitCode2) {
  const std::string preset = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json";
  EXPECT_EQ(run_cli({"design", "--preset", preset, "--zeta", "0.7", "--wn", "60", "--simulate", "--feedforward",
                     "velocity", "--json", temp("bad.json")}),
            2);
}
