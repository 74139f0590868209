// The Design panel driven by scripted mouse input (an ImGui context without a renderer): dragging
// the desired root moves s_d to the point under the mouse and the design follows; clicking a
// branch reads its gain and the closed-loop poles there. Built only with the app (ImGui).
#if __has_include(<imgui.h>)
#include <gtest/gtest.h>
#include <imgui.h>

#include <cmath>

#include "core/io/scenario_io.hpp"
#include "ui/app.hpp"
#include "ui/design/design_view.hpp"
#include "ui/plot/plot.hpp"
#include "tests/ui/app_frame.hpp"

using namespace gmslab;
using gmslab::control::cplx;

using Harness = uitest::DesignHarness;

TEST(DesignViewInput, DraggingTheDesiredRootMovesSdAndTheDesignFollows) {
  Harness h;
  ASSERT_TRUE(h.d().out.error.empty()) << h.d().out.error;
  const cplx start = h.d().in.root.s();  // zeta 0.7, wn 60
  h.frame(h.px(start), true);            // press on the diamond
  const cplx target(-30.0, 40.0);        // wn = 50, zeta = 0.6
  h.frame(h.px(0.5 * (start + target)), true);
  h.frame(h.px(target), true);
  h.frame(h.px(target), false);          // release
  h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  const double tol_px = 1.5 * (h.d().canvas.x1 - h.d().canvas.x0) / (h.d().canvas.px1 - h.d().canvas.px0);
  EXPECT_NEAR(h.d().in.root.wn, 50.0, 2 * tol_px);
  EXPECT_NEAR(h.d().in.root.zeta, 0.6, 2 * tol_px / 50.0);
  // The design was recomputed for the new root: it is a closed-loop pole of the drawn loop.
  double best = 1e300;
  for (const cplx& p : h.d().out.closed_loop_poles) best = std::min(best, std::abs(p - h.d().in.root.s()));
  EXPECT_LT(best, 1e-6);
}

TEST(DesignViewInput, ClickingABranchReadsItsGainAndTheClosedLoopPolesThere) {
  Harness h;
  const auto& rl = h.d().out.locus;
  // A branch sample well inside the canvas: the one closest to -20 + 20j.
  cplx best_s;
  double best = 1e300;
  for (const auto& br : rl.branches)
    for (const cplx& s : br)
      if (!std::isnan(s.real()) && std::abs(s - cplx(-20, 20)) < best) best = std::abs(s - cplx(-20, 20)), best_s = s;
  h.frame(h.px(best_s), true);
  h.frame(h.px(best_s), false);
  ASSERT_TRUE(h.d().picked);
  EXPECT_LT(std::abs(h.d().picked_s - best_s), 0.02 * (h.d().canvas.x1 - h.d().canvas.x0));
  // The picked gain puts a closed-loop pole at the picked point (den + k num = 0 there).
  double d = 1e300;
  for (const cplx& p : h.d().picked_poles) d = std::min(d, std::abs(p - h.d().picked_s));
  EXPECT_LT(d, 1e-6 * (1 + std::abs(h.d().picked_s)));
  EXPECT_GT(h.d().picked_k, 0.0);
}
// Dragging the compensator's zero (green o) along the real axis switches the design to manual: the
// zero follows the mouse, the drawn loop and its closed-loop poles are those of the new compensator
// (1 + Kc L(s) = 0 at each), and the pole stays where it was.
TEST(DesignViewInput, DraggingTheCompensatorZeroMakesAManualDesignThatTheLocusFollows) {
  Harness h;
  ASSERT_TRUE(h.d().out.compensator.has_value());
  const double z0 = h.d().out.compensator->z, p0 = h.d().out.compensator->p;
  const double z1 = 0.6 * z0;  // move the zero towards the origin
  h.frame(h.px(cplx(-z0, 0)), true);
  h.frame(h.px(cplx(-0.5 * (z0 + z1), 0)), true);
  h.frame(h.px(cplx(-z1, 0)), true);
  h.frame(h.px(cplx(-z1, 0)), false);
  h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  const auto& out = h.d().out;
  ASSERT_TRUE(out.compensator.has_value());
  EXPECT_EQ(out.compensator_kind, "manual");
  const double tol = 1.5 * (h.d().canvas.x1 - h.d().canvas.x0) / (h.d().canvas.px1 - h.d().canvas.px0);
  EXPECT_NEAR(out.compensator->z, z1, tol);
  EXPECT_NEAR(out.compensator->p, p0, 1e-9 * p0);
  bool zero_in_loop = false;
  for (const cplx& z : out.loop.zeros()) zero_in_loop |= std::abs(z - cplx(-out.compensator->z, 0)) < 1e-6 * z0;
  EXPECT_TRUE(zero_in_loop);
  ASSERT_FALSE(out.closed_loop_poles.empty());
  for (const cplx& p : out.closed_loop_poles)
    EXPECT_LT(std::abs(1.0 + out.compensator->Kc * out.loop(p)), 1e-6) << p.real() << " + j" << p.imag();
}

// Lead-lag and PID (two sections): dragging one section's zero moves exactly that zero; Kc, the
// other zero and both poles stay bit for bit, and the drawn loop carries the moved zero.
TEST(DesignViewInput, DraggingOneSectionsZeroChangesExactlyThatZero) {
  for (auto type : {control::CompensatorType::LeadLag, control::CompensatorType::PID}) {
    Harness h;
    h.d().settings.compensator = type;
    h.d().dirty = true;
    for (int i = 0; i < 2; ++i) h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
    ASSERT_TRUE(h.d().out.compensator && h.d().out.compensator->second) << h.d().out.error;
    const control::LeadCompensator c0 = *h.d().out.compensator;
    const double z0 = c0.second->z, z1 = 1.6 * z0;  // the second section's zero, moved left
    h.frame(h.px(cplx(-z0, 0)), true);
    h.frame(h.px(cplx(-0.5 * (z0 + z1), 0)), true);
    h.frame(h.px(cplx(-z1, 0)), true);
    h.frame(h.px(cplx(-z1, 0)), false);
    h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
    const auto& out = h.d().out;
    ASSERT_TRUE(out.compensator && out.compensator->second);
    EXPECT_EQ(out.compensator_kind, "manual");
    const double tol = 1.5 * (h.d().canvas.x1 - h.d().canvas.x0) / (h.d().canvas.px1 - h.d().canvas.px0);
    EXPECT_NEAR(out.compensator->second->z, z1, tol);
    EXPECT_NE(out.compensator->second->z, z0);
    EXPECT_EQ(out.compensator->second->p, c0.second->p);
    EXPECT_EQ(out.compensator->z, c0.z);
    EXPECT_EQ(out.compensator->p, c0.p);
    EXPECT_EQ(out.compensator->Kc, c0.Kc);
    bool zero_in_loop = false;
    for (const cplx& z : out.loop.zeros()) zero_in_loop |= std::abs(z - cplx(-out.compensator->second->z, 0)) < 1e-6 * z1;
    EXPECT_TRUE(zero_in_loop);
    for (const cplx& p : out.closed_loop_poles)
      EXPECT_LT(std::abs(1.0 + out.compensator->Kc * out.loop(p)), 1e-6) << p.real() << " + j" << p.imag();
  }
}

// With a sample time the locus canvas shows the z plane; the wheel over it zooms about the mouse
// and the z-plane locus is recomputed for the zoomed view (its resolution follows the view).
TEST(DesignViewInput, WheelZoomsTheZPlaneLocusAndItIsRecomputedForTheView) {
  Harness h;
  h.d().settings.sample_time = 0.01;
  h.d().dirty = true;
  for (int i = 0; i < 3; ++i) h.frame(ImVec2(-FLT_MAX, -FLT_MAX), false);
  ASSERT_TRUE(h.d().out.z_locus.has_value());
  ASSERT_TRUE(h.d().z_plane);
  const control::ViewBox v0 = h.d().out.z_locus->locus.view;
  const auto& t = h.d().z_canvas;
  const ImVec2 at(static_cast<float>(t.to_px_x(0.5)), static_cast<float>(t.to_px_y(0.2)));
  ImGui::GetIO().MouseWheel = 3.0f;
  h.frame(at, false);
  ImGui::GetIO().MouseWheel = 0.0f;
  h.frame(at, false);
  ASSERT_TRUE(h.d().in.z_locus_view.has_value());
  const control::ViewBox& v1 = *h.d().in.z_locus_view;
  EXPECT_LT(v1.width(), 0.7 * v0.width());
  EXPECT_TRUE(v1.contains(cplx(0.5, 0.2)));  // zoomed about the mouse
  // Recomputed: the drawn locus was resolved for the zoomed view.
  EXPECT_DOUBLE_EQ(h.d().out.z_locus->locus.view.re_min, v1.re_min);
  EXPECT_DOUBLE_EQ(h.d().out.z_locus->locus.view.width(), v1.width());
}
#endif
