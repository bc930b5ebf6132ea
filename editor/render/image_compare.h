// Tolerant image comparison for golden-image tests (ARCHITECTURE.md): a
// maximum and a mean per-channel difference, and a diff image on request.
#pragma once
#include <string>

#include "render/image.h"

namespace pliant::editor {

struct CompareResult {
  int max_diff = 0;          // largest |a - b| over all pixels and RGBA channels (0..255)
  double mean_diff = 0;      // mean |a - b| over all pixels and channels
  long differing_pixels = 0; // pixels with any channel differing by more than max_tol
  bool size_mismatch = false;
  bool pass = false;         // sizes equal, max_diff <= max_tol and mean_diff <= mean_tol
  std::string message;       // one line for test output
};

CompareResult compare(const Image& actual, const Image& golden, int max_tol, double mean_tol);

// |actual - golden| per RGB channel, amplified by `gain` and clamped; opaque.
// Pixels beyond max_tol are painted magenta so small failures are visible.
// Sizes must match (returns an empty image otherwise).
Image diff_image(const Image& actual, const Image& golden, int max_tol, float gain = 8.0f);

}  // namespace pliant::editor
