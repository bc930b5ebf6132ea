// 3D keyframes (editor/doc/smoke_keyframes_3d): painting one z slice of a painted
// volume, its bit-exact storage and compile, and the mesh gizmo's transforms
// checked on the engine's voxelisation (centroid shift = dragged cells).
#include "doc/smoke_keyframes_3d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "doc/paint_ops.h"
#include "doc/smoke_keyframes.h"
#include "pliant/geom/raster_grid.h"

namespace pliant::editor {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json scene3() {
  return json::parse(R"({"pliant": 1, "kind": "smoke", "name": "t3",
    "grid": {"resolution": [16, 12, 10], "cell_size_m": 0.0625},
    "time": {"dt_s": 0.05, "frames": 10}, "advection": "upwind", "buoyancy_m_per_s2": 0.0,
    "control": {"method": "lbfgs", "r": 1e-5,
      "initial_density": [{"type": "sphere", "center": [0.5, 0.3, 0.5], "radius": 0.2}],
      "keyframes": [{"frame": 10, "target": {"type": "sphere", "center": [0.5, 0.6, 0.5], "radius": 0.2}}]}})");
}

size_t count(const geom::PaintedGrid& g) { return painted_cell_count(g); }

TEST(SmokeKeyframes3D, SliceStrokeChangesExactlyThatSliceWithinTheBrush) {
  geom::PaintedGrid v = make_painted_volume(16, 12, 10);
  for (size_t c = 0; c < v.cells(); ++c) v.value[c] = uint8_t(c % 7 == 0 ? 40 : 0);  // some content
  const geom::PaintedGrid before = v;
  geom::PaintedGrid slice = volume_slice(v, 4);
  ASSERT_EQ(slice.dim, 2);
  ASSERT_EQ(slice.n, (std::array<int, 3>{16, 12, 1}));
  const Brush b{3.0, 1.0, false};
  paint_segment(slice, 4, 4, 10, 6, b);
  set_volume_slice(v, 4, slice);
  size_t changed = 0;
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 16; ++i) {
        const size_t c = size_t(i) + 16 * (size_t(j) + 12 * k);
        if (v.value[c] == before.value[c]) continue;
        ++changed;
        EXPECT_EQ(k, 4) << "voxel (" << i << "," << j << "," << k << ") changed off the slice";
        // Within the brush: distance of the cell centre to the segment <= radius.
        const double px = i + 0.5, py = j + 0.5, ax = 4, ay = 4, bx = 10, by = 6;
        const double t = std::clamp(((px - ax) * (bx - ax) + (py - ay) * (by - ay)) /
                                        ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)), 0.0, 1.0);
        EXPECT_LE(std::hypot(px - ax - t * (bx - ax), py - ay - t * (by - ay)), 3.0 + 1e-9);
      }
  // A capsule of radius 3 around a segment of length ~6.3: about pi 9 + 6 * 6.3 cells.
  EXPECT_GT(changed, 50u);
  EXPECT_LT(changed, 80u);
}

TEST(SmokeKeyframes3D, PaintedVolumeIsStoredBitForBitAndCompiles) {
  json s = scene3();
  std::string err;
  geom::PaintedGrid v = rasterize_slot_volume(s, {}, 0, &err);
  ASSERT_EQ(err, "");
  ASSERT_EQ(v.n, (std::array<int, 3>{16, 12, 10}));
  EXPECT_GT(count(v), 30u);  // the sphere (radius 2 cells), voxelised by the engine
  geom::PaintedGrid slice = volume_slice(v, 2);
  paint_dab(slice, 3.3, 8.7, Brush{2.5, 0.4, false});  // soft edge: values other than 0/255
  set_volume_slice(v, 2, slice);
  s = with_painted_volume_slot(s, 0, v);
  const json& t = s["control"]["keyframes"][0]["target"];
  EXPECT_EQ(t["type"], "painted");
  EXPECT_EQ(t["size"], json({16, 12, 10}));
  // Through text and back, then the exact decode and the engine's raster agree.
  const json reopened = json::parse(s.dump(2));
  geom::PaintedGrid back = rasterize_slot_volume(reopened, {}, 0, &err);
  ASSERT_EQ(err, "");
  EXPECT_EQ(back.value, v.value);
  std::array<int, 3> dims{};
  std::vector<float> d = rasterize_slot_density(reopened, {}, 0, &dims, &err);
  ASSERT_EQ(err, "");
  ASSERT_EQ(dims, (std::array<int, 3>{16, 12, 10}));
  for (size_t c = 0; c < d.size(); ++c) ASSERT_EQ(uint8_t(std::lround(d[c] * 255)), v.value[c]) << c;
  // Initial density painted the same way.
  s = with_painted_volume_slot(s, kInitialDensitySlot, v);
  EXPECT_EQ(rasterize_slot_volume(s, {}, kInitialDensitySlot, &err).value, v.value);
}

class MeshGizmo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("pliant-kf3d-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "cube.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                       "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                       "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    s = json::parse(R"({"pliant": 1, "kind": "smoke", "name": "m",
      "grid": {"resolution": [20, 20, 20], "cell_size_m": 0.05},
      "time": {"dt_s": 0.05, "frames": 10}, "advection": "upwind", "buoyancy_m_per_s2": 0.0,
      "control": {"method": "lbfgs", "r": 1e-5,
        "initial_density": [{"type": "sphere", "center": [0.5, 0.3, 0.5], "radius": 0.2}],
        "keyframes": [{"frame": 10, "target": {"type": "mesh", "file": "cube.obj", "center": [0.4, 0.5, 0.5],
                                               "size": 0.4}}]}})");
  }
  void TearDown() override { fs::remove_all(dir); }
  geom::PaintedGrid voxels(const json& scene) {
    std::string err;
    geom::PaintedGrid g = rasterize_slot_volume(scene, dir, 0, &err);
    EXPECT_EQ(err, "");
    return g;
  }
  fs::path dir;
  json s;
};

TEST_F(MeshGizmo, MoveShiftsTheVoxelisedMeshByTheDraggedCells) {
  ASSERT_TRUE(is_mesh_slot(s, 0));
  EXPECT_FALSE(is_mesh_slot(s, kInitialDensitySlot));
  const std::array<int, 3> n{20, 20, 20};
  const MeshTransform t0 = mesh_transform(s, 0);
  EXPECT_DOUBLE_EQ(t0.center[0], 0.4);
  const auto c0 = volume_centroid(voxels(s));
  EXPECT_NEAR(c0[0], 8.0, 0.05);  // 0.4 * 20
  const MeshTransform t1 = gizmo_move(t0, 3.0, -2.0, n);
  const json moved = with_mesh_transform(s, 0, t1);
  EXPECT_EQ(moved["control"]["keyframes"][0]["target"]["file"], "cube.obj");  // the rest is kept
  const auto c1 = volume_centroid(voxels(moved));
  EXPECT_NEAR(c1[0] - c0[0], 3.0, 0.05);
  EXPECT_NEAR(c1[1] - c0[1], -2.0, 0.05);
  EXPECT_NEAR(c1[2] - c0[2], 0.0, 0.05);
}

// On XZ (top view) and YZ (right view) slices a drag right / up moves the mesh
// along the slice's screen axes (doc/volume_slice.h): the voxel centroid follows.
TEST_F(MeshGizmo, MoveOnXzAndYzSlicesShiftsAlongTheSliceAxes) {
  const std::array<int, 3> n{20, 20, 20};
  const MeshTransform t0 = mesh_transform(s, 0);
  const auto c0 = volume_centroid(voxels(s));
  const struct {
    SliceAxis a;
    double want[3];
  } cases[2] = {{SliceAxis::XZ, {3.0, 0.0, 2.0}},    // right = +x, up = -z
                {SliceAxis::YZ, {0.0, -2.0, -3.0}}};  // right = -z, up = +y
  for (const auto& c : cases) {
    const MeshTransform t1 = gizmo_move(t0, 3.0, -2.0, n, c.a);
    const auto c1 = volume_centroid(voxels(with_mesh_transform(s, 0, t1)));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(c1[i] - c0[i], c.want[i], 0.05) << slice_axis_name(c.a) << " axis " << i;
    // The centre in slice cells moved by the drag, and scaling works about it.
    const auto p0 = mesh_centre_in_slice(t0, n, c.a), p1 = mesh_centre_in_slice(t1, n, c.a);
    EXPECT_NEAR(p1[0] - p0[0], 3.0, 1e-12);
    EXPECT_NEAR(p1[1] - p0[1], -2.0, 1e-12);
    EXPECT_NEAR(gizmo_scale(t0, p0[0] + 2, p0[1], p0[0] + 3, p0[1], n, c.a).scale, 1.5, 1e-12);
  }
}

TEST_F(MeshGizmo, ScaleAndRotateChangeVolumeAndFootprintAsPlaced) {
  const std::array<int, 3> n{20, 20, 20};
  const MeshTransform t0 = mesh_transform(s, 0);
  // Dragging from 2 cells to 3 cells away from the centre scales by 1.5: volume x 3.375.
  const double cx = t0.center[0] * 20, cy = t0.center[1] * 20;
  const MeshTransform ts = gizmo_scale(t0, cx + 2, cy, cx + 3, cy, n);
  EXPECT_NEAR(ts.scale, 1.5, 1e-12);
  auto sum = [](const geom::PaintedGrid& g) {
    double m = 0;
    for (uint8_t v : g.value) m += v / 255.0;
    return m;
  };
  const double v0 = sum(voxels(s)), v1 = sum(voxels(with_mesh_transform(s, 0, ts)));
  EXPECT_NEAR(v0, 8 * 8 * 8, 8 * 8 * 8 * 0.05);
  EXPECT_NEAR(v1 / v0, 3.375, 0.2);
  // A quarter turn about the centre: 90 degrees; 45 degrees widens the cube's
  // footprint along x by sqrt(2).
  const MeshTransform tr = gizmo_rotate(t0, cx + 3, cy, cx, cy + 3, n);
  EXPECT_NEAR(tr.rotation_deg, 90.0, 1e-9);
  const MeshTransform t45 = gizmo_rotate(t0, cx + 3, cy, cx + 3, cy + 3, n);
  EXPECT_NEAR(t45.rotation_deg, 45.0, 1e-9);
  auto width_x = [](const geom::PaintedGrid& g, int j, int k) {
    int w = 0;
    for (int i = 0; i < g.n[0]; ++i) w += g.value[size_t(i) + size_t(g.n[0]) * (size_t(j) + size_t(g.n[1]) * k)] > 127;
    return w;
  };
  const int w0 = width_x(voxels(s), 10, 10), w45 = width_x(voxels(with_mesh_transform(s, 0, t45)), 10, 10);
  EXPECT_NEAR(w0, 8, 1);
  EXPECT_NEAR(w45, 8 * std::sqrt(2.0), 1.5);
}

// Rotate on XZ / YZ: a counter-clockwise quarter sweep turns +90 degrees about the
// slice's normal (XZ +y, YZ +x; XY +z writes no rotation_axis key, as before), turns
// compose in world axes, the footprint is drawn at the in-slice angle, and a 3:1:1
// rod's voxels swing from x to z on XZ.
TEST_F(MeshGizmo, RotateOnXzAndYzTurnsAboutTheSliceNormal) {
  const std::array<int, 3> n{20, 20, 20};
  const MeshTransform t0 = mesh_transform(s, 0);
  auto quarter = [&](const MeshTransform& t, SliceAxis a) {
    const auto c = mesh_centre_in_slice(t, n, a);
    return gizmo_rotate(t, c[0] + 3, c[1], c[0], c[1] + 3, n, a);
  };
  const MeshTransform txz = quarter(t0, SliceAxis::XZ), tyz = quarter(t0, SliceAxis::YZ),
                      txy = quarter(t0, SliceAxis::XY);
  EXPECT_NEAR(txz.rotation_deg, 90.0, 1e-9);
  EXPECT_EQ(txz.rotation_axis, (std::array<double, 3>{0, 1, 0}));
  EXPECT_NEAR(tyz.rotation_deg, 90.0, 1e-9);
  EXPECT_EQ(tyz.rotation_axis, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(txy.rotation_axis, (std::array<double, 3>{0, 0, 1}));
  const json target_xy = with_mesh_transform(s, 0, txy)["control"]["keyframes"][0]["target"];
  EXPECT_FALSE(target_xy.contains("rotation_axis")) << "z-only scenes keep a plain rotation_deg";
  const json target_xz = with_mesh_transform(s, 0, txz)["control"]["keyframes"][0]["target"];
  EXPECT_EQ(target_xz["rotation_axis"], json::parse("[0.0, 1.0, 0.0]"));
  EXPECT_EQ(mesh_transform(with_mesh_transform(s, 0, txz), 0).rotation_axis, txz.rotation_axis);
  // XY quarter turn after the XZ one: R = Rz(90) Ry(90), as an axis-angle.
  const MeshTransform both = quarter(txz, SliceAxis::XY);
  geom::Placement pb;
  pb.rotation_axis = both.rotation_axis;
  pb.rotation_deg = both.rotation_deg;
  const geom::Rotation3 R = geom::placement_rotation(pb),
                        W = geom::rotation_product(geom::rotation_about({0, 0, 1}, 90), geom::rotation_about({0, 1, 0}, 90));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(R[i][j], W[i][j], 1e-9);
  // Footprint angles.
  MeshTransform f = t0;
  f.rotation_deg = 45;
  EXPECT_EQ(gizmo_footprint_deg(f, SliceAxis::XY), 45.0);
  EXPECT_NEAR(gizmo_footprint_deg(txz, SliceAxis::XZ), 90.0, 1e-9);
  EXPECT_NEAR(gizmo_footprint_deg(tyz, SliceAxis::YZ), 90.0, 1e-9);
  f.rotation_axis = {0, 1, 0};
  f.rotation_deg = 30;
  EXPECT_NEAR(gizmo_footprint_deg(f, SliceAxis::XZ), 30.0, 1e-9);
  EXPECT_NEAR(gizmo_footprint_deg(f, SliceAxis::XY), 0.0, 1e-9);
  // A rod long along x swings onto z (second moments of the voxels).
  std::ofstream(dir / "rod.obj") << "v 0 0 0\nv 3 0 0\nv 3 1 0\nv 0 1 0\nv 0 0 1\nv 3 0 1\nv 3 1 1\nv 0 1 1\n"
                                    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                    "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  json rod = s;
  rod["control"]["keyframes"][0]["target"]["file"] = "rod.obj";
  rod["control"]["keyframes"][0]["target"]["center"] = {0.5, 0.5, 0.5};
  rod["control"]["keyframes"][0]["target"]["size"] = 0.6;
  auto spread = [](const geom::PaintedGrid& g) {
    const auto c = volume_centroid(g);
    std::array<double, 3> m{0, 0, 0};
    for (int k = 0; k < g.n[2]; ++k)
      for (int j = 0; j < g.n[1]; ++j)
        for (int i = 0; i < g.n[0]; ++i) {
          const double w = g.value[size_t(i) + size_t(g.n[0]) * (size_t(j) + size_t(g.n[1]) * k)];
          m[0] += w * (i + 0.5 - c[0]) * (i + 0.5 - c[0]), m[2] += w * (k + 0.5 - c[2]) * (k + 0.5 - c[2]);
        }
    return m;
  };
  const auto m0 = spread(voxels(rod));
  const auto m1 = spread(voxels(with_mesh_transform(rod, 0, quarter(mesh_transform(rod, 0), SliceAxis::XZ))));
  EXPECT_GT(m0[0], 5 * m0[2]);
  EXPECT_GT(m1[2], 5 * m1[0]);
  EXPECT_NEAR(m1[2], m0[0], 0.02 * m0[0]);
}

}  // namespace
}  // namespace pliant::editor
