// The plot's data-to-pixel transform: round trips, zoom about the cursor, pan by the drag.
#include <gtest/gtest.h>

#include "ui/plot/plot_transform.hpp"

using gmslab::ui::PlotTransform;

TEST(PlotTransform, DataToPixelAndBackIsIdentityWithScreenYDown) {
  const PlotTransform t{-2.0, 3.0, 1e-6, 5e-6, 100, 50, 900, 650};
  EXPECT_DOUBLE_EQ(t.to_px_x(-2.0), 100);
  EXPECT_DOUBLE_EQ(t.to_px_x(3.0), 900);
  EXPECT_DOUBLE_EQ(t.to_px_y(1e-6), 650);  // bottom edge
  EXPECT_DOUBLE_EQ(t.to_px_y(5e-6), 50);   // top edge
  for (double x = -2; x <= 3; x += 0.37) EXPECT_NEAR(t.from_px_x(t.to_px_x(x)), x, 1e-12);
  for (double y = 1e-6; y <= 5e-6; y += 3.3e-7) EXPECT_NEAR(t.from_px_y(t.to_px_y(y)), y, 1e-18);
}

TEST(PlotTransform, ZoomKeepsTheDataPointUnderTheCursor) {
  const PlotTransform t{0, 10, -1, 1, 0, 0, 1000, 500};
  const double px = 237, py = 411;
  const double x = t.from_px_x(px), y = t.from_px_y(py);
  PlotTransform z = t.zoomed(px, py, 0.5, 0.25);
  z.px0 = t.px0, z.px1 = t.px1, z.py0 = t.py0, z.py1 = t.py1;
  EXPECT_NEAR(z.from_px_x(px), x, 1e-12);
  EXPECT_NEAR(z.from_px_y(py), y, 1e-12);
  EXPECT_NEAR(z.x1 - z.x0, 5.0, 1e-12);
  EXPECT_NEAR(z.y1 - z.y0, 0.5, 1e-12);
}

TEST(PlotTransform, PanMovesTheContentWithTheDrag) {
  const PlotTransform t{0, 10, -1, 1, 0, 0, 1000, 500};
  const double x = 4.2, y = 0.3;
  const double px = t.to_px_x(x), py = t.to_px_y(y);
  const PlotTransform p = t.panned(35, -20);  // drag right and up
  EXPECT_NEAR(p.to_px_x(x), px + 35, 1e-9);
  EXPECT_NEAR(p.to_px_y(y), py - 20, 1e-9);
}
