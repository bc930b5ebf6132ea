// Orbit camera matrices against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "render/mat4.h"
#include "render/orbit_camera.h"

namespace pliant::editor {
namespace {

void expect_mat_near(const Mat4& a, const Mat4& b, float tol = 1e-5f) {
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(a[i], b[i], tol) << "element " << i << " (col " << i / 4 << ", row " << i % 4 << ")";
}

TEST(OrbitCamera, EyeOnPlusZAtZeroYawAndPitch) {
  OrbitCamera c;
  c.yaw_deg = 0;
  c.pitch_deg = 0;
  c.distance = 2;
  const auto e = c.eye();
  EXPECT_NEAR(e[0], 0, 1e-6);
  EXPECT_NEAR(e[1], 0, 1e-6);
  EXPECT_NEAR(e[2], 2, 1e-6);
  // Looking down -z from (0,0,2): identity rotation, translation (0,0,-2).
  Mat4 expect = mat4_identity();
  expect[14] = -2;
  expect_mat_near(c.view(), expect);
}

TEST(OrbitCamera, YawNinetyLooksDownMinusX) {
  OrbitCamera c;
  c.yaw_deg = 90;
  c.pitch_deg = 0;
  c.distance = 3;
  c.target = {1, 2, 3};
  const auto e = c.eye();
  EXPECT_NEAR(e[0], 4, 1e-5);
  EXPECT_NEAR(e[1], 2, 1e-5);
  EXPECT_NEAR(e[2], 3, 1e-5);
  // The target lands on the view axis at depth -distance; +y stays up.
  const auto t = mat4_apply(c.view(), {1, 2, 3, 1});
  EXPECT_NEAR(t[0], 0, 1e-5);
  EXPECT_NEAR(t[1], 0, 1e-5);
  EXPECT_NEAR(t[2], -3, 1e-5);
  const auto up = mat4_apply(c.view(), {1, 3, 3, 1});
  EXPECT_NEAR(up[1], 1, 1e-5);
  // Camera right = forward x up = (-1,0,0) x (0,1,0) = (0,0,-1): world -z is screen right.
  const auto r = mat4_apply(c.view(), {1, 2, 2, 1});
  EXPECT_NEAR(r[0], 1, 1e-5);
}

TEST(OrbitCamera, PitchRaisesTheEye) {
  OrbitCamera c;
  c.yaw_deg = 0;
  c.pitch_deg = 30;
  c.distance = 2;
  const auto e = c.eye();
  EXPECT_NEAR(e[1], 1.0f, 1e-5);                 // 2 sin 30
  EXPECT_NEAR(e[2], std::sqrt(3.0f), 1e-5);      // 2 cos 30
  const auto t = mat4_apply(c.view(), {0, 0, 0, 1});
  EXPECT_NEAR(t[2], -2, 1e-5);
}

TEST(OrbitCamera, PerspectiveMatchesGluPerspective) {
  OrbitCamera c;
  c.fov_deg = 90;
  const auto p = c.projection(2.0f);
  const float n = OrbitCamera::kNear, f = OrbitCamera::kFar;
  Mat4 expect{};
  expect[0] = 0.5f;  // cot(45 deg) / aspect
  expect[5] = 1.0f;
  expect[10] = (f + n) / (n - f);
  expect[11] = -1;
  expect[14] = 2 * f * n / (n - f);
  expect_mat_near(p, expect);
  // A point on the near plane maps to clip z = -w; on the far plane to +w.
  const auto a = mat4_apply(p, {0, 0, -n, 1});
  EXPECT_NEAR(a[2] / a[3], -1, 1e-4);
  const auto b = mat4_apply(p, {0, 0, -f, 1});
  EXPECT_NEAR(b[2] / b[3], 1, 1e-4);
}

TEST(OrbitCamera, Ortho2DFitsDomainWithMargin) {
  OrbitCamera c;
  // 64x48 domain (1 x 0.75) in a 4:3 viewport: height-limited, half height 0.5 * 1.05 * 0.75.
  const auto m = c.view_projection_2d(4.0f / 3.0f, 1.0f, 0.75f);
  const float half_h = 0.5f * 1.05f * 0.75f;
  const auto top = mat4_apply(m, {0, 0.375f, 0, 1});
  EXPECT_NEAR(top[1], 0.375f / half_h, 1e-5);
  const auto right = mat4_apply(m, {0.5f, 0, 0, 1});
  EXPECT_NEAR(right[0], 0.5f / (half_h * 4.0f / 3.0f), 1e-5);
  // Wide domain in a square viewport is width-limited.
  const auto m2 = c.view_projection_2d(1.0f, 1.0f, 0.25f);
  EXPECT_NEAR(mat4_apply(m2, {0.5f, 0, 0, 1})[0], 1 / 1.05f, 1e-5);
  // Zoom 2 about pan (0.1, 0): the pan point is at the centre, scale doubles.
  c.zoom2d = 2;
  c.pan2d = {0.1f, 0};
  const auto m3 = c.view_projection_2d(1.0f, 1.0f, 1.0f);
  EXPECT_NEAR(mat4_apply(m3, {0.1f, 0, 0, 1})[0], 0, 1e-6);
  EXPECT_NEAR(mat4_apply(m3, {0.2f, 0, 0, 1})[0], 0.1f / (0.5f * 1.05f / 2), 1e-5);
}

TEST(OrbitCamera, InteractionsClampAndReset) {
  OrbitCamera c;
  c.orbit(0, 1000);
  EXPECT_FLOAT_EQ(c.pitch_deg, 89);
  c.orbit(0, -5000);
  EXPECT_FLOAT_EQ(c.pitch_deg, -89);
  const float d0 = OrbitCamera{}.distance;
  c.zoom(1);
  EXPECT_NEAR(c.distance, d0 / 1.1f, 1e-5);
  EXPECT_NEAR(c.zoom2d, 1.1f, 1e-5);
  c.reset();
  EXPECT_FLOAT_EQ(c.distance, d0);
  EXPECT_FLOAT_EQ(c.pitch_deg, OrbitCamera{}.pitch_deg);
}

TEST(OrbitCamera, PanMovesTheTargetInTheViewPlane) {
  OrbitCamera c;
  c.yaw_deg = 0;
  c.pitch_deg = 0;
  c.distance = 2;
  c.fov_deg = 90;
  // Viewport 100 px tall sees 2 * 2 * tan(45) = 4 world units: 25 px = 1 unit.
  c.pan(25, 0, 100);
  EXPECT_NEAR(c.target[0], -1, 1e-5);  // drag right: the scene follows the cursor
  EXPECT_NEAR(c.target[1], 0, 1e-5);
  c.pan(0, 25, 100);
  EXPECT_NEAR(c.target[1], 1, 1e-5);
  EXPECT_NEAR(c.pan2d[0], -0.25f, 1e-6);
}

}  // namespace
}  // namespace pliant::editor
