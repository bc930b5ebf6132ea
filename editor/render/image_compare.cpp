#include "render/image_compare.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace pliant::editor {

CompareResult compare(const Image& actual, const Image& golden, int max_tol, double mean_tol) {
  CompareResult r;
  char buf[256];
  if (actual.width != golden.width || actual.height != golden.height || actual.empty()) {
    r.size_mismatch = true;
    std::snprintf(buf, sizeof buf, "size mismatch: actual %dx%d, golden %dx%d", actual.width,
                  actual.height, golden.width, golden.height);
    r.message = buf;
    return r;
  }
  const size_t n = static_cast<size_t>(actual.width) * actual.height;
  long long sum = 0;
  for (size_t p = 0; p < n; ++p) {
    bool beyond = false;
    for (int c = 0; c < 4; ++c) {
      const int d = std::abs(int(actual.rgba[p * 4 + c]) - int(golden.rgba[p * 4 + c]));
      sum += d;
      r.max_diff = std::max(r.max_diff, d);
      beyond |= d > max_tol;
    }
    r.differing_pixels += beyond;
  }
  r.mean_diff = static_cast<double>(sum) / static_cast<double>(n * 4);
  r.pass = r.max_diff <= max_tol && r.mean_diff <= mean_tol;
  std::snprintf(buf, sizeof buf, "max diff %d (tolerance %d), mean diff %.4f (tolerance %.4f), %ld pixels beyond tolerance",
                r.max_diff, max_tol, r.mean_diff, mean_tol, r.differing_pixels);
  r.message = buf;
  return r;
}

Image diff_image(const Image& actual, const Image& golden, int max_tol, float gain) {
  Image d;
  if (actual.width != golden.width || actual.height != golden.height || actual.empty()) return d;
  d.width = actual.width;
  d.height = actual.height;
  d.rgba.resize(actual.rgba.size());
  const size_t n = static_cast<size_t>(d.width) * d.height;
  for (size_t p = 0; p < n; ++p) {
    int worst = 0;
    for (int c = 0; c < 4; ++c)
      worst = std::max(worst, std::abs(int(actual.rgba[p * 4 + c]) - int(golden.rgba[p * 4 + c])));
    for (int c = 0; c < 3; ++c) {
      const float v = gain * std::abs(int(actual.rgba[p * 4 + c]) - int(golden.rgba[p * 4 + c]));
      d.rgba[p * 4 + c] = static_cast<uint8_t>(std::min(255.0f, v));
    }
    if (worst > max_tol) {
      d.rgba[p * 4 + 0] = 255;
      d.rgba[p * 4 + 1] = 0;
      d.rgba[p * 4 + 2] = 255;
    }
    d.rgba[p * 4 + 3] = 255;
  }
  return d;
}

}  // namespace pliant::editor
