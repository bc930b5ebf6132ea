// Slice orientations of 3D keyframes (editor/doc/volume_slice): the (axis, k, u, v)
// <-> voxel (x, y, z) mapping round trips and is a bijection in all three
// orientations, its handedness is the documented one (front / top / right views,
// +y up on screen), and a slice write touches only that slice.
#include "doc/volume_slice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "doc/paint_ops.h"
#include "doc/smoke_keyframes_3d.h"

namespace pliant::editor {
namespace {

const SliceAxis kVsAxes[3] = {SliceAxis::XY, SliceAxis::XZ, SliceAxis::YZ};

TEST(VolumeSlice, IndexMappingRoundTripsAndCoversEveryVoxelOnceInAllOrientations) {
  const std::array<int, 3> n{5, 4, 3};  // all different: a swapped axis shows
  for (SliceAxis a : kVsAxes) {
    const auto wh = slice_size(n, a);
    const int kn = slice_count(n, a);
    EXPECT_EQ(size_t(kn) * wh[0] * wh[1], size_t(n[0]) * n[1] * n[2]) << slice_axis_name(a);
    std::set<std::array<int, 3>> seen;
    for (int k = 0; k < kn; ++k)
      for (int v = 0; v < wh[1]; ++v)
        for (int u = 0; u < wh[0]; ++u) {
          const auto p = slice_to_voxel(n, a, k, u, v);
          for (int c = 0; c < 3; ++c) {
            ASSERT_GE(p[c], 0);
            ASSERT_LT(p[c], n[c]);
          }
          EXPECT_EQ(p[slice_normal_index(a)], k) << "the slice index is the normal coordinate";
          EXPECT_EQ(voxel_to_slice(n, a, p[0], p[1], p[2]), (std::array<int, 3>{k, u, v}));
          seen.insert(p);
        }
    EXPECT_EQ(seen.size(), size_t(n[0]) * n[1] * n[2]) << slice_axis_name(a) << ": every voxel once";
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) {
          const auto s = voxel_to_slice(n, a, x, y, z);
          EXPECT_EQ(slice_to_voxel(n, a, s[0], s[1], s[2]), (std::array<int, 3>{x, y, z}));
        }
  }
}

// The slice's screen axes (u right, v up, viewer looking along -normal) as world
// vectors: right x up must equal the direction towards the viewer (no mirror), and
// +y is up wherever y lies in the slice.
TEST(VolumeSlice, OrientationsAreUnmirroredViewsWithTheVerticalUp) {
  const std::array<int, 3> n{6, 7, 8};
  const int towards_viewer[3][3] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};  // XY from +z, XZ from +y, YZ from +x
  for (int ai = 0; ai < 3; ++ai) {
    const SliceAxis a = kVsAxes[ai];
    const auto o = slice_to_voxel(n, a, 2, 1, 1), r = slice_to_voxel(n, a, 2, 2, 1), up = slice_to_voxel(n, a, 2, 1, 2);
    const int du[3] = {r[0] - o[0], r[1] - o[1], r[2] - o[2]}, dv[3] = {up[0] - o[0], up[1] - o[1], up[2] - o[2]};
    const int cross[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]};
    for (int c = 0; c < 3; ++c) EXPECT_EQ(cross[c], towards_viewer[ai][c]) << slice_axis_name(a) << " component " << c;
    if (a != SliceAxis::XZ) {
      EXPECT_EQ(dv[1], 1) << slice_axis_name(a) << ": +y up";
    }
  }
}

TEST(VolumeSlice, SetSliceWritesOnlyThatSliceAndReadsBackInEveryOrientation) {
  geom::PaintedGrid v = make_painted_volume(5, 4, 3);
  for (size_t c = 0; c < v.cells(); ++c) v.value[c] = uint8_t(c * 7 % 251);
  for (SliceAxis a : kVsAxes)
    for (int k = 0; k < slice_count(v.n, a); ++k) {
      const geom::PaintedGrid before = v;
      geom::PaintedGrid s = volume_slice(v, a, k);
      ASSERT_EQ(s.dim, 2);
      const auto wh = slice_size(v.n, a);
      ASSERT_EQ(s.n, (std::array<int, 3>{wh[0], wh[1], 1}));
      for (auto& b : s.value) b = uint8_t(255 - b);
      set_volume_slice(v, a, k, s);
      EXPECT_EQ(volume_slice(v, a, k).value, s.value);
      for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 4; ++y)
          for (int x = 0; x < 5; ++x) {
            const size_t c = size_t(x) + 5 * (size_t(y) + 4 * z);
            const int kk = a == SliceAxis::XY ? z : a == SliceAxis::XZ ? y : x;
            if (kk != k) EXPECT_EQ(v.value[c], before.value[c]);
            else EXPECT_EQ(v.value[c], uint8_t(255 - before.value[c]));
          }
    }
  // The XY orientation is the old z-slice API.
  EXPECT_EQ(volume_slice(v, SliceAxis::XY, 1).value, volume_slice(v, 1).value);
}

// The volume view's outline: on the plane through the slice's cell centres along
// the normal, spanning the full extent of the two other axes.
TEST(VolumeSlice, OutlineLiesOnTheSlicePlaneAndSpansTheOtherAxes) {
  const std::array<int, 3> n{8, 4, 16};
  const std::array<float, 3> e{0.5f, 0.25f, 1.0f};  // longest side 1, as the renderer frames it
  for (SliceAxis a : kVsAxes) {
    const int na = slice_normal_index(a), k = 1;
    const auto c = slice_outline(n, a, k, e);
    float lo[3] = {9, 9, 9}, hi[3] = {-9, -9, -9};
    for (const auto& p : c) {
      EXPECT_FLOAT_EQ(p[na], ((k + 0.5f) / n[na] - 0.5f) * e[na]) << slice_axis_name(a);
      for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
    }
    for (int i = 0; i < 3; ++i)
      if (i != na) {
        EXPECT_FLOAT_EQ(lo[i], -0.5f * e[i]) << slice_axis_name(a) << " axis " << i;
        EXPECT_FLOAT_EQ(hi[i], 0.5f * e[i]) << slice_axis_name(a) << " axis " << i;
      }
    // A closed quad: consecutive corners differ in exactly one coordinate.
    for (int i = 0; i < 4; ++i) {
      int d = 0;
      for (int j = 0; j < 3; ++j) d += c[i][j] != c[(i + 1) % 4][j];
      EXPECT_EQ(d, 1);
    }
  }
}

}  // namespace
}  // namespace pliant::editor
