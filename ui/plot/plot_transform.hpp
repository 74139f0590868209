// gmslab ui: the data-to-pixel transform of one plot, a value type (pure; no ImGui).
//
// Data limits [x0, x1] x [y0, y1] map linearly onto the pixel rectangle [px0, px1] x [py0, py1]
// with screen y growing downwards (y0 at the bottom edge py1, y1 at the top edge py0):
//   px = px0 + (x - x0) (px1 - px0) / (x1 - x0)
//   py = py1 - (y - y0) (py1 - py0) / (y1 - y0)
// zoomed() and panned() return new data limits for the interactions, so the widget's view state
// is just the four limits.
#pragma once

namespace gmslab::ui {

struct PlotTransform {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;          // data limits (axis units)
  double px0 = 0, py0 = 0, px1 = 1, py1 = 1;      // pixel rectangle, py0 = top

  double to_px_x(double x) const { return px0 + (x - x0) * (px1 - px0) / (x1 - x0); }
  double to_px_y(double y) const { return py1 - (y - y0) * (py1 - py0) / (y1 - y0); }
  double from_px_x(double px) const { return x0 + (px - px0) * (x1 - x0) / (px1 - px0); }
  double from_px_y(double py) const { return y0 + (py1 - py) * (y1 - y0) / (py1 - py0); }

  // Scale the data ranges by `fx`, `fy` (< 1 zooms in) keeping the data point under the pixel
  // (px, py) fixed.
  PlotTransform zoomed(double px, double py, double fx, double fy) const {
    PlotTransform t = *this;
    const double cx = from_px_x(px), cy = from_px_y(py);
    t.x0 = cx + (x0 - cx) * fx;
    t.x1 = cx + (x1 - cx) * fx;
    t.y0 = cy + (y0 - cy) * fy;
    t.y1 = cy + (y1 - cy) * fy;
    return t;
  }
  // Move the view so the content follows a mouse drag of (dpx, dpy) pixels.
  PlotTransform panned(double dpx, double dpy) const {
    PlotTransform t = *this;
    const double dx = dpx * (x1 - x0) / (px1 - px0);
    const double dy = dpy * (y1 - y0) / (py1 - py0);
    t.x0 -= dx;
    t.x1 -= dx;
    t.y0 += dy;
    t.y1 += dy;
    return t;
  }
};

}  // namespace gmslab::ui
