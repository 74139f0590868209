// Where the design's plant comes from (core/control/design_plant.hpp): a typed num/den through a
// session and the CLI, its validation naming the field, the assembled two-mass chain's collocated
// and non-collocated transfer functions against the closed form, and the loop on the assembled
// plant against the linear closed loop (no friction) and the one-body loop (one body).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>

#include "app/cli/cli.hpp"
#include "core/control/design_plant.hpp"
#include "core/control/design_session.hpp"
#include "core/control/design_settings.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/friction/gms.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/session_io.hpp"
#include "tests/core/run_cli.hpp"

namespace gmslab::control {
namespace {

std::string num_text(const std::vector<double>& c) {
  std::string s;
  char b[40];
  for (double x : c) std::snprintf(b, sizeof b, "%s%.17g", s.empty() ? "" : " ", x), s += b;
  return s;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("gmslab_plantsrc_" + name + "_" + std::to_string(getpid()) + ".json"))
      .string();
}

using gmslab::test_util::run_cli;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::vector<cplx> sorted(std::vector<cplx> v) {
  std::sort(v.begin(), v.end(), [](cplx a, cplx b) {
    return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
  });
  return v;
}

// A typed plant, saved in a session and loaded back, designs the same lead (and closed-loop poles,
// and plant) in the Design tab's computation as `gmslab design --num --den` for the same G(s).
// Random type-1 plants K (s + b) / (s (s + a) (s + c)) and desired roots.
TEST(PlantSource, TypedPlantRoundTripsThroughASessionAndDesignsAsTheCli) {
  std::mt19937 rng(2615);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int designed = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const double K = 0.5 + 20 * u(rng), a = 0.5 + 5 * u(rng), b = 5 + 20 * u(rng), c = 20 + 40 * u(rng);
    const Poly den = Poly({0.0, 1.0}) * Poly({a, 1.0}) * Poly({c, 1.0});
    DesignSettings ds;
    ds.plant.source = PlantSource::Typed;
    ds.plant.num = num_text({K, K * b});
    ds.plant.den = num_text(den.descending_coeffs());
    ds.zeta = 0.4 + 0.4 * u(rng);
    ds.wn = 2 + 6 * u(rng);
    ds.max_ratio = 10 + 20 * u(rng);
    Session s;
    s.scenario.friction = model_info("gms").defaults();
    s.design = ds;
    const std::string path = temp_path("typed");
    save_session(s, path);
    const Session back = load_session(path);
    std::filesystem::remove(path);
    ASSERT_EQ(back.design, ds);
    ASSERT_EQ(back.design.plant.num, ds.plant.num);

    DesignInputs in;
    set_design_inputs(back.design, in);
    in.simulate = false;
    const DesignOutputs out = compute_design(in);
    EXPECT_EQ(out.source, PlantSource::Typed);
    EXPECT_FALSE(out.loop_note.empty());  // says why no loop with friction is drawn
    EXPECT_TRUE(out.plain().trace.t.empty());

    const std::string json = temp_path("cli");
    char zeta[40], wn[40], ratio[40];
    std::snprintf(zeta, sizeof zeta, "%.17g", ds.zeta);
    std::snprintf(wn, sizeof wn, "%.17g", ds.wn);
    std::snprintf(ratio, sizeof ratio, "%.17g", ds.max_ratio);
    ASSERT_EQ(run_cli({"design", "--num", ds.plant.num, "--den", ds.plant.den, "--zeta", zeta, "--wn", wn,
                       "--max-ratio", ratio, "--json", json}),
              0);
    const auto j = nlohmann::json::parse(read_file(json));
    std::filesystem::remove(json);
    // The same plant, coefficient by coefficient.
    ASSERT_EQ(j["plant"]["den"].size(), den.descending_coeffs().size());
    for (std::size_t i = 0; i < j["plant"]["den"].size(); ++i)
      EXPECT_DOUBLE_EQ(j["plant"]["den"][i].get<double>(), out.plant.g.den.descending_coeffs()[i]);
    for (std::size_t i = 0; i < j["plant"]["num"].size(); ++i)
      EXPECT_DOUBLE_EQ(j["plant"]["num"][i].get<double>(), out.plant.g.num.descending_coeffs()[i]);
    const bool cli_has = j.contains("z") && !j["z"].is_null();
    ASSERT_EQ(cli_has, out.compensator.has_value()) << trial;
    if (!cli_has) continue;
    ++designed;
    const LeadCompensator& cc = *out.compensator;
    EXPECT_NEAR(j["Kc"].get<double>(), cc.Kc, 1e-9 * cc.Kc);
    EXPECT_NEAR(j["z"].get<double>(), cc.z, 1e-9 * cc.z);
    EXPECT_NEAR(j["p"].get<double>(), cc.p, 1e-9 * cc.p);
    std::vector<cplx> cli_poles;
    for (const auto& p : j["closed_loop_poles"]) cli_poles.emplace_back(p[0].get<double>(), p[1].get<double>());
    const auto a1 = sorted(cli_poles), a2 = sorted(out.closed_loop_poles);
    ASSERT_EQ(a1.size(), a2.size());
    for (std::size_t i = 0; i < a1.size(); ++i) EXPECT_LT(std::abs(a1[i] - a2[i]), 1e-7 * (1 + std::abs(a2[i])));
  }
  EXPECT_GE(designed, 8);  // the comparison compared designs, not two failures
}

// Bad coefficient strings are refused with the field's name and why; the session names the key path;
// the value in force never changes to a rejected one.
TEST(PlantSource, BadTypedCoefficientsNameTheField) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  const std::vector<std::string> garbage = {"x", "1..2", "nan", "inf", "-inf", "2s", "1e999", "--1", "0x"};
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<std::string> tok;
    const int n = 1 + static_cast<int>(rng() % 4);
    for (int i = 0; i < n; ++i) tok.push_back(std::to_string(1.0 + std::abs(u(rng))));
    tok.insert(tok.begin() + static_cast<long>(rng() % (tok.size() + 1)), garbage[rng() % garbage.size()]);
    std::string bad;
    for (const auto& t : tok) bad += (bad.empty() ? "" : " ") + t;
    const bool in_den = trial % 2 == 1;
    const std::string msg = error_of([&] {
      typed_plant(in_den ? "1" : bad, in_den ? bad + " 1 1 1 1 1" : "1 2 3 4 5 6 7", "plant num", "plant den");
    });
    EXPECT_NE(msg.find(in_den ? "plant den" : "plant num"), std::string::npos) << bad << ": " << msg;
    EXPECT_NE(msg.find("not a finite number"), std::string::npos) << msg;
    EXPECT_FALSE(coefficients_problem(bad, in_den).empty());
  }
  EXPECT_NE(error_of([] { typed_plant("", "1 2", "num", "den"); }).find("num '': empty"), std::string::npos);
  EXPECT_NE(error_of([] { typed_plant("1", " , ", "num", "den"); }).find("den ' , ': empty"), std::string::npos);
  EXPECT_NE(error_of([] { typed_plant("1", "0 1 2", "num", "den"); }).find("den '0 1 2': the leading coefficient"),
            std::string::npos);
  EXPECT_NE(error_of([] { typed_plant("0 0", "1 2", "num", "den"); }).find("num '0 0': all coefficients are zero"),
            std::string::npos);
  EXPECT_NE(error_of([] { typed_plant("1 2 3", "1 2", "num", "den"); }).find("must be proper"), std::string::npos);
  EXPECT_NO_THROW(typed_plant("0 1 2", "3, 4, 5", "num", "den"));  // a leading zero of num is fine
  EXPECT_EQ(typed_plant("2", "1 3 0").den.degree(), 2);

  // The session: the key path of the field, and old sessions without design.plant still load.
  Session s;
  s.scenario.friction = model_info("gms").defaults();
  s.design.plant = {PlantSource::Typed, "4", "1 2 0", "", ""};
  const nlohmann::json good = to_json(s);
  auto rejected = [&](const char* key, const nlohmann::json& value) {
    nlohmann::json j = good;
    j["design"]["plant"][key] = value;
    return error_of([&] { session_from_json(j, "s.json"); });
  };
  EXPECT_NE(rejected("num", "1 q").find("design.plant.num"), std::string::npos);
  EXPECT_NE(rejected("den", "0 1").find("design.plant.den"), std::string::npos);
  EXPECT_NE(rejected("den", "").find("design.plant.den"), std::string::npos);
  EXPECT_NE(rejected("num", "1 2 3 4").find("design.plant.num"), std::string::npos);  // improper
  EXPECT_NE(rejected("source", "file").find("design.plant.source"), std::string::npos);
  EXPECT_NE(rejected("num", 4).find("design.plant.num"), std::string::npos);
  EXPECT_NE(rejected("bogus", "x").find("design.plant.bogus"), std::string::npos);
  nlohmann::json old = good;
  old["design"].erase("plant");
  EXPECT_EQ(session_from_json(old, "old.json").design.plant, PlantChoice{});
  EXPECT_EQ(session_from_json(good, "s.json").design.plant, s.design.plant);
  // The CLI refuses them too (exit code 2: bad input).
  EXPECT_EQ(run_cli({"design", "--num", "1 q", "--den", "1 2 0", "--zeta", "0.5", "--wn", "4"}), 2);
  EXPECT_EQ(run_cli({"design", "--num", "1", "--den", "0 2 0", "--zeta", "0.5", "--wn", "4"}), 2);
}

// A random undamped two-mass chain: motor m1 -- k12 -- load m2, each maybe tied to ground by a
// spring. With M x'' + K x = b F the closed form is
//   det(s) = (m1 s^2 + k1 + k12)(m2 s^2 + k2 + k12) - k12^2,
//   collocated     x1 / F = (m2 s^2 + k2 + k12) / det(s)   zeros at s^2 = -(k2 + k12) / m2,
//   non-collocated x2 / F = k12 / det(s)                    no finite zeros,
// and the poles w^2 solve m1 m2 w^4 - (m1 (k2 + k12) + m2 (k1 + k12)) w^2 + (k1 + k12)(k2 + k12) - k12^2 = 0.
// The collocated poles and zeros alternate on the imaginary axis: w1 < wz < w2.
TEST(PlantSource, CollocatedTwoMassPolesAndZerosInterlaceNonCollocatedHasNoZeros) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const double m1 = 0.1 + 3 * u(rng), m2 = 0.1 + 3 * u(rng), k12 = 100 + 5000 * u(rng);
    const double k1 = trial % 3 == 0 ? 0.0 : 2000 * u(rng), k2 = trial % 4 == 0 ? 0.0 : 2000 * u(rng);
    Assembly a;
    a.bodies = {{"motor", m1}, {"load", m2}};
    a.springs = {{"shaft", 0, 1, k12}};
    if (k1 > 0) a.springs.push_back({"k1", 0, kGround, k1});
    if (k2 > 0) a.springs.push_back({"k2", 1, kGround, k2});
    a.drives = {{"torque", DrivePart::Kind::Force, 0, Signal::constant(0.0)}};
    const double A = m1 * m2, B = m1 * (k2 + k12) + m2 * (k1 + k12), C = (k1 + k12) * (k2 + k12) - k12 * k12;
    const double disc = std::sqrt(B * B - 4 * A * C);
    const double w1 = std::sqrt(std::max(0.0, (B - disc) / (2 * A))), w2 = std::sqrt((B + disc) / (2 * A));
    const double wz = std::sqrt((k2 + k12) / m2);
    ASSERT_LT(w1, wz);
    ASSERT_LT(wz, w2);
    for (Regime r : {Regime::Presliding, Regime::Sliding}) {  // no contacts: both regimes alike
      const PlantChoice col{PlantSource::Assembly, "1", "1 2 0", "torque", "x.motor"};
      const PlantChoice non{PlantSource::Assembly, "1", "1 2 0", "", "load"};  // defaults and a bare body name
      const DesignPlant pc = design_plant(col, r, 0.0, nullptr, &a);
      const DesignPlant pn = design_plant(non, r, 0.0, nullptr, &a);
      EXPECT_EQ(pc.port.output, "x.motor");
      EXPECT_EQ(pn.port.output, "x.load");
      EXPECT_EQ(pn.port.drive_name, "torque");
      // Frequencies on the imaginary axis (|Re| negligible), one of each conjugate pair.
      auto freqs = [&](const std::vector<cplx>& roots) {
        std::vector<double> w;
        for (const cplx& s : roots) {
          EXPECT_LT(std::abs(s.real()), 1e-6 * w2) << s;
          if (s.imag() >= -1e-6 * w2) w.push_back(std::abs(s.imag()));
        }
        std::sort(w.begin(), w.end());
        return w;
      };
      const auto poles = freqs(pc.linear.g.poles()), zeros = freqs(pc.linear.g.zeros());
      // Poles: w1 (twice at 0 when nothing ties the chain to ground), w2; zeros: wz.
      ASSERT_EQ(zeros.size(), 1u);
      EXPECT_NEAR(zeros[0], wz, 1e-6 * wz);
      ASSERT_GE(poles.size(), 2u);
      EXPECT_NEAR(poles.back(), w2, 1e-6 * w2);
      EXPECT_NEAR(poles.front(), w1, 1e-5 * w2);
      EXPECT_LT(poles.front(), zeros[0]);  // interlacing
      EXPECT_LT(zeros[0], poles.back());
      // The non-collocated plant: the same poles, a constant numerator k12 / (m1 m2) after scaling.
      EXPECT_EQ(pn.linear.g.num.degree(), 0) << trial;
      EXPECT_TRUE(pn.linear.g.zeros().empty());
      EXPECT_NEAR(pn.linear.g.num.descending_coeffs()[0] / pn.linear.g.den.descending_coeffs()[0], k12 / A,
                  1e-9 * k12 / A);
      const auto pn_poles = freqs(pn.linear.g.poles());
      EXPECT_NEAR(pn_poles.back(), w2, 1e-6 * w2);
    }
  }
  // Names that are not there are refused, listing what there is.
  Assembly a;
  a.bodies = {{"motor", 1.0}, {"load", 1.0}};
  a.springs = {{"shaft", 0, 1, 100.0}};
  a.drives = {{"torque", DrivePart::Kind::Force, 0, Signal::constant(0.0)}};
  EXPECT_NE(error_of([&] { assembly_port(a, "motor", ""); }).find("force / pull drives: torque"), std::string::npos);
  EXPECT_NE(error_of([&] { assembly_port(a, "", "x.lod"); }).find("(motor, load)"), std::string::npos);
  EXPECT_NE(error_of([&] { design_plant({PlantSource::Assembly, "1", "1 0", "", ""}, Regime::Sliding, 0, nullptr, nullptr); })
                .find("no assembled plant"),
            std::string::npos);
}

// The Design tab's outputs and units (issue 11): every output the tab offers (assembly_outputs:
// x.BODY and v.BODY) is accepted by assembly_port, as `gmslab design --output` takes it; a v output
// is s times the x output; a pull drive's input is a displacement, so its plant y/u is m/m (at DC a
// pull spring alone holding a free chain moves it with the point: G(0) = 1) and Kc is labelled m/m;
// a force drive keeps N/m. Random chains of 1 to 3 bodies (fixed seed).
TEST(PlantSource, OutputsOfferedIncludeVelocityAndUnitsFollowTheDrive) {
  std::mt19937 rng(1511);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    Assembly a;
    const int n = 1 + static_cast<int>(rng() % 3);
    for (int i = 0; i < n; ++i) a.bodies.push_back({"b" + std::to_string(i), 0.1 + 3 * u(rng)});
    for (int i = 1; i < n; ++i) {
      a.springs.push_back({"k" + std::to_string(i), i - 1, i, 100 + 3000 * u(rng)});
      a.dampers.push_back({"c" + std::to_string(i), i - 1, i, 0.5 + 5 * u(rng)});
    }
    const int fb = static_cast<int>(rng() % n), pb = static_cast<int>(rng() % n);
    DrivePart pull{"pull", DrivePart::Kind::Pull, pb, Signal::constant(0.0)};
    pull.pull_spring = 200 + 2000 * u(rng), pull.pull_damper = 1 + 5 * u(rng);
    a.drives = {{"force", DrivePart::Kind::Force, fb, Signal::constant(0.0)}, pull};
    const std::vector<std::string> outs = assembly_outputs(a);
    ASSERT_EQ(outs.size(), 2u * n);
    for (const std::string drive : {"force", "pull"}) {
      const bool is_pull = drive == "pull";
      for (const std::string& y : outs) {
        SCOPED_TRACE(drive + " -> " + y);
        const AssemblyPort port = assembly_port(a, drive, y);
        EXPECT_EQ(port.output, y);
        EXPECT_EQ(port.pull, is_pull);
        EXPECT_EQ(port.velocity, y[0] == 'v');
        const LoopUnits lu = loop_units(PlantSource::Assembly, port);
        EXPECT_EQ(lu.input, is_pull ? "m" : "N");
        EXPECT_EQ(lu.output, port.velocity ? "m/s" : "m");
        EXPECT_EQ(lu.gain, is_pull ? (port.velocity ? "m/(m/s)" : "m/m") : (port.velocity ? "N s/m" : "N/m"));
        // The same plant as the CLI's `--drive D --output Y` (design_plant is its one function).
        const PlantChoice choice{PlantSource::Assembly, "1", "1 2 0", drive, y};
        const DesignPlant dp = design_plant(choice, Regime::Sliding, 0.0, nullptr, &a);
        EXPECT_EQ(dp.port.output, y);
        if (!port.velocity) {
          const DesignPlant dv = design_plant({PlantSource::Assembly, "1", "1 2 0", drive, "v" + y.substr(1)},
                                              Regime::Sliding, 0.0, nullptr, &a);
          const cplx s(-0.3 + u(rng), 0.5 + 20 * u(rng));
          EXPECT_LT(std::abs(dv.linear.g(s) - s * dp.linear.g(s)), 1e-8 * std::abs(s * dp.linear.g(s)));
          if (is_pull) {  // at DC the free chain follows the pull point: a dimensionless 1 (m/m)
            EXPECT_NEAR(std::abs(dp.linear.g(cplx(1e-7, 0))), 1.0, 1e-4);
          }
        }
      }
    }
  }
  // The scenario and a typed G(s) are force -> position.
  EXPECT_EQ(loop_units(PlantSource::Scenario, {}).gain, "N/m");
  EXPECT_EQ(loop_units(PlantSource::Typed, {}).gain, "N/m");
}

// A random damped chain without contacts (no friction): the loop simulated on the assembled plant
// follows the linear closed loop's step response (ZOH-exact, linear_response.hpp) with a first-order
// integration error: below 5e-4 of the step (measured 1e-5 to 1.6e-4 at dt = 1e-5 s) and halved with half the step.
TEST(PlantSource, AssembledLoopWithoutFrictionMatchesTheLinearClosedLoop) {
  std::mt19937 rng(909);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 40 && checked < 8; ++trial) {
    Assembly a;
    const double m1 = 0.2 + 2 * u(rng), m2 = 0.2 + 2 * u(rng);
    a.bodies = {{"motor", m1}, {"load", m2}};
    a.springs = {{"shaft", 0, 1, 200 + 3000 * u(rng)}, {"tie", 1, kGround, 500 * u(rng)}};
    a.dampers = {{"loss", 0, 1, 0.5 + 5 * u(rng)}, {"guide", 1, kGround, 1 + 10 * u(rng)},
                 {"bearing", 0, kGround, 1 + 10 * u(rng)}};
    const bool pull = trial % 3 == 2;
    DrivePart d{"drive", pull ? DrivePart::Kind::Pull : DrivePart::Kind::Force, 0, Signal::constant(0.0)};
    if (pull) d.pull_spring = 500 + 2000 * u(rng), d.pull_damper = 2 * u(rng);
    a.drives = {d};
    const std::string output = trial % 2 == 0 ? "x.motor" : "x.load";
    const DesignPlant dp = design_plant({PlantSource::Assembly, "1", "1 0", "drive", output}, Regime::Sliding, 0.0,
                                        nullptr, &a);
    LeadCompensator c;
    c.z = 1 + 15 * u(rng);
    c.p = c.z * (3 + 10 * u(rng));
    c.Kc = (pull ? 0.5 : 200.0) * (0.2 + 5 * u(rng));
    const TransferFunction T = closed_loop(dp.linear.g, c);
    bool stable = true;
    for (const cplx& s : T.poles()) stable = stable && s.real() < -0.5;
    if (!stable) continue;
    ++checked;
    AssemblyScenario sc;
    sc.name = "chain";
    sc.plant = a;
    sc.run.dt = 1e-5;
    const double amp = 1e-3 * (1 + 9 * u(rng)), duration = 1.0;
    const int n = 201;
    const StepResponse lin = step_response(T, duration, n);
    auto max_error = [&](double dt) {
      LoopConfig cfg;
      cfg.reference = Signal::constant(amp);
      cfg.C = c;
      cfg.comp = trial % 2 ? Compensation::Gms : Compensation::Coulomb;  // no contacts: nothing to feed forward
      cfg.dt = dt;
      cfg.duration = duration;
      cfg.record_every = static_cast<int>(std::lround(duration / (n - 1) / dt));
      const LoopTrace tr = simulate_loop(sc, dp.port, cfg);
      EXPECT_EQ(tr.t.size(), lin.t.size());
      double e = 0.0;
      for (std::size_t i = 0; i < std::min(tr.t.size(), lin.t.size()); ++i) {
        EXPECT_NEAR(tr.t[i], lin.t[i], 1e-9);
        EXPECT_EQ(tr.ff[i], 0.0);
        e = std::max(e, std::abs(tr.x[i] - amp * lin.y[i]));
      }
      return e / amp;
    };
    const double e1 = max_error(2e-5), e2 = max_error(1e-5);
    EXPECT_LT(e2, 5e-4) << "trial " << trial << (pull ? " pull " : " force ") << output;
    EXPECT_LT(e2, 0.6 * e1) << "first order: " << e1 << " -> " << e2;
  }
  EXPECT_GE(checked, 6);
}

// A one-body assembly (assembly_from_scenario of a force-driven scenario) gives the one-body loop's
// trace: positions, control, feedforward and friction, for random plants, references and compensations.
TEST(PlantSource, OneBodyAssemblyLoopMatchesTheOneBodyLoop) {
  std::mt19937 rng(31337);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 9; ++trial) {
    Scenario s;
    s.name = "one body";
    s.friction = GmsParams::reference(trial % 2 == 0).to_params();
    s.friction.set_scalar("Fs", 0.5 + 2 * u(rng));
    s.friction.set_scalar("Fc", 0.6 * s.friction.scalar("Fs"));
    s.plant = {0.5 + 2 * u(rng), 100 * u(rng), 2 * u(rng)};
    s.drive.kind = Drive::Kind::Force;
    s.drive.signal = Signal::constant(0.0);
    s.run.dt = 1e-5;
    s.run.duration = 1.0;
    const AssemblyScenario as = assembly_from_scenario(s);
    const AssemblyPort port = assembly_port(as.plant, "", "");
    ASSERT_EQ(port.output, "x.mass");
    LoopConfig cfg;
    cfg.reference = trial % 3 == 0   ? Signal::constant(2e-3 * (1 + u(rng)))
                    : trial % 3 == 1 ? Signal::ramp(0.0, 0.01 * (1 + u(rng)))
                                     : Signal::sine(0.0, 0.005, 1 + 2 * u(rng));
    cfg.C = {200 + 2000 * u(rng), 5 + 20 * u(rng), 0.0};
    cfg.C.p = cfg.C.z * (2 + 10 * u(rng));
    cfg.comp = static_cast<Compensation>(trial % 3);
    cfg.mismatch.force = 0.8 + 0.4 * u(rng);
    cfg.dt = 2e-5;
    cfg.duration = 0.4;
    cfg.record_every = 7;
    if (trial == 4) cfg.sample_time = 1e-3;
    const LoopTrace a = simulate_loop(s, cfg);
    const LoopTrace b = simulate_loop(as, port, cfg);
    ASSERT_EQ(a.t.size(), b.t.size());
    double scale_x = 1e-12, scale_f = 1e-12;
    for (std::size_t i = 0; i < a.t.size(); ++i)
      scale_x = std::max(scale_x, std::abs(a.x[i])), scale_f = std::max(scale_f, std::abs(a.u[i]) + std::abs(a.friction[i]));
    bool any_friction = false;
    for (std::size_t i = 0; i < a.t.size(); ++i) {
      EXPECT_EQ(a.t[i], b.t[i]);
      EXPECT_NEAR(a.x[i], b.x[i], 1e-9 * scale_x) << trial << " at " << a.t[i];
      EXPECT_NEAR(a.v[i], b.v[i], 1e-6 * scale_x + 1e-9);
      EXPECT_NEAR(a.u[i], b.u[i], 1e-9 * scale_f);
      EXPECT_NEAR(a.ff[i], b.ff[i], 1e-9 * scale_f);
      EXPECT_NEAR(a.friction[i], b.friction[i], 1e-9 * scale_f);
      any_friction = any_friction || std::abs(a.friction[i]) > 0.1 * s.friction.scalar("Fc");
    }
    EXPECT_TRUE(any_friction);  // the friction acted (the comparison is not of two frictionless runs)
  }
}

// The Design tab's computation on the two-mass preset: the loops run on the assembled plant, and the
// collocated and non-collocated plants differ as the closed form says (zeros: the collocated pair
// only; the shaft's damper adds the one real zero -k/c of the non-collocated plant).
TEST(PlantSource, DesignOnTheTwoMassPresetRunsTheAssembledLoops) {
  const std::string path = std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path;
  const AssemblyScenario as = load_assembly_scenario(path);
  DesignSettings ds;
  ds.plant.source = PlantSource::Assembly;
  ds.wn = 10.0;
  DesignInputs in;
  in.assembly = as;
  set_design_inputs(ds, in);
  in.horizon = 0.5;
  in.reference = Signal::constant(0.005);
  const DesignOutputs col = compute_design(in);
  ASSERT_TRUE(col.error.empty()) << col.error;
  EXPECT_EQ(col.port.output, "x.motor");
  EXPECT_EQ(col.plant.g.num.degree(), 2);
  EXPECT_FALSE(col.plain().trace.t.empty());
  EXPECT_FALSE(col.compensated().trace.t.empty());
  // A step moves the train until static friction holds it: at rest the controller's DC force
  // Kc z / p e balances at most the break-away forces of both contacts (1 N + 3 N).
  ASSERT_TRUE(col.compensator);
  const double k_dc = col.compensator->Kc * col.compensator->z / col.compensator->p;
  EXPECT_GT(col.compensated().trace.x.back(), 1e-4);
  EXPECT_LE(std::abs(0.005 - col.compensated().trace.x.back()), 1.05 * 4.0 / k_dc);
  ds.plant.output = "x.load";
  set_design_inputs(ds, in);
  const DesignOutputs non = compute_design(in);
  EXPECT_EQ(non.port.output, "x.load");
  ASSERT_EQ(non.plant.g.zeros().size(), 1u);
  EXPECT_NEAR(non.plant.g.zeros()[0].real(), -2000.0 / 2.0, 1e-6 * 1000);  // shaft 2000 N/m, 2 N s/m
  // The automatic view fits s_d and the resonance (+-j70.7), not the far zero at -1000 rad/s.
  EXPECT_GT(non.locus.view.re_min, -500.0);
  EXPECT_GT(non.locus.view.im_max, 70.7);
  EXPECT_LT(non.locus.view.im_min, -70.7);
  EXPECT_LT(non.locus.view.re_min, -7.0);
  // `gmslab design PRESET --drive --output`: the same plant (design_plant) and the same lead as the
  // Design tab's computation, for both outputs.
  for (const char* o : {"x.motor", "x.load"}) {
    ds.plant.output = o;
    set_design_inputs(ds, in);
    in.simulate = false;
    const DesignOutputs tab = compute_design(in);
    const std::string json = temp_path("assembled");
    ASSERT_EQ(run_cli({"design", "--preset", path, "--drive", "motor_force", "--output", o, "--regime", "sliding",
                       "--zeta", "0.7", "--wn", "10", "--json", json}),
              0);
    const auto j = nlohmann::json::parse(read_file(json));
    std::filesystem::remove(json);
    EXPECT_EQ(j["plant"]["plant_source"], "assembly");
    EXPECT_EQ(j["plant"]["output"], o);
    EXPECT_EQ(j["plant"]["drive"], "motor_force");
    const auto den = tab.plant.g.den.descending_coeffs();
    ASSERT_EQ(j["plant"]["den"].size(), den.size());
    for (std::size_t i = 0; i < den.size(); ++i) EXPECT_DOUBLE_EQ(j["plant"]["den"][i].get<double>(), den[i]);
    ASSERT_TRUE(tab.compensator);
    EXPECT_NEAR(j["Kc"].get<double>(), tab.compensator->Kc, 1e-9 * tab.compensator->Kc);
    EXPECT_NEAR(j["z"].get<double>(), tab.compensator->z, 1e-9 * tab.compensator->z);
    EXPECT_NEAR(j["p"].get<double>(), tab.compensator->p, 1e-9 * tab.compensator->p);
  }
  EXPECT_EQ(run_cli({"design", "--preset", path, "--drive", "load", "--zeta", "0.7", "--wn", "10"}), 2);
  EXPECT_EQ(run_cli({"design", "--preset", path, "--output", "x.shaft", "--zeta", "0.7", "--wn", "10"}), 2);
  // Without an assembled plant the design says so (not a blank view).
  in.assembly.reset();
  const DesignOutputs none = compute_design(in);
  EXPECT_NE(none.error.find("no assembled plant"), std::string::npos);
}

}  // namespace
}  // namespace gmslab::control
