// Switching the Design tab's plant between gross sliding and presliding by clicking its radio
// button (scripted mouse): the view fits the new locus (the presliding poles near +-460j for
// Fig. 4 lie far outside the sliding view) and a gain picked on the old locus is dropped.
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <cmath>

#include "core/io/scenario_io.hpp"
#include "tests/ui/app_frame.hpp"
#include "ui/app.hpp"
#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"

using namespace gmslab;
using gmslab::control::cplx;

using Harness = uitest::DesignHarness;

TEST(DesignRegimeSwitch, ThePresslidingLocusIsInViewAndTheStalePickIsGone) {
  Harness h;
  auto& d = h.s.design;
  ASSERT_EQ(d.settings.regime, "sliding");
  // Pick a branch point of the sliding locus (as a user reading a gain would).
  cplx best_s;
  double best = 1e300;
  for (const auto& br : d.out.locus.branches)
    for (const cplx& z : br)
      if (!std::isnan(z.real()) && std::abs(z - cplx(-20, 20)) < best) best = std::abs(z - cplx(-20, 20)), best_s = z;
  h.frame(h.px(best_s), true);
  h.frame(h.px(best_s), false);
  ASSERT_TRUE(d.picked);
  // Zoom in on the sliding locus (mouse wheel over the canvas): the view is now the user's.
  {
    const ImVec2 c = h.px(cplx(-30, 0));
    ImGui::GetIO().MouseWheel = 2.0f;
    h.frame(c, false);
    ImGui::GetIO().MouseWheel = 0.0f;
    h.frame(c, false);
  }
  ASSERT_TRUE(d.in.locus_view.has_value());
  // Click the "presliding" radio: the first radio button at the top of the left column. Found by
  // scanning its column (clicks elsewhere in that strip only focus fields or toggle nothing).
  bool switched = false;
  // (Below the menu and tab bars; if a click lands on a tab, the Design tab is selected again.)
  for (float y = 50; y < 260 && !switched; y += 3) {
    for (float x = 14; x <= 30 && !switched; x += 4) {
      if (h.s.view.tab != "Design") h.s.view.tab = "Design", h.s.select_tab = 2;
      h.frame(ImVec2(x, y), false);
      h.frame(ImVec2(x, y), true);
      h.frame(ImVec2(x, y), false);
      switched = d.settings.regime == "presliding";
    }
  }
  ASSERT_TRUE(switched) << "presliding radio not found";
  h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  EXPECT_FALSE(d.picked) << "the gain picked on the sliding locus is gone";
  EXPECT_FALSE(d.in.locus_view.has_value());
  ASSERT_EQ(d.out.plant.regime, control::Regime::Presliding);
  const auto& t = d.canvas;
  const auto poles = d.out.plant.g.poles();
  ASSERT_FALSE(poles.empty());
  for (const cplx& p : poles) {
    EXPECT_GE(p.real(), std::min(t.x0, t.x1));
    EXPECT_LE(p.real(), std::max(t.x0, t.x1));
    EXPECT_GE(p.imag(), std::min(t.y0, t.y1)) << p.imag();
    EXPECT_LE(p.imag(), std::max(t.y0, t.y1)) << p.imag();
  }
}
#endif
