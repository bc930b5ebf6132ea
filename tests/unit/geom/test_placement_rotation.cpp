// Placement rotations about any axis: a zero rotation is bitwise no rotation, 90
// degree turns permute extents voxel-exactly, composing a turn and its inverse
// returns the original, and matrix <-> axis-angle round trips (incl. 180 degrees).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

#include "pliant/geom/keyframe_raster.h"

namespace pliant::geom {
namespace {

RasterGrid prot_grid(int n) {
  RasterGrid g;
  g.dim = 3;
  g.n = {n, n, n};
  g.cell_size_m = 1.0 / n;
  return g;
}

// A right-triangle prism: legs 3 (x) and 2 (y), extruded 1 along z; outward faces.
// Asymmetric in every axis, bounding box 3 x 2 x 1.
TriangleMesh prot_wedge() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {3, 0, 0}, {0, 2, 0}, {0, 0, 1}, {3, 0, 1}, {0, 2, 1}};
  m.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {0, 3, 5}, {0, 5, 2}, {1, 2, 5}, {1, 5, 4}};
  return m;
}

// Cells with any coverage: inclusive index bounds per axis.
std::array<std::array<int, 2>, 3> prot_bbox(const RasterGrid& g, const std::vector<float>& d) {
  std::array<std::array<int, 2>, 3> b{{{g.n[0], -1}, {g.n[1], -1}, {g.n[2], -1}}};
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i)
        if (d[i + size_t(g.n[0]) * (j + size_t(g.n[1]) * k)] > 0.0f) {
          const int c[3] = {i, j, k};
          for (int a = 0; a < 3; ++a) b[a][0] = std::min(b[a][0], c[a]), b[a][1] = std::max(b[a][1], c[a]);
        }
  return b;
}

std::array<double, 3> prot_centroid(const RasterGrid& g, const std::vector<float>& d) {
  double m = 0, s[3] = {0, 0, 0};
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        const double w = d[i + size_t(g.n[0]) * (j + size_t(g.n[1]) * k)];
        m += w, s[0] += w * (i + 0.5), s[1] += w * (j + 0.5), s[2] += w * (k + 0.5);
      }
  return {s[0] / m, s[1] / m, s[2] / m};
}

bool prot_bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(PlacementRotation, ZeroRotationAboutAnyAxisIsBitwiseNoRotation) {
  const RasterGrid g = prot_grid(16);
  Placement p0;
  p0.center_m = {0.47, 0.52, 0.5};
  const TriangleMesh wedge = prot_wedge();
  const auto box0 = raster_box(g, p0, {0.3, 0.1, 0.2}, 2);
  const auto sph0 = raster_sphere(g, p0, 0.27, 2);
  const auto mesh0 = raster_mesh(g, wedge, p0, 0.7, 2);
  for (const std::array<double, 3> axis : {std::array<double, 3>{0, 1, 0}, {1, 0, 0}, {1, 2, 3}}) {
    Placement p = p0;
    p.rotation_axis = axis;
    EXPECT_TRUE(prot_bitwise_equal(raster_box(g, p, {0.3, 0.1, 0.2}, 2), box0));
    EXPECT_TRUE(prot_bitwise_equal(raster_sphere(g, p, 0.27, 2), sph0));
    EXPECT_TRUE(prot_bitwise_equal(raster_mesh(g, wedge, p, 0.7, 2), mesh0));
  }
}

// The box's faces fall between sub-samples, so the 90 degree turn about y is
// voxel-exact: the same grid as the box with its x and z half extents swapped.
TEST(PlacementRotation, BoxTurned90AboutYIsTheBoxWithXAndZSwapped) {
  const RasterGrid g = prot_grid(16);
  Placement p;
  p.center_m = {0.5, 0.5, 0.5};
  const auto swapped = raster_box(g, p, {0.2, 0.1, 0.3}, 2);
  p.rotation_axis = {0, 1, 0};
  for (double deg : {90.0, -90.0}) {
    p.rotation_deg = deg;
    const auto turned = raster_box(g, p, {0.3, 0.1, 0.2}, 2);
    EXPECT_TRUE(prot_bitwise_equal(turned, swapped)) << deg;
  }
  // Not trivially equal: unturned it differs.
  p.rotation_deg = 0;
  EXPECT_FALSE(prot_bitwise_equal(raster_box(g, p, {0.3, 0.1, 0.2}, 2), swapped));
}

// A 3:2:1 wedge mesh turned 90 degrees about x / y / z: its voxel bounding-box
// extents (24, 16, 8 cells) permute as R maps the axes, and the turn is the sense
// of the right-hand rule (the centroid's offset is R times the unturned one).
TEST(PlacementRotation, MeshTurned90AboutEachAxisPermutesItsExtents) {
  const RasterGrid g = prot_grid(32);
  const TriangleMesh wedge = prot_wedge();
  Placement p;
  p.center_m = {0.5, 0.5, 0.5};
  const auto d0 = raster_mesh(g, wedge, p, 0.75, 2);
  const auto b0 = prot_bbox(g, d0);
  int e0[3];
  for (int a = 0; a < 3; ++a) e0[a] = b0[a][1] - b0[a][0] + 1;
  EXPECT_EQ(e0[0], 24);
  EXPECT_EQ(e0[1], 16);
  EXPECT_EQ(e0[2], 8);
  const auto c0 = prot_centroid(g, d0);
  struct Case {
    std::array<double, 3> axis;
    std::array<int, 3> from;  // extent along world axis a = unturned extent along from[a]
  };
  for (const Case& k : {Case{{1, 0, 0}, {0, 2, 1}}, Case{{0, 1, 0}, {2, 1, 0}}, Case{{0, 0, 1}, {1, 0, 2}}}) {
    p.rotation_axis = k.axis;
    p.rotation_deg = 90;
    const auto d = raster_mesh(g, wedge, p, 0.75, 2);
    const auto b = prot_bbox(g, d);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(b[a][1] - b[a][0] + 1, e0[k.from[a]]) << "axis " << a;
    const Rotation3 R = placement_rotation(p);
    const auto c = prot_centroid(g, d);
    for (int a = 0; a < 3; ++a) {
      const double want = 16 + R[a][0] * (c0[0] - 16) + R[a][1] * (c0[1] - 16) + R[a][2] * (c0[2] - 16);
      EXPECT_NEAR(c[a], want, 0.05) << "axis " << a;
    }
  }
}

// Turning a placed mesh by 70 degrees about y and back (rotate_placement twice)
// gives the original rotation to 1e-12 and the same voxels within one cell; four
// quarter turns about x return to the start; the parallel-axis path adds angles
// exactly and keeps the placement's own axis.
TEST(PlacementRotation, ComposingATurnAndItsInverseReturnsTheOriginal) {
  const RasterGrid g = prot_grid(32);
  const TriangleMesh wedge = prot_wedge();
  Placement p;
  p.center_m = {0.5, 0.5, 0.5};
  p.rotation_axis = {1, 2, 3};
  p.rotation_deg = 50;
  const Rotation3 R0 = placement_rotation(p);
  const auto d0 = raster_mesh(g, wedge, p, 0.75, 2);
  Placement q = p;
  rotate_placement(q, {0, 1, 0}, 70);
  const Rotation3 R1 = placement_rotation(q);
  EXPECT_GT(std::abs(R1[0][0] - R0[0][0]) + std::abs(R1[2][2] - R0[2][2]), 0.1);  // it did turn
  // R1 = Ry(70) R0.
  const Rotation3 want = rotation_product(rotation_about({0, 1, 0}, 70), R0);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(R1[i][j], want[i][j], 1e-12);
  rotate_placement(q, {0, 1, 0}, -70);
  const Rotation3 R2 = placement_rotation(q);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(R2[i][j], R0[i][j], 1e-12);
  const auto d2 = raster_mesh(g, wedge, q, 0.75, 2);
  const auto b0 = prot_bbox(g, d0), b2 = prot_bbox(g, d2);
  for (int a = 0; a < 3; ++a)
    for (int e = 0; e < 2; ++e) EXPECT_LE(std::abs(b2[a][e] - b0[a][e]), 1);
  const auto c0 = prot_centroid(g, d0), c2 = prot_centroid(g, d2);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(c2[a], c0[a], 0.05);
  // Four quarter turns about x.
  Placement f = p;
  for (int t = 0; t < 4; ++t) rotate_placement(f, {1, 0, 0}, 90);
  const Rotation3 R4 = placement_rotation(f);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(R4[i][j], R0[i][j], 1e-12);
  // Parallel axes: exact sums, own axis kept, wrapped into [-180, 180].
  Placement z;
  rotate_placement(z, {0, 0, 1}, 30);
  EXPECT_EQ(z.rotation_deg, 30.0);
  EXPECT_EQ(z.rotation_axis, (std::array<double, 3>{0, 0, 1}));
  z.rotation_axis = {0, 0, 2};
  rotate_placement(z, {0, 0, -1}, 10);
  EXPECT_EQ(z.rotation_deg, 20.0);
  EXPECT_EQ(z.rotation_axis, (std::array<double, 3>{0, 0, 2}));
  rotate_placement(z, {0, 0, 1}, 170);
  EXPECT_EQ(z.rotation_deg, -170.0);
  EXPECT_THROW(rotate_placement(z, {0, 0, 0}, 10), GeomError);
}

TEST(PlacementRotation, AxisAngleRoundTripIncludingHalfTurns) {
  for (const std::array<double, 3> axis :
       {std::array<double, 3>{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 2, 3}, {-2, 0.5, 1}, {1, 1, 0}}) {
    for (double deg : {0.0, 1e-7, 10.0, 90.0, 179.9999, 180.0, 270.0, -45.0}) {
      const Rotation3 R = rotation_about(axis, deg);
      const AxisAngle aa = axis_angle_of(R);
      EXPECT_GE(aa.deg, 0.0);
      EXPECT_LE(aa.deg, 180.0);
      const Rotation3 S = rotation_about(aa.axis, aa.deg);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(S[i][j], R[i][j], 1e-12) << deg;
    }
  }
  const AxisAngle id = axis_angle_of(rotation_about({0, 1, 0}, 0));
  EXPECT_EQ(id.deg, 0.0);
  EXPECT_EQ(id.axis, (std::array<double, 3>{0, 0, 1}));
}

}  // namespace
}  // namespace pliant::geom
