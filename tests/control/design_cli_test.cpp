// gmslab design: the JSON keys of the issue and their values for the worked examples, the preset
// path with a simulated loop, and clear errors (exit code 2) for malformed input.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/cli/cli.hpp"
#include "core/io/atomic_file.hpp"
#include "tests/core/run_cli.hpp"

namespace {
using gmslab::test_util::run_cli;

std::string temp_json(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string("gmslab_design_") + name + ".json")).string();
}

nlohmann::json design(std::vector<std::string> args, const char* name) {
  const std::string out = temp_json(name);
  std::filesystem::remove(out);
  args.insert(args.begin(), "design");
  args.push_back("--json");
  args.push_back(out);
  EXPECT_EQ(run_cli(args), 0);
  return nlohmann::json::parse(gmslab::read_file(out));
}
}  // namespace

TEST(DesignCli, G1Kv5WritesTheIssuesKeysWithTheWorkedExampleValues) {
  const auto j = design({"--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "5",
                         "--max-ratio", "20"}, "g1");
  for (const char* key : {"applicable", "phi_deg", "K0", "K_max", "K_max_usable", "z", "p", "Kc",
                          "K", "closed_loop_poles"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["applicable"].get<bool>());
  EXPECT_NEAR(j["phi_deg"].get<double>(), 30.0, 1e-9);
  EXPECT_NEAR(j["K0"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(j["K_max"].get<double>(), 8.0, 1e-9);
  EXPECT_LT(j["K_max_usable"].get<double>(), 8.0);
  EXPECT_NEAR(j["z"].get<double>(), 2.857143, 1e-6);
  EXPECT_NEAR(j["p"].get<double>(), 5.333333, 1e-6);
  EXPECT_NEAR(j["Kc"].get<double>(), 4.666667, 1e-6);
  EXPECT_NEAR(j["K"].get<double>(), 5.0, 1e-9);
  ASSERT_EQ(j["closed_loop_poles"].size(), 3u);
  bool has_real = false;
  for (const auto& p : j["closed_loop_poles"]) {
    ASSERT_EQ(p.size(), 2u);
    if (std::abs(p[1].get<double>()) < 1e-12) {
      EXPECT_NEAR(p[0].get<double>(), -3.333333, 1e-6);
      has_real = true;
    } else {
      EXPECT_NEAR(p[0].get<double>(), -2.0, 1e-9);
      EXPECT_NEAR(std::abs(p[1].get<double>()), 3.464102, 1e-6);
    }
  }
  EXPECT_TRUE(has_real);
  EXPECT_TRUE(j["relocations"].empty());  // present, empty: one shape
}

TEST(DesignCli, UnreachableConstantListsRelocationsPerPathWithReasons) {
  const auto j = design({"--num", "1", "--den", "1 6 5 0", "--zeta", "0.5", "--wn", "2", "--K", "8"},
                        "g2");
  EXPECT_NEAR(j["K_max"].get<double>(), 3.2, 1e-9);
  ASSERT_TRUE(j.contains("relocations"));
  ASSERT_EQ(j["relocations"].size(), 3u);
  const auto& kz = j["relocations"][0];
  EXPECT_EQ(kz["path"], "keep_zeta");
  EXPECT_EQ(kz["name"], "keep_zeta");
  EXPECT_FALSE(kz["found"].get<bool>());
  EXPECT_NEAR(kz["peak_K"].get<double>(), 6.4, 1e-6);
  EXPECT_FALSE(kz["reason"].get<std::string>().empty());
  const auto& ks = j["relocations"][1];
  EXPECT_EQ(ks["path"], "keep_zeta_wn");
  ASSERT_TRUE(ks["found"].get<bool>());
  for (const char* key : {"wn", "zeta", "z", "p", "Kc"}) EXPECT_TRUE(ks.contains(key)) << key;
  // Kv_max(wd) at zeta wn = 1 reaches 8 (1 + 0.1) a little beyond wd = 3.
  EXPECT_NEAR(ks["zeta"].get<double>() * ks["wn"].get<double>(), 1.0, 1e-9);
  EXPECT_GT(ks["wn"].get<double>(), std::hypot(1.0, 3.0));
  EXPECT_NEAR(ks["K"].get<double>(), 8.0, 1e-9);
}

TEST(DesignCli, PresetSlidingPlantDesignAndSimulationWithEachCompensation) {
  const auto j = design({"--preset", std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json",
                         "--regime", "sliding", "--zeta", "0.7", "--wn", "60", "--K", "1000",
                         "--simulate", "--reference", "ramp", "--duration", "1"}, "preset");
  EXPECT_EQ(j["plant"]["regime"], "sliding");
  EXPECT_NEAR(j["plant"]["damping_N_s_per_m"].get<double>(), 0.4, 1e-9);
  EXPECT_NEAR(j["K0"].get<double>(), 2.5, 1e-9);  // 1 / sigma2
  ASSERT_EQ(j["simulation"].size(), 3u);
  const double e_none = j["simulation"][0]["steady_state_error_m"].get<double>();
  const double e_gms = j["simulation"][2]["steady_state_error_m"].get<double>();
  EXPECT_EQ(j["simulation"][2]["compensation"], "gms");
  EXPECT_NEAR(e_none, 2.51e-3, 2e-5);  // F_ss(v) / (Kc z / p) with Kc z / p = 400 N/m
  EXPECT_LT(std::abs(e_gms), 1e-6);
}

TEST(DesignCli, MalformedInputIsAClearErrorWithExitCode2) {
  const std::string out = temp_json("bad");
  EXPECT_EQ(run_cli({"design", "--num", "4 x", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--json", out}), 2);
  EXPECT_EQ(run_cli({"design", "--num", "4", "--den", "1 2 0", "--zeta", "1.2", "--wn", "4", "--json", out}), 2);
  EXPECT_EQ(run_cli({"design", "--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "-1", "--json", out}), 2);
  EXPECT_EQ(run_cli({"design", "--num", "1 2 3", "--den", "1 2", "--zeta", "0.5", "--wn", "4", "--json", out}), 2);
  EXPECT_EQ(run_cli({"design", "--den", "1 2", "--zeta", "0.5", "--wn", "4", "--json", out}), 2);
  EXPECT_EQ(run_cli({"design", "--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "0", "--json", out}), 2);
  EXPECT_EQ(run_cli({"design", "--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--simulate", "--json", out}), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
}

// The "frequency" key: margins of the designed loop Kc (s + z) 4 / ((s + p) s (s + 2)), checked
// against the loop evaluated from the JSON's own z, p, Kc (|L| = 1 at w_gc, L real negative at
// w_pc, PM = 180 + arg L), and Nyquist's verdict against the closed-loop poles.
TEST(DesignCli, FrequencyKeyReportsTheDesignedLoopsMargins) {
  const auto j = design({"--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "5"}, "freq");
  ASSERT_TRUE(j.contains("frequency"));
  const auto& m = j["frequency"]["margins"];
  const double z = j["z"].get<double>(), p = j["p"].get<double>(), Kc = j["Kc"].get<double>();
  const auto L = [&](double w) {
    const std::complex<double> s(0.0, w);
    return Kc * (s + z) * 4.0 / ((s + p) * s * (s + 2.0));
  };
  const double wgc = m["gain_crossover_rad_s"].get<double>();
  EXPECT_NEAR(std::abs(L(wgc)), 1.0, 1e-9);
  EXPECT_NEAR(m["phase_margin_deg"].get<double>(), 180.0 + std::arg(L(wgc)) * 180.0 / M_PI, 1e-7);
  EXPECT_TRUE(m["gain_margin"].is_null());  // type 1, one pole-zero pair: the phase never reaches -180
  EXPECT_TRUE(m["phase_crossovers_rad_s"].empty());
  bool stable = true;
  for (const auto& pole : j["closed_loop_poles"]) stable &= pole[0].get<double>() < 0.0;
  EXPECT_EQ(j["frequency"]["nyquist"]["stable"].get<bool>(), stable);
  EXPECT_EQ(j["frequency"]["nyquist"]["axis_poles"].get<int>(), 1);
  EXPECT_GT(j["frequency"]["closed_loop"]["bandwidth_rad_s"].get<double>(), 0.0);
  // Export: tf coefficients (highest power first) and code that rebuilds them to the last digit.
  const auto& c = j["compensator"];
  EXPECT_EQ(c["num"][0].get<double>(), Kc);
  EXPECT_EQ(c["num"][1].get<double>(), Kc * z);
  EXPECT_EQ(c["den"][1].get<double>(), p);
  double a = 0, b = 0, one = 0, pp = 0;
  ASSERT_EQ(std::sscanf(c["matlab"].get<std::string>().c_str(), "C = tf([%lf, %lf], [%lf, %lf]);", &a, &b, &one, &pp), 4);
  EXPECT_EQ(a, Kc);
  EXPECT_EQ(b, Kc * z);
  EXPECT_EQ(pp, p);
  ASSERT_EQ(std::sscanf(c["python"].get<std::string>().c_str(), "import control\nC = control.tf([%lf, %lf], [%lf, %lf])", &a, &b, &one, &pp), 4);
  EXPECT_EQ(b, Kc * z);
}

// With --sample-time the sampled loop's margins are reported (frequency.discrete), below the
// Nyquist frequency, and approach the continuous ones as T -> 0 (the hold's delay T/2 costs
// w_gc T/2 rad of phase margin).
TEST(DesignCli, SampleTimeAddsTheSampledLoopsMargins) {
  const auto j = design({"--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "5",
                         "--sample-time", "0.01"}, "sampled");
  ASSERT_TRUE(j["frequency"].contains("discrete"));
  const auto& d = j["frequency"]["discrete"];
  const double wgc = j["frequency"]["margins"]["gain_crossover_rad_s"].get<double>();
  const double pm = j["frequency"]["margins"]["phase_margin_deg"].get<double>();
  EXPECT_NEAR(d["nyquist_frequency_rad_s"].get<double>(), M_PI / 0.01, 1e-9);
  EXPECT_NEAR(d["margins"]["gain_crossover_rad_s"].get<double>(), wgc, 0.02 * wgc);
  EXPECT_NEAR(d["margins"]["phase_margin_deg"].get<double>(), pm - wgc * 0.01 / 2 * 180 / M_PI, 0.5);
  EXPECT_TRUE(d["nyquist"]["stable"].get<bool>());
}

// The z-plane locus of the sampled loop (--sample-time): its first unit-circle crossing is where
// the gain reaches Kc x the sampled gain margin (computed independently, from the w-plane phase
// crossover) at the phase crossover frequency; the design gain is stable there exactly when the
// sampled Nyquist count says so. Over sample times from 1 ms to 0.2 s.
TEST(DesignCli, SampleTimeAddsTheZPlaneLocusConsistentWithTheSampledMargins) {
  for (const char* T : {"0.001", "0.01", "0.05", "0.2", "0.4"}) {
    const auto j = design({"--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "5",
                           "--sample-time", T}, "zlocus");
    ASSERT_TRUE(j.contains("z_locus")) << T;
    const auto& z = j["z_locus"];
    const auto& m = j["frequency"]["discrete"]["margins"];
    const double Kc = j["Kc"].get<double>();
    EXPECT_NEAR(z["gain"].get<double>(), Kc, 1e-12 * Kc);
    EXPECT_EQ(z["stable_at_gain"].get<bool>(), j["frequency"]["discrete"]["nyquist"]["stable"].get<bool>()) << T;
    ASSERT_FALSE(z["unit_circle_crossings"].empty());
    const auto& c = z["unit_circle_crossings"][0];
    const double re = c["z"][0].get<double>(), im = c["z"][1].get<double>();
    EXPECT_NEAR(std::hypot(re, im), 1.0, 1e-9);
    if (!m["gain_margin"].is_null() && m["gain_margin"].get<double>() > 1.0) {
      EXPECT_NEAR(c["gain"].get<double>(), Kc * m["gain_margin"].get<double>(), 1e-6 * c["gain"].get<double>()) << T;
      EXPECT_NEAR(c["omega_rad_s"].get<double>(), m["phase_crossover_rad_s"].get<double>(), 1e-6 * c["omega_rad_s"].get<double>()) << T;
      EXPECT_NEAR(z["stable_gain_intervals"][0][1].get<double>(), c["gain"].get<double>(), 1e-9 * c["gain"].get<double>());
    }
  }
}

// --lag-K adds a lag after the chosen lead: the G1 Kv = 5 design made Kv = 50 (x10) reports the
// lag zero at 0.1 |Re s_d| = 0.2 rad/s, its pole at 0.02, K = 50 and the compensator's coefficients
// (conv of lead and lag), a slow real pole just left of the lag zero -0.2; a target below the lead's own is
// an error with exit code 2.
TEST(DesignCli, LagKAddsALagWithItsErrorConstantAndSlowPole) {
  const auto j = design({"--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "5",
                         "--lag-K", "50"}, "leadlag");
  ASSERT_TRUE(j.contains("lead_lag"));
  const auto& l = j["lead_lag"];
  EXPECT_NEAR(l["zl"].get<double>(), 0.2, 1e-12);
  EXPECT_NEAR(l["pl"].get<double>(), 0.02, 1e-9);
  EXPECT_NEAR(l["K"].get<double>(), 50.0, 1e-9);
  EXPECT_NEAR(l["K_lead"].get<double>(), 5.0, 1e-9);
  const double Kc = j["Kc"].get<double>(), z = j["z"].get<double>(), p = j["p"].get<double>();
  const std::vector<double> num = l["num"], den = l["den"];
  ASSERT_EQ(num.size(), 3u);
  EXPECT_NEAR(num[0], Kc, 1e-9 * Kc);
  EXPECT_NEAR(num[1], Kc * (z + 0.2), 1e-9 * Kc);
  EXPECT_NEAR(num[2], Kc * z * 0.2, 1e-9 * Kc);
  EXPECT_NEAR(den[1], p + 0.02, 1e-9);
  const double slow = l["slow_pole"][0].get<double>();
  EXPECT_LT(slow, -0.2);  // just left of the lag zero (its branch ends there)
  EXPECT_GT(slow, -0.26);
  EXPECT_NEAR(l["slow_time_constant_s"].get<double>(), -1.0 / slow, 1e-12);
  EXPECT_EQ(run_cli({"design", "--num", "4", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4", "--K", "5",
                     "--lag-K", "3"}), 2);
}
