// gmslab app: the headless renderer. An OSMesa context (CPU, llvmpipe) with the ImGui OpenGL2
// backend draws the same ui:: frame functions as the window into a memory buffer, which is written
// as PNG. No display, no libGL. Deterministic: fixed DeltaTime, no mouse, no clocks; the same
// input gives the same bytes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"
#include "core/figures/figure.hpp"

namespace gmslab::app {

// One OSMesa + ImGui + plot context of a fixed size. Not copyable; one at a time per thread.
class Offscreen {
 public:
  // font_px <= 0: scaled with the height (17 px at 1000 px). Throws InternalError when
  // OSMesa cannot create the context.
  Offscreen(int width, int height, float font_px = 0.0f);
  ~Offscreen();
  Offscreen(const Offscreen&) = delete;
  Offscreen& operator=(const Offscreen&) = delete;

  // Runs `frames` ImGui frames (1/60 s each), calling draw() inside each, and returns the last
  // one as RGBA bytes, rows top to bottom (width * height * 4).
  const std::vector<unsigned char>& render(const std::function<void()>& draw, int frames = 3);

  int width() const { return w_; }
  int height() const { return h_; }

 private:
  int w_, h_;
  std::vector<unsigned char> gl_buf_, out_;
  void* ctx_ = nullptr;      // OSMesaContext
  void* imgui_ = nullptr;    // ImGuiContext
  void* plot_ = nullptr;     // ui::PlotContext: this renderer's plot view state (never shared)
};

// PNG bytes of an RGBA image (rows top to bottom).
std::string encode_png(int width, int height, const std::vector<unsigned char>& rgba);
// Writes the PNG atomically (write_file_atomic).
void write_png(const std::string& path, int width, int height, const std::vector<unsigned char>& rgba);

// Draws a Figure filling the whole frame on white, as in the paper (inside Offscreen::render).
void draw_figure_window(const Figure& f);

// `gmslab render`: load the preset (a file or a shipped preset's name), simulate to --time (or the
// end), draw the app's view, write PNG.
int render_command(const cli::RenderOptions& o);
// `gmslab figures`: every figure (or --only) to DIR/id.png + DIR/id.csv, with progress on stderr.
int figures_command(const cli::FiguresOptions& o);

}  // namespace gmslab::app
