// Keyframe outlines by marching squares (editor/render/contour).
#include "render/contour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace pliant::editor {
namespace {

TEST(Contour, CircleOutlineHasTheCircumferenceAndRadius) {
  const int n = 64;
  std::vector<float> v(n * n);
  const double r = 20;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) v[j * n + i] = float(r - std::hypot(i + 0.5 - 32, j + 0.5 - 32));  // signed distance
  auto segs = contour_lines(v.data(), n, n, 0.0f);
  double len = 0;
  for (const auto& s : segs) {
    len += std::hypot(s.b[0] - s.a[0], s.b[1] - s.a[1]);
    EXPECT_NEAR(std::hypot(s.a[0] - 32, s.a[1] - 32), r, 0.05);
  }
  EXPECT_NEAR(len, 2 * M_PI * r, 0.01 * 2 * M_PI * r);
}

TEST(Contour, ShapesTouchingTheBorderAreClosed) {
  std::vector<float> v(4 * 4, 1.0f);  // everything inside
  auto segs = contour_lines(v.data(), 4, 4, 0.5f);
  ASSERT_FALSE(segs.empty());
  // Closed: every end point is shared by exactly two segments; all lie outside the
  // cell centres' square, within half a cell of the grid border.
  std::map<std::pair<long, long>, int> ends;
  auto key = [](const std::array<float, 2>& p) {
    return std::make_pair(std::lround(p[0] * 1e4), std::lround(p[1] * 1e4));
  };
  for (const auto& s : segs) {
    ++ends[key(s.a)];
    ++ends[key(s.b)];
    for (const auto& p : {s.a, s.b}) {
      EXPECT_GE(std::max({0.5f - p[0], p[0] - 3.5f, 0.5f - p[1], p[1] - 3.5f}), 0.0f);
      EXPECT_LE(std::max({-0.5f - p[0], p[0] - 4.5f, -0.5f - p[1], p[1] - 4.5f}), 0.0f);
    }
  }
  for (const auto& [p, n] : ends) EXPECT_EQ(n, 2);
}

}  // namespace
}  // namespace pliant::editor
