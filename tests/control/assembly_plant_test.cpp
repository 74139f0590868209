// The linear plant of an assembly from a drive to an output (core/control/assembly_plant.hpp):
// against the closed form of the two-mass train (collocated and non-collocated), and against the
// one-body linear plant for every v1 preset.
#include <gtest/gtest.h>

#include <complex>
#include <filesystem>
#include <random>

#include "core/control/assembly_plant.hpp"
#include "core/error.hpp"
#include "core/friction/gms.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab::control {
namespace {

TEST(AssemblyPlant, TwoMassTrainMatchesTheClosedForm) {
  std::mt19937 rng(1112);
  std::uniform_real_distribution<double> u(0.2, 3.0);
  for (int trial = 0; trial < 30; ++trial) {
    const double m1 = u(rng), m2 = u(rng), k = 1000 * u(rng), c = u(rng);
    ModelParams f1 = GmsParams::reference(true).to_params(), f2 = GmsParams::reference(trial % 2 == 0).to_params();
    f2.set_scalar("Fs", 3.0);
    f2.set_scalar("Fc", 2.0);
    Assembly a;
    a.bodies = {{"motor", m1}, {"load", m2}};
    a.springs = {{"shaft", 0, 1, k}};
    a.dampers = {{"loss", 0, 1, c}};
    a.contacts = {{"f1", 0, kGround, f1}, {"f2", 1, kGround, f2}};
    a.drives = {{"u", DrivePart::Kind::Force, 0, Signal::constant(0.0)}};
    for (Regime r : {Regime::Presliding, Regime::Sliding}) {
      const double v0 = 0.02 * u(rng);
      double k1 = 0, k2 = 0, c1, c2;
      if (r == Regime::Presliding) {
        k1 = stuck_stiffness(f1), k2 = stuck_stiffness(f2);
        c1 = contact_damping(f1), c2 = contact_damping(f2);
      } else {
        auto slope = [&](const ModelParams& p) {
          const auto m = build_model(p);
          return (m->steady_state(v0 * (1 + 1e-6)) - m->steady_state(v0 * (1 - 1e-6))) / (2e-6 * v0);
        };
        c1 = slope(f1), c2 = slope(f2);
      }
      const TransferFunction col = assembly_transfer_function(a, 0, "x.motor", r, r == Regime::Sliding ? v0 : 0.0);
      const TransferFunction non = assembly_transfer_function(a, 0, "x.load", r, r == Regime::Sliding ? v0 : 0.0);
      const TransferFunction vel = assembly_transfer_function(a, 0, "v.load", r, r == Regime::Sliding ? v0 : 0.0);
      for (int q = 0; q < 6; ++q) {
        const cplx s(-5.0 + 10.0 * u(rng), 50.0 * u(rng));
        const cplx a11 = m1 * s * s + (c + c1) * s + k + k1, a22 = m2 * s * s + (c + c2) * s + k + k2,
                   a12 = -(c * s + k);
        const cplx det = a11 * a22 - a12 * a12;
        const cplx g11 = a22 / det, g21 = -a12 / det;
        EXPECT_LT(std::abs(col(s) - g11), 1e-7 * std::abs(g11)) << "collocated, s = " << s;
        EXPECT_LT(std::abs(non(s) - g21), 1e-7 * std::abs(g21)) << "non-collocated, s = " << s;
        EXPECT_LT(std::abs(vel(s) - s * g21), 1e-7 * std::abs(s * g21)) << "velocity, s = " << s;
      }
      // Collocated: two zeros (the load's anti-resonance); non-collocated: one (-k/c).
      EXPECT_EQ(col.zeros().size(), 2u);
      ASSERT_EQ(non.zeros().size(), 1u);
      EXPECT_NEAR(non.zeros()[0].real(), -k / c, 1e-6 * k / c);
      EXPECT_EQ(col.poles().size(), 4u);
    }
  }
}

TEST(AssemblyPlant, OneBodyPresetsGiveTheOneBodyLinearPlant) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(GMSLAB_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    if (read_file(e.path().string()).find("\"schema_version\": 2") != std::string::npos) continue;
    const Scenario s = load_scenario(e.path().string());
    if (s.drive.kind != Drive::Kind::Force && s.drive.kind != Drive::Kind::Pull) continue;
    SCOPED_TRACE(e.path().string());
    // The one-body plant is force -> x with the pull spring left out; the assembly ties the body
    // to ground through it, so compare with the pull spring and damper added to the plant.
    Scenario s1 = s;
    const AssemblyScenario as = assembly_from_scenario(s);
    Assembly a = as.plant;
    if (s.drive.kind == Drive::Kind::Pull) {
      s1.plant.spring += s.drive.pull_spring;
      s1.plant.damper += s.drive.pull_damper;
      a.drives[0].kind = DrivePart::Kind::Force;
      a.springs.push_back({"pull_k", 0, kGround, s.drive.pull_spring});
      a.dampers.push_back({"pull_c", 0, kGround, s.drive.pull_damper});
    }
    for (Regime r : {Regime::Presliding, Regime::Sliding}) {
      const auto g1 = linear_plant(s1, r).g;
      const auto g2 = assembly_transfer_function(a, 0, "x.mass", r);
      for (double w : {0.5, 5.0, 50.0, 500.0}) {
        const cplx sw(0.0, w);
        EXPECT_LT(std::abs(g1(sw) - g2(sw)), 1e-8 * std::abs(g1(sw))) << to_string(r) << " w = " << w;
      }
    }
    ++n;
  }
  EXPECT_GE(n, 2);
}

TEST(AssemblyPlant, PullDriveInputIsThePointPosition) {
  const auto sc = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig3_stick_slip_scheme.json");
  const auto g = assembly_transfer_function(sc.plant, 0, "x.block", Regime::Sliding, 0.1);
  // Static gain: a point moved by 1 m moves the block by k_p / (k_p + 0) = 1 (sliding: no spring).
  EXPECT_NEAR(std::abs(g(cplx(0.0, 1e-6))), 1.0, 1e-6);
}

TEST(AssemblyPlant, BadDriveOrOutputIsNamed) {
  const auto sc = load_assembly_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/two_mass_drive.json");
  EXPECT_THROW(assembly_transfer_function(sc.plant, 3, "x.load", Regime::Presliding), InputError);
  try {
    assembly_transfer_function(sc.plant, 0, "x.lod", Regime::Presliding);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.lod"), std::string::npos);
  }
}

}  // namespace
}  // namespace gmslab::control
