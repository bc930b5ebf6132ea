#include <gtest/gtest.h>

#include "render/mat4.h"

namespace pliant::editor {
namespace {

TEST(Mat4, InverseTimesMatrixIsIdentity) {
  const Mat4 vp = mat4_mul(perspective(40, 1.5f, 0.01f, 100), look_at({1.3f, 0.7f, 2.1f}, {0.1f, -0.2f, 0.3f}, {0, 1, 0}));
  const Mat4 id = mat4_mul(mat4_inverse(vp), vp);
  const Mat4 expect = mat4_identity();
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(id[i], expect[i], 1e-4) << i;
}

TEST(Mat4, InverseOfKnownMatrix) {
  // Scale (2, 4, 5) then translate (1, 2, 3): inverse scales by (1/2, 1/4, 1/5) and translates back.
  Mat4 m = mat4_identity();
  m[0] = 2; m[5] = 4; m[10] = 5;
  m[12] = 1; m[13] = 2; m[14] = 3;
  const Mat4 inv = mat4_inverse(m);
  EXPECT_NEAR(inv[0], 0.5f, 1e-6);
  EXPECT_NEAR(inv[5], 0.25f, 1e-6);
  EXPECT_NEAR(inv[10], 0.2f, 1e-6);
  EXPECT_NEAR(inv[12], -0.5f, 1e-6);
  EXPECT_NEAR(inv[13], -0.5f, 1e-6);
  EXPECT_NEAR(inv[14], -0.6f, 1e-6);
}

TEST(Mat4, MultiplyAppliesRightFirst) {
  Mat4 t = mat4_identity();
  t[12] = 1;  // translate x by 1
  Mat4 s = mat4_identity();
  s[0] = 3;  // scale x by 3
  const auto p = mat4_apply(mat4_mul(t, s), {1, 0, 0, 1});  // t(s(p)) = 3 + 1
  EXPECT_FLOAT_EQ(p[0], 4);
}

TEST(Mat4, OrthoMapsBoxToUnitCube) {
  const Mat4 o = ortho(-2, 6, -1, 3, -1, 1);
  const auto a = mat4_apply(o, {-2, -1, 0, 1});
  const auto b = mat4_apply(o, {6, 3, 0, 1});
  EXPECT_FLOAT_EQ(a[0], -1);
  EXPECT_FLOAT_EQ(a[1], -1);
  EXPECT_FLOAT_EQ(b[0], 1);
  EXPECT_FLOAT_EQ(b[1], 1);
}

}  // namespace
}  // namespace pliant::editor
