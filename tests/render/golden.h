// Golden-image checks for GoogleTest (render tests and scripted editor tests).
//
//   pliant::test::expect_matches_golden(image, golden_path, diff_path, max_tol, mean_tol);
//   PLIANT_EXPECT_MATCHES_GOLDEN(image, golden_path, diff_path[, max_tol[, mean_tol]]);
//
// Compares `image` with the PNG at golden_path (editor::compare: max per-channel
// difference <= max_tol and mean difference <= mean_tol). On failure it writes
// diff_path (amplified |difference|, magenta beyond max_tol) and the actual image
// beside it (<diff_path minus .png>_actual.png), and the gtest failure names both.
// With PLIANT_UPDATE_GOLDEN=1 in the environment it (re)writes golden_path
// instead (creating its folder) and passes. Folders of diff_path are created.
#pragma once
#include <gtest/gtest.h>

#include <string>

#include "render/image.h"
#include "render/image_compare.h"

namespace pliant::test {

inline constexpr int kGoldenMaxTol = 8;
inline constexpr double kGoldenMeanTol = 0.5;

// True when PLIANT_UPDATE_GOLDEN=1.
bool updating_goldens();

// The check as an AssertionResult, for EXPECT_TRUE/ASSERT_TRUE.
::testing::AssertionResult matches_golden(const editor::Image& image, const std::string& golden_path,
                                          const std::string& diff_path, int max_tol = kGoldenMaxTol,
                                          double mean_tol = kGoldenMeanTol);

// EXPECT-style: records a non-fatal gtest failure.
inline void expect_matches_golden(const editor::Image& image, const std::string& golden_path,
                                  const std::string& diff_path, int max_tol = kGoldenMaxTol,
                                  double mean_tol = kGoldenMeanTol) {
  EXPECT_TRUE(matches_golden(image, golden_path, diff_path, max_tol, mean_tol));
}

}  // namespace pliant::test

// Same check; the failure is reported at the caller's line.
#define PLIANT_EXPECT_MATCHES_GOLDEN(image, golden_path, ...) \
  EXPECT_TRUE(::pliant::test::matches_golden(image, golden_path, __VA_ARGS__))
