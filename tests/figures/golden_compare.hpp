// Test helper: comparing a render with a golden image. The tolerance survives what differs between
// llvmpipe builds (anti-aliased edges: small per-pixel differences) but not a missing curve, axis,
// label or a layout change:
//   - pixels whose largest channel difference exceeds 64 levels: at most 0.05 % of the image;
//   - 8x8 block means (a downscaled comparison): no block may differ by more than 24 levels.
// Used by the figure goldens (golden_images_test.cpp) and the app view goldens
// (golden_views_test.cpp; those are stored at half resolution and compared with 4x4 blocks, the
// same 8x8 area of the full render).
#pragma once

#include <stb_image.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

namespace gmslab::golden {

struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;  // 3 bytes per pixel
  int at(int x, int y, int c) const { return rgb[(static_cast<std::size_t>(y) * w + x) * 3 + c]; }
  unsigned char& ref(int x, int y, int c) { return rgb[(static_cast<std::size_t>(y) * w + x) * 3 + c]; }
};

struct Difference {
  std::size_t strong_pixels = 0;  // largest channel difference > 64
  double worst_block = 0.0;       // largest BxB block mean difference [levels]
};

inline Difference compare(const Image& a, const Image& b, int B = 8) {
  Difference d;
  for (int by = 0; by + B <= a.h; by += B)
    for (int bx = 0; bx + B <= a.w; bx += B) {
      double sum = 0.0;
      for (int y = by; y < by + B; ++y)
        for (int x = bx; x < bx + B; ++x) {
          int worst = 0;
          for (int c = 0; c < 3; ++c) {
            const int diff = std::abs(a.at(x, y, c) - b.at(x, y, c));
            worst = std::max(worst, diff);
            sum += diff / 3.0;
          }
          d.strong_pixels += worst > 64;
        }
      d.worst_block = std::max(d.worst_block, sum / (B * B));
    }
  return d;
}

inline bool acceptable(const Difference& d, const Image& im) {
  return d.strong_pixels <= static_cast<std::size_t>(0.0005 * im.w * im.h) && d.worst_block <= 24.0;
}

inline Image load(const std::string& path) {
  Image im;
  int n = 0;
  unsigned char* p = stbi_load(path.c_str(), &im.w, &im.h, &n, 3);
  if (p) {
    im.rgb.assign(p, p + static_cast<std::size_t>(im.w) * im.h * 3);
    stbi_image_free(p);
  }
  return im;
}

// 2x2 box mean (rounded): w/2 x h/2.
inline Image half(const Image& a) {
  Image h;
  h.w = a.w / 2, h.h = a.h / 2;
  h.rgb.resize(static_cast<std::size_t>(h.w) * h.h * 3);
  for (int y = 0; y < h.h; ++y)
    for (int x = 0; x < h.w; ++x)
      for (int c = 0; c < 3; ++c)
        h.ref(x, y, c) = static_cast<unsigned char>(
            (a.at(2 * x, 2 * y, c) + a.at(2 * x + 1, 2 * y, c) + a.at(2 * x, 2 * y + 1, c) + a.at(2 * x + 1, 2 * y + 1, c) + 2) / 4);
  return h;
}

}  // namespace gmslab::golden
