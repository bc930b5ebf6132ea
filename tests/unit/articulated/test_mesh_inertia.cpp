// Mesh mass properties (mesh_inertia.cpp): the solid's against analytic values, and
// MuJoCo 2.2.2's rule against its closed forms (libmujoco itself: test_mujoco_reference).
#include <gtest/gtest.h>

#include <cmath>

#include "pliant/articulated/model.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

// A prism over the polygon (counter-clockwise; `caps`: its triangles, counter-
// clockwise), z in [0, h], outward-facing.
MeshShape prism(const std::vector<std::array<double, 2>>& poly, const std::vector<std::array<int, 3>>& caps,
                double h) {
  MeshShape m;
  const int n = static_cast<int>(poly.size());
  for (double z : {0.0, h})
    for (const auto& p : poly) m.vertices.emplace_back(p[0], p[1], z);
  for (const auto& t : caps) {
    m.triangles.push_back({t[0], t[2], t[1]});
    m.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, j + n});
    m.triangles.push_back({i, j + n, i + n});
  }
  return m;
}

// Three unit squares in an L, 1 high: volume 3, centre (5/6, 5/6, 1/2).
MeshShape l_prism() {
  return prism({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, {{3, 4, 5}, {3, 5, 0}, {3, 0, 1}, {3, 1, 2}}, 1);
}

Mat3 inertia_about(const Mat3& second, double volume, const Vec3& c) {
  const Mat3 s = second - volume * c * c.transpose();
  return s.trace() * Mat3::Identity() - s;
}

TEST(MeshInertia, LPrismHasItsAnalyticVolumeCentreAndInertia) {
  double v;
  Vec3 c;
  Mat3 s;
  mesh_volume_moments(l_prism(), &v, &c, &s);
  EXPECT_NEAR(v, 3, 1e-12);
  EXPECT_NEAR((c - Vec3(5.0 / 6, 5.0 / 6, 0.5)).norm(), 0, 1e-12);
  // Three unit cubes: each (1 + 1) / 12 about its own centre, plus parallel axes.
  const Mat3 i = inertia_about(s, v, c);
  EXPECT_NEAR(i(2, 2), 3 * 2.0 / 12 + (2.0 / 9 + 5.0 / 9 + 5.0 / 9), 1e-12);  // 11/6
  // About x: each cube (1 + 1)/12 plus its y offset squared (cube centres -1/3, -1/3,
  // 2/3 from the centre in y; -1/3, 2/3, -1/3 in x): 7/6; product -sum dx dy = 1/3.
  EXPECT_NEAR(i(0, 0), 7.0 / 6, 1e-12);
  EXPECT_NEAR(i(0, 1), 1.0 / 3, 1e-12);
  // Inside out: the same magnitudes, negative volume.
  MeshShape flipped = l_prism();
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  double vf;
  mesh_volume_moments(flipped, &vf, nullptr, nullptr);
  EXPECT_NEAR(vf, -3, 1e-12);
}

TEST(MeshInertia, MuJoCo222RuleTakesTheMassFromTheEquivalentInertiaBox) {
  // A box: the equivalent box is the box itself, so both rules agree.
  const MeshShape box = prism({{0, 0}, {1, 0}, {1, 2}, {0, 2}}, {{0, 1, 2}, {0, 2, 3}}, 3);
  double mv, v, v_exact;
  Vec3 c, c_exact;
  Mat3 s, s_exact;
  mesh_mujoco222_moments(box, &mv, &v, &c, &s);
  mesh_volume_moments(box, &v_exact, &c_exact, &s_exact);
  EXPECT_NEAR(mv, 6, 1e-12);
  EXPECT_NEAR(v, 6, 1e-12);
  EXPECT_NEAR((c - Vec3(0.5, 1, 1.5)).norm(), 0, 1e-12);
  EXPECT_NEAR((s - (s_exact - v_exact * c_exact * c_exact.transpose())).norm(), 0, 1e-11);  // about c
  // The L (star-shaped about its surface centroid, so |tetrahedra| sum to the
  // volume): principal moments per unit density 5/6, 3/2, 11/6 give half-sizes
  // a^2 = 3 (J2 + J3 - J1) / (2 V) = 1/4, 7/12, 5/4 and 8 a b c = sqrt(35/3).
  mesh_mujoco222_moments(l_prism(), &mv, &v, &c, &s);
  EXPECT_NEAR(v, 3, 1e-12);
  EXPECT_NEAR(mv, std::sqrt(35.0 / 3), 1e-12);
  EXPECT_NEAR((c - Vec3(5.0 / 6, 5.0 / 6, 0.5)).norm(), 0, 1e-12);
  // Not star-shaped about its surface centroid (a U: a 3 x 2 block with a 1 x 1 notch
  // in the middle of its top edge): the unsigned tetrahedra from outside the kernel
  // count more than the solid's 5.
  const MeshShape u = prism({{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}},
                            {{0, 1, 4}, {0, 4, 5}, {1, 2, 4}, {2, 3, 4}, {0, 5, 7}, {5, 6, 7}}, 1);
  mesh_volume_moments(u, &v_exact, nullptr, nullptr);
  mesh_mujoco222_moments(u, &mv, &v, &c, nullptr);
  EXPECT_NEAR(v_exact, 5, 1e-12);
  EXPECT_GT(v, 5 + 1e-3);
  EXPECT_NEAR(c.x(), 1.5, 1e-12);  // symmetric about x = 1.5
}

}  // namespace
}  // namespace pliant::articulated
