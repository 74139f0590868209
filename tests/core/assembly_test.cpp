// The assembled 1-D plant (core/sim/assembly.hpp): every v1 preset gives the one-body trace through
// the general plant; modal frequencies against closed forms; momentum and energy balance; a contact
// between two bodies acts equal and opposite; structural validation.
#include "core/sim/assembly.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "core/friction/gms.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

namespace fs = std::filesystem;

int file_schema_version(const std::string& path) {
  std::ifstream in(path);
  const auto j = nlohmann::json::parse(in);
  return j.at("schema_version").get<int>();
}

// The one-body loop (simulate(Scenario): the fast path of its drive kind, the one-body trace) vs
// the general loops (the plant with a second, zero spring to ground, which no fast path takes:
// advance_one_body for a free body, compute_step for prescribed motion): x, v, friction force,
// drive force at every sample.
void expect_same_trace(const Scenario& s) {
  const Trace a = simulate(s);
  AssemblyScenario general = assembly_from_scenario(s);
  general.plant.springs.push_back({"spring_zero", 0, kGround, 0.0});
  const AssemblyTrace b = simulate(general);
  ASSERT_EQ(a.size(), b.size());
  const auto x = b.series("x.mass"), v = b.series("v.mass"), f = b.series("F.friction"),
             d = b.series("F.drive");
  double scale_x = 1e-300, scale_v = 1e-300, scale_f = 1e-300;
  for (std::size_t k = 0; k < a.size(); ++k) {
    scale_x = std::max(scale_x, std::abs(a.x[k]));
    scale_v = std::max(scale_v, std::abs(a.v[k]));
    scale_f = std::max({scale_f, std::abs(a.friction[k]), std::abs(a.applied[k])});
  }
  std::size_t worst = 0;
  double err = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a.t[k], b.t[k]);
    const double e = std::max({std::abs(a.x[k] - x[k]) / scale_x, std::abs(a.v[k] - v[k]) / scale_v,
                               std::abs(a.friction[k] - f[k]) / scale_f, std::abs(a.applied[k] - d[k]) / scale_f});
    if (e > err) err = e, worst = k;
  }
  EXPECT_LE(err, 1e-12) << "worst sample " << worst << " at t = " << a.t[worst] << " s";
  // Element states are carried through.
  ASSERT_EQ(b.n_elements.size(), 1u);
  EXPECT_EQ(b.n_elements[0], a.n_elements);
  EXPECT_EQ(b.element_slip[0], a.element_slip);
}

TEST(Assembly, EveryVersion1PresetGivesTheOneBodyTrace) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json" || file_schema_version(e.path().string()) != 1) continue;
    SCOPED_TRACE(e.path().string());
    expect_same_trace(load_scenario(e.path().string()));
    ++n;
  }
  EXPECT_GE(n, 10);
}

TEST(Assembly, RandomOneBodyPlantsOfEveryDriveKindGiveTheOneBodyTrace) {
  std::mt19937 rng(1101);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 24; ++trial) {
    Scenario s;
    s.name = "random " + std::to_string(trial);
    s.friction = GmsParams::reference(trial % 2 == 0).to_params();
    s.plant.mass = 0.2 + 3.0 * u(rng);
    s.drive.kind = static_cast<Drive::Kind>(trial % 4);
    const bool massive = s.drive.kind == Drive::Kind::Force || s.drive.kind == Drive::Kind::Pull;
    if (massive) {
      s.plant.spring = 50.0 * u(rng);
      s.plant.damper = 2.0 * u(rng);
    }
    switch (s.drive.kind) {
      case Drive::Kind::Displacement: s.drive.signal = Signal::sine(0, 2e-5 * (0.5 + u(rng)), 1.0 + 3 * u(rng)); break;
      case Drive::Kind::Velocity: s.drive.signal = Signal::sine(0, 0.01 * (0.5 + u(rng)), 0.5 + u(rng)); break;
      case Drive::Kind::Force: s.drive.signal = Signal::sine(0.2 * u(rng), 1.0 + 2.0 * u(rng), 0.5 + u(rng)); break;
      case Drive::Kind::Pull:
        s.drive.signal = Signal::ramp(0, 0.05 + 0.1 * u(rng));
        s.drive.pull_spring = 1.0 + 5.0 * u(rng);
        s.drive.pull_damper = 0.5 * u(rng);
        break;
    }
    s.run = {massive ? 1e-5 : 1e-4, 2.0, 1 + trial % 3};
    SCOPED_TRACE(s.name + " drive " + to_string(s.drive.kind));
    expect_same_trace(s);
  }
}

// The one-body loop runs the steps between two events (a sample, an energy check) in an inner
// loop, with an instance per GMS element count: a run advanced one step at a time (no step between
// events) gives the same trace bit for bit, for force and pull drives, 1 to 8 elements (drawn
// over the registry's ranges scaled to a stable step) and record intervals that do not divide 64.
TEST(Assembly, OneStepAtATimeGivesTheSameTraceForEveryElementCount) {
  std::mt19937 rng(2207);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int cases = 0;
  for (std::size_t ne = 1; ne <= GmsModel::kScalarElements; ++ne) {
    for (const Drive::Kind kind : {Drive::Kind::Force, Drive::Kind::Pull}) {
      Scenario s;
      s.name = std::to_string(ne) + " elements";
      GmsParams g = GmsParams::reference(true);
      g.alpha.assign(ne, 0.0);
      g.k.assign(ne, 0.0);
      g.sigma.assign(ne, 0.0);
      double sum = 0.0;
      for (std::size_t i = 0; i < ne; ++i) sum += g.alpha[i] = 0.2 + u(rng);
      for (std::size_t i = 0; i < ne; ++i) {
        g.alpha[i] /= sum;
        g.k[i] = 1e4 + 7e4 * u(rng);
        g.sigma[i] = 1e-3 * g.k[i] * u(rng);
      }
      s.friction = g.to_params();
      s.plant.mass = 0.5 + 2.0 * u(rng);
      s.plant.spring = 20.0 * u(rng);
      s.plant.damper = 1.0 * u(rng);
      s.drive.kind = kind;
      if (kind == Drive::Kind::Force) {
        s.drive.signal = Signal::sine(0.2 * u(rng), 1.5 + 2.0 * u(rng), 0.5 + u(rng));
      } else {
        s.drive.signal = Signal::ramp(0, 0.05 + 0.1 * u(rng));
        s.drive.pull_spring = 20.0 + 40.0 * u(rng);
        s.drive.pull_damper = 0.5 * u(rng);
      }
      s.run = {1e-5, 1.0, 1 + static_cast<int>(rng() % 13)};
      SCOPED_TRACE(s.name + " drive " + to_string(kind) + " record_every " +
                   std::to_string(s.run.record_every));
      AssemblySimulation blocks = one_body_simulation(s);
      blocks.run_to_end();
      AssemblySimulation steps = one_body_simulation(s);
      while (!steps.finished()) steps.advance(1);
      const Trace& a = blocks.one_body_trace();
      const Trace& b = steps.one_body_trace();
      ASSERT_EQ(a.size(), b.size());
      test_util::expect_same_samples(a, b);
      EXPECT_EQ(blocks.state_vector(), steps.state_vector());
      // The run slides as well as sticks: both branches of the element update are in it.
      EXPECT_NE(std::find(a.element_slip.begin(), a.element_slip.end(), 1), a.element_slip.end());
      EXPECT_NE(std::find(a.element_slip.begin(), a.element_slip.end(), 0), a.element_slip.end());
      ++cases;
    }
  }
  EXPECT_EQ(cases, 16);
}

// Ground -k1- m1 -k2- m2 (free end).
Assembly two_body_chain(double m1, double m2, double k1, double k2) {
  Assembly a;
  a.bodies = {{"m1", m1}, {"m2", m2}};
  a.springs = {{"k1", 0, kGround, k1}, {"k2", 1, 0, k2}};
  return a;
}

TEST(Assembly, TwoBodyChainModesMatchTheClosedForm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> lm(-1.0, 1.0), lk(1.0, 5.0);
  for (int trial = 0; trial < 50; ++trial) {
    const double m1 = std::pow(10.0, lm(rng)), m2 = std::pow(10.0, lm(rng));
    const double k1 = std::pow(10.0, lk(rng)), k2 = std::pow(10.0, lk(rng));
    // det(K - lambda M) = m1 m2 l^2 - ((k1 + k2) m2 + k2 m1) l + k1 k2 = 0
    const double A = m1 * m2, B = (k1 + k2) * m2 + k2 * m1, C = k1 * k2;
    const double disc = std::sqrt(B * B - 4 * A * C);
    const double l_hi = (B + disc) / (2 * A), l_lo = 2 * C / (B + disc);
    const auto w = modal_frequencies(two_body_chain(m1, m2, k1, k2));
    ASSERT_EQ(w.size(), 2u);
    EXPECT_NEAR(w[0], std::sqrt(l_lo), 1e-9 * std::sqrt(l_lo));
    EXPECT_NEAR(w[1], std::sqrt(l_hi), 1e-9 * std::sqrt(l_hi));
    EXPECT_NEAR(stability_limit_dt(two_body_chain(m1, m2, k1, k2)), 2.0 / std::sqrt(l_hi), 1e-9 / std::sqrt(l_hi));
  }
}

TEST(Assembly, ThreeBodyChainModesMatchTheClosedForm) {
  // Uniform chain fixed at both ends: w_j = 2 sqrt(k / m) sin(j pi / 8), j = 1..3.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> lm(-1.0, 1.0), lk(1.0, 5.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double m = std::pow(10.0, lm(rng)), k = std::pow(10.0, lk(rng));
    Assembly a;
    a.bodies = {{"a", m}, {"b", m}, {"c", m}};
    a.springs = {{"s0", 0, kGround, k}, {"s1", 1, 0, k}, {"s2", 2, 1, k}, {"s3", 2, kGround, k}};
    const auto w = modal_frequencies(a);
    ASSERT_EQ(w.size(), 3u);
    for (int j = 1; j <= 3; ++j) {
      const double wj = 2.0 * std::sqrt(k / m) * std::sin(j * M_PI / 8.0);
      EXPECT_NEAR(w[j - 1], wj, 1e-9 * wj) << "mode " << j;
    }
  }
  // Random masses and springs (free end): the squared frequencies are the roots of the cubic
  // det(K - l M); their sum, pairwise products and product are its coefficients (Vieta).
  for (int trial = 0; trial < 50; ++trial) {
    const double m1 = std::pow(10.0, lm(rng)), m2 = std::pow(10.0, lm(rng)), m3 = std::pow(10.0, lm(rng));
    const double k1 = std::pow(10.0, lk(rng)), k2 = std::pow(10.0, lk(rng)), k3 = std::pow(10.0, lk(rng));
    Assembly a;
    a.bodies = {{"a", m1}, {"b", m2}, {"c", m3}};
    a.springs = {{"s1", 0, kGround, k1}, {"s2", 0, 1, k2}, {"s3", 1, 2, k3}};
    const auto w = modal_frequencies(a);
    ASSERT_EQ(w.size(), 3u);
    const double l1 = w[0] * w[0], l2 = w[1] * w[1], l3 = w[2] * w[2];
    // M^-1 K with K = [[k1+k2, -k2, 0], [-k2, k2+k3, -k3], [0, -k3, k3]]
    const double a11 = (k1 + k2) / m1, a12 = -k2 / m1, a21 = -k2 / m2, a22 = (k2 + k3) / m2, a23 = -k3 / m2,
                 a32 = -k3 / m3, a33 = k3 / m3;
    const double tr = a11 + a22 + a33;
    const double minors = (a11 * a22 - a12 * a21) + (a22 * a33 - a23 * a32) + a11 * a33;
    const double det = k1 * k2 * k3 / (m1 * m2 * m3);
    EXPECT_NEAR(l1 + l2 + l3, tr, 1e-9 * tr);
    EXPECT_NEAR(l1 * l2 + l2 * l3 + l1 * l3, minors, 1e-8 * minors);
    EXPECT_NEAR(l1 * l2 * l3, det, 1e-8 * det);
  }
}

TEST(Assembly, SimulatedFreeVibrationHasTheModalFrequency) {
  // A 2-body chain released from a static deflection in its first mode shape vibrates at w_1
  // (checked against the eigen-solution through the period of the first body's motion).
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  for (int trial = 0; trial < 5; ++trial) {
    const double m1 = u(rng), m2 = u(rng), k1 = 100 * u(rng), k2 = 100 * u(rng);
    AssemblyScenario s;
    s.name = "chain";
    s.plant = two_body_chain(m1, m2, k1, k2);
    // A short force pulse on m2 excites both modes; the spectrum's peaks are the two modes.
    DrivePart d;
    d.name = "pulse";
    d.body = 1;
    d.signal = Signal::piecewise_linear({0.0, 1e-3, 2e-3}, {0.0, 1.0, 0.0});
    s.plant.drives = {d};
    const auto w = modal_frequencies(s.plant);
    s.run = {1e-5, 40.0, 10};
    const auto tr = simulate(s);
    const auto x1 = tr.series("x.m1"), x2 = tr.series("x.m2");
    // Hann-windowed Fourier amplitude of both bodies' motion at wq [rad/s].
    auto amp = [&](double wq) {
      double total = 0.0;
      for (const auto* x : {&x1, &x2}) {
        double c = 0, sn = 0;
        for (std::size_t k = 0; k < tr.size(); ++k) {
          const double win = 0.5 * (1.0 - std::cos(2.0 * M_PI * tr.t[k] / s.run.duration));
          c += win * (*x)[k] * std::cos(wq * tr.t[k]);
          sn += win * (*x)[k] * std::sin(wq * tr.t[k]);
        }
        total += std::hypot(c, sn);
      }
      return total;
    };
    if (w[1] < 1.3 * w[0]) continue;  // modes too close to tell apart by a 8 % detuning
    for (double wm : w) {
      EXPECT_GT(amp(wm), 3.0 * amp(wm * 1.08)) << "mode " << wm << " rad/s";
      EXPECT_GT(amp(wm), 3.0 * amp(wm * 0.92)) << "mode " << wm << " rad/s";
    }
  }
}

// Two free bodies tied by a spring, a damper and a GMS contact, not tied to ground; a force drive on
// the first. Internal forces cancel: the momentum is the impulse of the drive, step by step.
TEST(Assembly, MomentumChangesOnlyByTheExternalImpulse) {
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  for (int trial = 0; trial < 8; ++trial) {
    AssemblyScenario s;
    s.name = "pair";
    s.plant.bodies = {{"a", u(rng)}, {"b", u(rng)}, {"c", u(rng)}};
    s.plant.springs = {{"ab", 0, 1, 300 * u(rng)}, {"bc", 1, 2, 300 * u(rng)}};
    s.plant.dampers = {{"cab", 0, 1, 0.5 * u(rng)}};
    s.plant.contacts = {{"fab", 0, 1, GmsParams::reference(true).to_params()},
                        {"fbc", 2, 1, GmsParams::reference(false).to_params()}};
    DrivePart d;
    d.name = "push";
    d.body = 0;
    d.signal = Signal::sine(0.5 * u(rng), 3.0 * u(rng), u(rng));
    s.plant.drives = {d};
    s.run = {1e-5, 3.0, 1};
    AssemblySimulation sim(s);
    double impulse = 0.0, scale = 0.0;
    while (!sim.finished()) {
      impulse += s.run.dt * d.signal(sim.time());
      sim.advance(1);
      scale = std::max(scale, std::abs(impulse));
    }
    EXPECT_NEAR(sim.momentum(), impulse, 1e-10 * scale);
    // It did slip: the contacts took force both ways.
    const auto f = sim.trace().series("F.fab");
    EXPECT_GT(*std::max_element(f.begin(), f.end()), 0.5);
    EXPECT_LT(*std::min_element(f.begin(), f.end()), -0.5);
  }
}

// Energy: kinetic + spring energy - its start = drive work - damper and friction dissipation.
TEST(Assembly, EnergyBalancesDriveWorkAndDissipation) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  for (int trial = 0; trial < 6; ++trial) {
    AssemblyScenario s;
    s.name = "energy";
    s.plant.bodies = {{"a", u(rng)}, {"b", u(rng)}};
    s.plant.springs = {{"ka", 0, kGround, 50 * u(rng)}, {"kab", 0, 1, 80 * u(rng)}};
    s.plant.dampers = {{"cab", 1, 0, 0.3 * u(rng)}};
    ModelParams coulomb = model_info("coulomb").defaults();
    s.plant.contacts = {{"fb", 1, kGround, coulomb}};
    DrivePart d;
    d.name = "push";
    d.body = 0;
    d.signal = Signal::sine(0.0, 5.0 * u(rng), 0.5 * u(rng));
    s.plant.drives = {d};
    s.run = {1e-5, 4.0, 1};
    AssemblySimulation sim(s);
    const double e0 = sim.kinetic_energy() + sim.spring_energy();
    double w_drive = 0.0, w_loss = 0.0;
    while (!sim.finished()) {
      const double t = sim.time();
      const auto x0 = std::vector<double>(sim.positions().begin(), sim.positions().end());
      sim.advance(1);
      const auto& tr = sim.trace();
      const std::size_t k = tr.size() - 1;
      const double dxa = sim.positions()[0] - x0[0], dxb = sim.positions()[1] - x0[1];
      w_drive += d.signal(t) * dxa;
      w_loss += tr.at(k, tr.channel("F.cab")) * (dxb - dxa) + tr.at(k, tr.channel("F.fb")) * dxb;
    }
    const double e1 = sim.kinetic_energy() + sim.spring_energy();
    EXPECT_GT(w_loss, 0.0);
    EXPECT_NEAR(e1 - e0, w_drive - w_loss, 2e-3 * (std::abs(w_drive) + w_loss + e1));
  }
}

// A slider on a moving table: the contact's force acts on the slider as -F and on the table as +F.
TEST(Assembly, ContactBetweenTwoBodiesActsEqualAndOpposite) {
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  for (int trial = 0; trial < 6; ++trial) {
    AssemblyScenario s;
    s.name = "slider";
    const double ms = u(rng), mt = 3 * u(rng);
    s.plant.bodies = {{"slider", ms}, {"table", mt}};
    s.plant.contacts = {{"pad", 0, 1, GmsParams::reference(true).to_params()}};
    s.plant.dampers = {{"bearing", 1, kGround, 0.0}};
    DrivePart d;
    d.name = "motor";
    d.body = 1;
    d.signal = Signal::sine(0.0, 40.0 * u(rng), 0.5);
    s.plant.drives = {d};
    s.run = {1e-5, 2.0, 1};
    const auto tr = simulate(s);
    const auto vs = tr.series("v.slider"), vt = tr.series("v.table"), f = tr.series("F.pad"),
               fd = tr.series("F.motor");
    double worst = 0.0, fmax = 0.0;
    for (std::size_t k = 0; k + 1 < tr.size(); ++k) {
      const double fs = ms * (vs[k + 1] - vs[k]) / s.run.dt;  // force on the slider in step k
      const double ft = mt * (vt[k + 1] - vt[k]) / s.run.dt;  // force on the table
      worst = std::max({worst, std::abs(fs + f[k + 1]), std::abs(ft - fd[k + 1] - f[k + 1])});
      fmax = std::max(fmax, std::abs(f[k + 1]));
    }
    EXPECT_LT(worst, 1e-6 * std::max(1.0, fmax));
    EXPECT_GT(fmax, 1.0);  // the pad slipped (Fs = 1.5 N) under the table's acceleration
    // The slider slipped at some point and stuck at another.
    const auto& slip = tr.contact_slip[0];
    EXPECT_GT(std::accumulate(slip.begin(), slip.end(), 0), 10);
    EXPECT_LT(std::accumulate(slip.begin(), slip.end(), 0), static_cast<int>(slip.size()) - 10);
  }
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& m : v) s += m + "\n";
  return s;
}

TEST(Assembly, ValidationNamesTheKeyPath) {
  Assembly a = two_body_chain(1, 1, 10, 10);
  EXPECT_TRUE(validate(a).empty()) << joined(validate(a));
  auto bad = a;
  bad.springs[1].b = 1;  // spring to itself
  EXPECT_NE(joined(validate(bad)).find("plant.springs[1]: connects body 'm2' to itself"), std::string::npos)
      << joined(validate(bad));
  bad = a;
  bad.bodies[1].mass = -1;
  EXPECT_NE(joined(validate(bad)).find("plant.bodies[1].mass"), std::string::npos);
  bad = a;
  bad.springs[1].b = 5;
  EXPECT_NE(joined(validate(bad)).find("plant.springs[1].b: body index 5"), std::string::npos);
  bad = a;
  bad.springs.pop_back();  // m2 floats
  EXPECT_NE(joined(validate(bad)).find("plant.bodies[1]: body 'm2' is connected neither"), std::string::npos);
  bad.drives.push_back({"f", DrivePart::Kind::Force, 1, Signal::constant(1.0)});
  EXPECT_TRUE(validate(bad).empty()) << joined(validate(bad));
  bad = a;
  bad.springs[0].name = "m1";
  EXPECT_NE(joined(validate(bad)).find("plant.springs[0].name: 'm1' is used twice"), std::string::npos);
  bad = a;
  for (int i = 0; i < 8; ++i) bad.bodies.push_back({"extra" + std::to_string(i), 1.0});
  EXPECT_NE(joined(validate(bad)).find("plant.bodies: 10 bodies"), std::string::npos);
}

TEST(Assembly, StepAboveTheStiffestModeIsRejected) {
  AssemblyScenario s;
  s.name = "stiff";
  s.plant = two_body_chain(1, 0.01, 10, 1e6);
  s.plant.drives = {{"f", DrivePart::Kind::Force, 0, Signal::constant(1.0)}};
  const double lim = stability_limit_dt(s.plant);
  s.run = {1.01 * lim, 1.0, 1};
  try {
    AssemblySimulation sim(s);
    FAIL() << "accepted dt above the limit";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run.dt"), std::string::npos) << e.what();
  }
  s.run.dt = 0.5 * lim;
  EXPECT_NO_THROW(simulate(s));
}

std::string preset(const std::string& name) { return std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name; }

// Live edits (the window's Simulation and Plant tabs): values change between steps, the state is
// kept. The same values again leave the run as it would have been; a spring's new stiffness is in
// the very next step's spring force, k (x_a - x_b) at the step's start; a contact given another
// model restarts virgin while the other contact keeps its state; another structure or an invalid
// value is refused naming the key, and nothing changes.
TEST(Assembly, LiveEditsChangeValuesAndKeepTheState) {
  const AssemblyScenario sc =
      load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/three_body_chain.json");
  AssemblySimulation a(sc), b(sc);
  a.advance(123457);
  b.advance(123457);
  b.set_plant(sc.plant);  // the same values
  a.advance(50000);
  b.advance(50000);
  EXPECT_EQ(a.trace().values, b.trace().values);
  for (std::size_t j = 0; j < 2; ++j)
    EXPECT_EQ(a.trace().element_force[j], b.trace().element_force[j]);

  Assembly stiffer = sc.plant;
  ASSERT_EQ(stiffer.springs[0].name, "k12");
  stiffer.springs[0].stiffness = 800.0;
  b.set_plant(stiffer);
  // Up to the step that records a sample (every run.record_every steps), then that step.
  const auto every = static_cast<std::uint64_t>(sc.run.record_every);
  const auto step = static_cast<std::uint64_t>(std::llround(b.time() / sc.run.dt));
  b.advance((every - 1 - step % every + every) % every);
  const std::vector<double> x0(b.positions().begin(), b.positions().end());
  b.advance(1);
  ASSERT_EQ(std::llround(b.time() / sc.run.dt) % static_cast<long long>(every), 0);
  const auto c = static_cast<std::size_t>(b.trace().channel("F.k12"));
  EXPECT_EQ(b.trace().values[(b.trace().size() - 1) * b.trace().channels.size() + c],
            800.0 * (x0[0] - x0[1]));

  const std::vector<double> other(b.contact_state(1).begin(), b.contact_state(1).end());
  ModelParams lugre = model_info("lugre").defaults();
  b.set_friction(lugre, 0);
  EXPECT_EQ(b.contact_model(0).info().tag, "lugre");
  std::vector<double> virgin(b.contact_model(0).state_size());
  b.contact_model(0).reset(virgin);
  EXPECT_EQ(std::vector<double>(b.contact_state(0).begin(), b.contact_state(0).end()), virgin);
  EXPECT_EQ(std::vector<double>(b.contact_state(1).begin(), b.contact_state(1).end()), other);
  b.advance(1000);
  const AssemblyTrace& tr = b.trace();
  EXPECT_EQ(tr.n_elements[0], b.contact_model(0).element_count());
  EXPECT_EQ(tr.element_force[0].size(), tr.size() * tr.n_elements[0]);
  EXPECT_EQ(tr.element_slip[0].size(), tr.size() * tr.n_elements[0]);

  const double t = b.time();
  const std::vector<double> x1(b.positions().begin(), b.positions().end());
  Assembly fewer = stiffer;
  fewer.springs.pop_back();
  try {
    b.set_plant(fewer);
    ADD_FAILURE() << "another structure accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.springs: 1 instead of 2"), std::string::npos)
        << e.what();
  }
  Assembly bad = stiffer;
  bad.bodies[1].mass = -1.0;
  try {
    b.set_plant(bad);
    ADD_FAILURE() << "a negative mass accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.bodies[1].mass"), std::string::npos) << e.what();
  }
  EXPECT_EQ(b.time(), t);
  EXPECT_EQ(std::vector<double>(b.positions().begin(), b.positions().end()), x1);
  EXPECT_EQ(b.scenario().plant.bodies[1].mass, sc.plant.bodies[1].mass);
  EXPECT_EQ(b.contact_model(0).info().tag, "lugre");
}

TEST(AssemblyIo, Version2PresetsLoadRoundTripAndRun) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    SCOPED_TRACE(e.path().string());
    const AssemblyScenario a = load_assembly_scenario(e.path().string());  // v1 and v2 alike
    const std::string out = (fs::temp_directory_path() / ("gmslab_asm_rt_" + std::to_string(getpid()) + ".json")).string();
    save_assembly_scenario(a, out);
    EXPECT_EQ(load_assembly_scenario(out), a);
    fs::remove(out);
    if (file_schema_version(e.path().string()) != 2) continue;
    ++n;
    AssemblyScenario shortened = a;
    shortened.run.duration = std::min(a.run.duration, 2.0);
    const auto tr = simulate(shortened);
    EXPECT_GT(tr.size(), 10u);
  }
  EXPECT_GE(n, 4);
}

TEST(AssemblyIo, Version1LoadsAsTheOneBodyAssembly) {
  const Scenario s = load_scenario(preset("fig4_stick_slip.json"));
  EXPECT_EQ(load_assembly_scenario(preset("fig4_stick_slip.json")), assembly_from_scenario(s));
}

TEST(AssemblyIo, Fig3SchemeGivesTheFig4Trace) {
  AssemblyScenario a = load_assembly_scenario(preset("fig3_stick_slip_scheme.json"));
  Scenario s = load_scenario(preset("fig4_stick_slip.json"));
  a.run.duration = s.run.duration = 8.0;
  const auto ta = simulate(a);
  const auto tb = simulate(s);
  ASSERT_EQ(ta.size(), tb.size());
  const auto x = ta.series("x.block"), f = ta.series("F.surface");
  for (std::size_t k = 0; k < tb.size(); ++k) {
    ASSERT_EQ(x[k], tb.x[k]) << k;
    ASSERT_EQ(f[k], tb.friction[k]) << k;
  }
}

std::string load_error(const std::string& text) {
  const std::string path =
      (fs::temp_directory_path() / ("gmslab_asm_bad_" + std::to_string(getpid()) + ".json")).string();
  write_file_atomic(path, text);
  std::string msg;
  try {
    load_assembly_scenario(path);
  } catch (const InputError& e) {
    msg = e.what();
  }
  fs::remove(path);
  return msg;
}

std::string with_plant(const std::string& plant) {
  return R"({"schema_version": 2, "name": "t", "plant": )" + plant +
         R"(, "run": {"dt": 1e-5, "duration": 1}})";
}

TEST(AssemblyIo, TraceCsvHasEveryOutputAndSlipFlag) {
  AssemblyScenario s = load_assembly_scenario(preset("slider_on_table.json"));
  s.run.duration = 0.5;
  const auto tr = simulate(s);
  std::ostringstream o;
  write_assembly_trace_csv(tr, o);
  std::istringstream in(o.str());
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "t_s,x.slider_m,v.slider_mps,x.table_m,v.table_mps,F.pad_N,F.holder_N,F.bearing_N,F.belt_N,slip.pad");
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 9) << line;
  }
  EXPECT_EQ(rows, tr.size());
  // Full precision: the last row's table position reads back exactly.
  const std::string last = o.str().substr(o.str().rfind('\n', o.str().size() - 2) + 1);
  std::istringstream cells(last);
  std::string cell;
  for (int i = 0; i < 4; ++i) std::getline(cells, cell, ',');
  EXPECT_EQ(std::stod(cell), tr.series("x.table").back());
}

TEST(AssemblyIo, LoadingErrorsNameTheKeyPath) {
  const std::string bodies = R"("bodies": [{"name": "m1", "mass": 1}, {"name": "m2", "mass": 2}])";
  const std::string ok = with_plant("{" + bodies + R"(, "springs": [{"name": "k", "a": "m1", "b": "ground", "stiffness": 10},
      {"name": "k2", "a": "m1", "b": "m2", "stiffness": 10}]})");
  EXPECT_EQ(load_error(ok), "");
  struct Case {
    std::string plant, expect;
  };
  const std::vector<Case> cases = {
      {"{" + bodies + R"(, "springs": [{"name": "k", "a": "m1", "b": "lod", "stiffness": 10}]})",
       "key 'plant.springs[0].b': unknown body 'lod' (bodies: m1, m2, or ground)"},
      {"{" + bodies + R"(, "springs": [{"name": "k", "a": "m2", "b": "m2", "stiffness": 10}]})",
       "key 'plant.springs[0]': connects m2 to itself"},
      {"{" + bodies + R"(, "springs": [{"name": "k", "a": "m1", "b": "ground", "stiffness": 10}]})",
       "key 'plant.bodies[1]': body 'm2' is connected neither to ground nor to a drive"},
      {R"({"bodies": [{"name": "m1", "mass": -1}]})", "key 'plant.bodies[0].mass'"},
      {"{" + bodies + R"(, "dampers": [{"name": "c", "a": "m1", "b": "m2", "damping": -3}]})",
       "key 'plant.dampers[0].damping'"},
      {"{" + bodies + R"(, "contacts": [{"name": "f", "a": "m1", "b": "m3", "friction": {"model": "coulomb", "Fs": 1, "Fc": 1, "sigma2": 0, "v_stick": 1e-5}}]})",
       "key 'plant.contacts[0].b': unknown body 'm3'"},
      {"{" + bodies + R"(, "drives": [{"name": "d", "type": "force", "body": "ground", "signal": {"type": "constant", "value": 1}}]})",
       "key 'plant.drives[0].body'"},
      {"{" + bodies + R"(, "springz": []})", "plant.springz"},
  };
  for (const auto& c : cases) {
    const std::string msg = load_error(with_plant(c.plant));
    EXPECT_NE(msg.find(c.expect), std::string::npos) << "got: " << msg << "\nexpected: " << c.expect;
    EXPECT_NE(msg.find("gmslab_asm_bad_"), std::string::npos) << "the file is named: " << msg;
  }
  // A v2 file through the one-body loader: a clear pointer, not a version mismatch alone.
  try {
    load_scenario(preset("two_mass_drive.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("assembled plant"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gmslab
