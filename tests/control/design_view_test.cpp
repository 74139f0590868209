// The design view's computation (core/control/design_session) for the Fig. 4 mass, and - when
// the app is built - its headless render: the PNG shows the desired-root diamonds and the
// compensator's green markers.
#include <gtest/gtest.h>

#include <tuple>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/control/design_session.hpp"
#include "core/io/scenario_io.hpp"

#ifdef GMSLAB_HEADLESS_EXE
#include <stb_image.h>
#endif

using namespace gmslab;
using namespace gmslab::control;

namespace {
const std::string kPreset = std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json";
}

TEST(DesignSession, UsableMaximumDesignPlacesSdAndFeedsBothLoops) {
  DesignInputs in;
  in.scenario = load_scenario(kPreset);
  in.root = {0.7, 60.0};
  in.reference = Signal::sine(0.0, 0.01, 2.0);
  const DesignOutputs out = compute_design(in);
  ASSERT_TRUE(out.error.empty()) << out.error;
  EXPECT_FALSE(out.error_kind.has_value());
  ASSERT_TRUE(out.compensator.has_value());
  EXPECT_EQ(out.compensator_kind, "usable_maximum");
  EXPECT_NEAR(out.compensator->p / out.compensator->z, 20.0, 1e-6);
  // s_d is a closed-loop pole of the drawn loop at its gain Kc.
  double best = 1e300;
  for (const cplx& p : out.closed_loop_poles) best = std::min(best, std::abs(p - in.root.s()));
  EXPECT_LT(best, 1e-6);
  // The linear loop is type 1: the unit step settles at 1.
  EXPECT_NEAR(out.step.y.back(), 1.0, 1e-3);
  // The friction loops cover two sine periods (1 s) and the feedforward lowers the RMS error.
  EXPECT_NEAR(out.plain().trace.t.back(), 1.0, 1e-9);
  EXPECT_LT(out.compensated().metrics.rms_error, out.plain().metrics.rms_error);
  // The plotted tracking errors are r - x of each loop, and their RMS is the metric's.
  for (const auto& [tr, e, m] : {std::tuple{&out.plain().trace, &out.plain().error, &out.plain().metrics},
                                 std::tuple{&out.compensated().trace, &out.compensated().error, &out.compensated().metrics}}) {
    ASSERT_EQ(e->size(), tr->t.size());
    double s2 = 0.0;
    for (std::size_t i = 0; i < e->size(); ++i) {
      EXPECT_EQ((*e)[i], tr->r[i] - tr->x[i]);
      s2 += (*e)[i] * (*e)[i];
    }
    EXPECT_NEAR(std::sqrt(s2 / static_cast<double>(e->size())), m->rms_error, 1e-12);
  }
}

TEST(DesignSession, FailuresAreReportedNotThrown) {
  DesignInputs in;
  in.scenario = load_scenario(kPreset);
  in.root = {0.7, 60.0};
  in.K = -3.0;
  const DesignOutputs out = compute_design(in);
  EXPECT_NE(out.error.find("design"), std::string::npos) << out.error;
  EXPECT_EQ(out.error_kind, ErrorKind::Input);  // typed: a bad desired K is bad input
  EXPECT_FALSE(out.compensator.has_value());
  // The plant's own locus is still there: 1/(s^2 + 0.4 s), two branches from 0 and -0.4.
  ASSERT_EQ(out.locus.branches.size(), 2u);
  EXPECT_NEAR(out.locus.breakaways.at(0).s.real(), -0.2, 1e-9);
}

TEST(DesignSession, NegativeSlidingDampingIsReportedWithThePlantLocus) {
  // At v0 = Vs the Stribeck slope (-367 N s/m) beats sigma2: an unstable real pole, K0 < 0.
  DesignInputs in;
  in.scenario = load_scenario(kPreset);
  in.velocity = 1e-3;
  const DesignOutputs out = compute_design(in);
  EXPECT_NE(out.error.find("K0"), std::string::npos) << out.error;
  EXPECT_LT(out.plant.damping, 0.0);
  ASSERT_EQ(out.locus.poles.size(), 2u);
  double pmax = -1e300;
  for (const cplx& p : out.locus.poles) pmax = std::max(pmax, p.real());
  EXPECT_NEAR(pmax, -out.plant.damping / out.plant.mass, 1e-9);
}

#ifdef GMSLAB_HEADLESS_EXE
TEST(DesignViewRender, HeadlessRenderShowsTheLocusMarkers) {
  const std::string out = (std::filesystem::temp_directory_path() / "gmslab_design_view.png").string();
  std::filesystem::remove(out);
  const std::string cmd = std::string(GMSLAB_HEADLESS_EXE) + " render " + kPreset +
                          " --view design --size 1200x800 --out " + out + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(out.c_str(), &w, &h, &n, 4);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 1200);
  EXPECT_EQ(h, 800);
  auto count = [&](int r, int g, int b) {
    int c = 0;
    for (int i = 0; i < w * h; ++i)
      c += std::abs(px[4 * i] - r) < 8 && std::abs(px[4 * i + 1] - g) < 8 && std::abs(px[4 * i + 2] - b) < 8;
    return c;
  };
  EXPECT_GT(count(204, 121, 167), 20);  // desired-root diamonds
  EXPECT_GT(count(0, 158, 115), 200);   // compensator zero, pole label and the green branch
  stbi_image_free(px);
}
#endif
