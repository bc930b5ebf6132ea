// 3D keyframes in the editor (issue 4, the slice-and-volume view): a brush stroke
// on one z slice is one undo step and changes only that slice within the brush
// (also on XZ / YZ slices, and a rectangle at strength 0.5 writes 128; the gizmo
// moves a mesh in x and z on an XZ slice and turns it about y there);
// the mesh gizmo moves the voxelised keyframe by the dragged cells (one undo
// step; golden of the slice + volume view); painted 3D keyframes survive
// save/reopen bit for bit; a tiny 3D solve from a painted keyframe runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "doc/paint_ops.h"
#include "doc/smoke_keyframes.h"
#include "doc/smoke_keyframes_3d.h"
#include "editor_harness.h"
#include "pliant/core/take.h"
#include "render/image_compare.h"
#include "render/screenshot.h"

namespace pliant::editor::test {

using nlohmann::json;

namespace {

geom::PaintedGrid slot_volume(App& app, int slot) {
  std::string err;
  geom::PaintedGrid g = rasterize_slot_volume(app.doc.scene(), app.doc.path().parent_path(), slot, &err);
  EXPECT_EQ(err, "");
  return g;
}

void write_cube(const fs::path& file) {
  std::ofstream(file) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                         "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                         "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
}

// The window screenshot cropped to the slice view and the volume view beside it,
// compared with tests/editor/golden/<name> (PLIANT_UPDATE_GOLDEN=1 rewrites it).
void match_slices_golden(App& app, const fs::path& shot_file, const std::string& name) {
  std::string err;
  Image shot = read_png(shot_file.string(), &err);
  ASSERT_FALSE(shot.empty()) << err;
  const UiRect* a = app.marks.find("slice_view");
  const UiRect* b = app.marks.find("slice_volume");
  ASSERT_TRUE(a && b);
  const int x0 = std::max(0, int(std::floor(std::min(a->x0, b->x0)))), y0 = std::max(0, int(std::floor(std::min(a->y0, b->y0))));
  const int x1 = std::min(shot.width, int(std::ceil(std::max(a->x1, b->x1)))),
            y1 = std::min(shot.height, int(std::ceil(std::max(a->y1, b->y1))));
  ASSERT_GT(x1 - x0, 16);
  ASSERT_GT(y1 - y0, 16);
  Image crop;
  crop.width = x1 - x0;
  crop.height = y1 - y0;
  crop.rgba.resize(size_t(crop.width) * crop.height * 4);
  for (int y = 0; y < crop.height; ++y)
    std::copy_n(shot.pixel(x0, y0 + y), size_t(crop.width) * 4, crop.pixel(0, y));
  match_golden_image(crop, name);
}

}  // namespace

TEST(EditorKeyframes3D, SliceStrokeIsOneUndoStepAndChangesOnlyThatSliceWithinTheBrush) {
  EditorHarness h("kf3d_stroke");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item slice_slot\nwait 2\nclick_item slot_10\nwait 2\n"),
            "");
  ASSERT_EQ(h.app->canvas.slot, 0);
  h.app->canvas.slice = 5;  // the z slider (UI state, not document data)
  h.app->canvas.radius_cells = 2.5f;
  h.app->canvas.hardness = 1.0f;
  const json before = h.app->doc.scene();
  const geom::PaintedGrid v0 = slot_volume(*h.app, 0);  // the voxelised sphere
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("wait 1\ndrag_item_at slice_view 0.2 0.2 0.4 0.3 6\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1) << "one stroke, one undo step";
  const json after = h.app->doc.scene();
  const json& t = after["control"]["keyframes"][0]["target"];
  EXPECT_EQ(t["type"], "painted");
  EXPECT_EQ(t["size"], json({16, 16, 16}));
  const geom::PaintedGrid v1 = slot_volume(*h.app, 0);
  EXPECT_EQ(h.app->canvas.vol.value, v1.value) << "the view shows the stored bytes";
  // The drag in cells (+y up) on the 16x16 slice: (3.2, 12.8) -> (6.4, 11.2).
  const double ax = 0.2 * 16, ay = 16 - 0.2 * 16, bx = 0.4 * 16, by = 16 - 0.3 * 16, r = 2.5 + 0.6;
  size_t changed = 0;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i) {
        const size_t c = size_t(i) + 16 * (size_t(j) + 16 * k);
        if (v1.value[c] == v0.value[c]) continue;
        ++changed;
        EXPECT_EQ(k, 5) << "voxel (" << i << "," << j << "," << k << ") changed off the slice";
        const double px = i + 0.5, py = j + 0.5;
        const double u = std::clamp(((px - ax) * (bx - ax) + (py - ay) * (by - ay)) /
                                        ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)), 0.0, 1.0);
        EXPECT_LE(std::hypot(px - ax - u * (bx - ax), py - ay - u * (by - ay)), r)
            << "voxel (" << i << "," << j << ") outside the brush";
      }
  EXPECT_GT(changed, 15u);
  // Undo restores the scene exactly (the sphere target), redo the painted bytes.
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  EXPECT_EQ(h.app->canvas.vol.value, v0.value);
  ASSERT_EQ(h.run("key CTRL+SHIFT+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), after);
  EXPECT_EQ(h.app->canvas.vol.value, v1.value);
  // Fill, rectangle, ellipse and clear on the slice: one step each.
  const size_t n0 = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item tool_Rectangle\nwait 1\ndrag_item_at slice_view 0.6 0.6 0.9 0.9 4\nwait 1\n"
                  "click_item tool_Ellipse\nwait 1\ndrag_item_at slice_view 0.1 0.6 0.3 0.9 4\nwait 1\n"
                  "click_item tool_Fill\nwait 1\nclick_item_at slice_view 0.05 0.05\nwait 1\n"
                  "click_item slice_clear\nwait 2\n"),
            "");
  EXPECT_EQ(h.app->doc.history().size(), n0 + 4);
  const geom::PaintedGrid v2 = slot_volume(*h.app, 0);
  EXPECT_EQ(painted_cell_count(volume_slice(v2, 5)), 0u);
  for (int k = 0; k < 16; ++k) {
    if (k != 5) {
      EXPECT_EQ(volume_slice(v2, k).value, volume_slice(v1, k).value) << "slice " << k;
    }
  }
  EXPECT_EQ(h.app->scene_error(), "");
}

// XZ (top view) and YZ (side view) slices: a stroke changes only voxels of the
// chosen slice within the brush (in the slice's own cells), is one undo step with
// exact undo; the orientation is UI state (no history step, scene unchanged); the
// screen's top-left lands where the documented views put it; a rectangle at
// strength 0.5 writes 128 in a box and nothing else.
TEST(EditorKeyframes3D, XzAndYzSliceStrokesChangeOnlyThatSliceAndRectangleStrengthIsExact) {
  EditorHarness h("kf3d_axes");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item slice_slot\nwait 2\nclick_item slot_10\nwait 2\n"),
            "");
  h.app->canvas.radius_cells = 2.5f;
  h.app->canvas.hardness = 1.0f;
  const std::array<int, 3> n{16, 16, 16};
  const struct {
    const char* mark;
    SliceAxis axis;
    int k;
    double want_x, want_y, want_z;  // centroid of the changed voxels (cells), -1 = not checked
  } cases[2] = {
      // Top view: screen top = -z (back), so a stroke near the top-left paints low x, low z.
      {"slice_axis_XZ", SliceAxis::XZ, 9, 4.8, -1, 16 - 12.0},
      // Right view: screen left = +z, top = +y.
      {"slice_axis_YZ", SliceAxis::YZ, 6, -1, 12.0, 16 - 4.8},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.mark);
    const json before = h.app->doc.scene();
    const size_t steps = h.app->doc.history().size();
    ASSERT_EQ(h.run(std::string("click_item ") + c.mark + "\nwait 2\n"), "");
    EXPECT_EQ(h.app->canvas.slice_axis, c.axis);
    EXPECT_EQ(h.app->doc.history().size(), steps) << "the orientation is not an edit";
    EXPECT_EQ(h.app->doc.scene(), before);
    current_slice(h.app->canvas) = c.k;  // the orientation's own slider (UI state)
    const geom::PaintedGrid v0 = h.app->canvas.vol;
    ASSERT_EQ(h.run("wait 1\ndrag_item_at slice_view 0.2 0.2 0.4 0.3 6\nwait 2\n"), "");
    EXPECT_EQ(h.app->doc.history().size(), steps + 1) << "one stroke, one undo step";
    const json after = h.app->doc.scene();
    const geom::PaintedGrid v1 = slot_volume(*h.app, 0);
    EXPECT_EQ(h.app->canvas.vol.value, v1.value);
    const double ax = 0.2 * 16, ay = 16 - 0.2 * 16, bx = 0.4 * 16, by = 16 - 0.3 * 16, r = 2.5 + 0.6;
    size_t changed = 0;
    double m[3] = {0, 0, 0};
    for (int z = 0; z < 16; ++z)
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
          const size_t cell = size_t(x) + 16 * (size_t(y) + 16 * z);
          if (v1.value[cell] == v0.value[cell]) continue;
          ++changed;
          m[0] += x + 0.5, m[1] += y + 0.5, m[2] += z + 0.5;
          const auto kuv = voxel_to_slice(n, c.axis, x, y, z);
          EXPECT_EQ(kuv[0], c.k) << "voxel (" << x << "," << y << "," << z << ") changed off the slice";
          const double px = kuv[1] + 0.5, py = kuv[2] + 0.5;
          const double u = std::clamp(((px - ax) * (bx - ax) + (py - ay) * (by - ay)) /
                                          ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)), 0.0, 1.0);
          EXPECT_LE(std::hypot(px - ax - u * (bx - ax), py - ay - u * (by - ay)), r)
              << "voxel (" << x << "," << y << "," << z << ") outside the brush";
        }
    ASSERT_GT(changed, 15u);
    const double want[3] = {c.want_x, c.want_y, c.want_z};
    for (int a = 0; a < 3; ++a)
      if (want[a] >= 0) {
        EXPECT_NEAR(m[a] / changed, want[a], 1.5) << "axis " << a;
      }
    ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
    EXPECT_EQ(h.app->doc.scene(), before);
    EXPECT_EQ(h.app->canvas.vol.value, v0.value) << "undo restores the bytes";
    ASSERT_EQ(h.run("key CTRL+SHIFT+Z\nwait 2\n"), "");
    EXPECT_EQ(h.app->doc.scene(), after);
    EXPECT_EQ(h.app->canvas.vol.value, v1.value);
  }
  // Rectangle at strength 0.5 on the YZ slice x = 6: 128 in a box, nothing else.
  h.app->canvas.strength = 0.5f;
  const json before = h.app->doc.scene();
  const geom::PaintedGrid v0 = h.app->canvas.vol;
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item tool_Rectangle\nwait 1\ndrag_item_at slice_view 0.6 0.6 0.9 0.9 4\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  const geom::PaintedGrid v1 = slot_volume(*h.app, 0);
  int lo[2] = {99, 99}, hi[2] = {-1, -1};
  size_t changed = 0;
  for (size_t cell = 0; cell < v1.cells(); ++cell) {
    if (v1.value[cell] == v0.value[cell]) continue;
    const int x = int(cell % 16), y = int(cell / 16 % 16), z = int(cell / 256);
    const auto kuv = voxel_to_slice(n, SliceAxis::YZ, x, y, z);
    EXPECT_EQ(kuv[0], 6);
    EXPECT_EQ(v1.value[cell], 128) << "strength 0.5 writes round(127.5)";
    ++changed;
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], kuv[1 + a]), hi[a] = std::max(hi[a], kuv[1 + a]);
  }
  // The drag spans u 9.6..14.4, v 1.6..6.4 cells: centres 10..13 x 2..5 (a pixel either way).
  EXPECT_NEAR(lo[0], 10, 1);
  EXPECT_NEAR(hi[0], 13, 1);
  EXPECT_NEAR(lo[1], 2, 1);
  EXPECT_NEAR(hi[1], 5, 1);
  const geom::PaintedGrid sl = volume_slice(v1, SliceAxis::YZ, 6);
  for (int v = lo[1]; v <= hi[1]; ++v)
    for (int u = lo[0]; u <= hi[0]; ++u) EXPECT_EQ(sl.value[size_t(v) * 16 + u], 128) << u << "," << v;
  EXPECT_GT(changed, 0u);
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  EXPECT_EQ(h.app->canvas.vol.value, v0.value);
  EXPECT_EQ(h.app->scene_error(), "");
}

TEST(EditorKeyframes3D, GizmoDragMovesTheVoxelisedMeshByTheDraggedCellsInOneUndoStep) {
  EditorHarness h("kf3d_gizmo");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  write_cube(h.dir / "cube.obj");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\ndrop cube.obj\nwait 2\nexpect \"Import mesh cube.obj\"\n"
                  "click_item view_keyframes\nwait 3\n"),
            "");
  ASSERT_EQ(h.app->canvas.slot, 0);
  ASSERT_TRUE(is_mesh_slot(h.app->doc.scene(), 0));
  EXPECT_EQ(h.app->canvas.tool, CanvasTool::Gizmo) << "a mesh keyframe opens with its gizmo";
  const geom::PaintedGrid v0 = h.app->canvas.vol;
  const auto c0 = volume_centroid(v0);
  EXPECT_NEAR(c0[0], 8.0, 0.05);
  const json before = h.app->doc.scene();
  const size_t steps = h.app->doc.history().size();
  // Grab the centre and drag 1/8 of the slice to the right and 1/8 down: +2, -2 cells.
  ASSERT_EQ(h.run("drag_item_at slice_view 0.5 0.5 0.625 0.625 8\nwait 3\nexpect \"Move mesh\"\n"), "");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1) << "one drag, one undo step";
  const MeshTransform t = mesh_transform(h.app->doc.scene(), 0);
  EXPECT_NEAR(t.center[0], 0.625, 0.01);
  EXPECT_NEAR(t.center[1], 0.375, 0.01);
  EXPECT_DOUBLE_EQ(t.center[2], 0.5);
  // The slice view now shows the engine's voxelisation of the moved mesh.
  const geom::PaintedGrid& v1 = h.app->canvas.vol;
  EXPECT_EQ(v1.value, slot_volume(*h.app, 0).value);
  const auto c1 = volume_centroid(v1);
  EXPECT_NEAR(c1[0] - c0[0], 2.0, 0.2);
  EXPECT_NEAR(c1[1] - c0[1], -2.0, 0.2);
  EXPECT_NEAR(c1[2] - c0[2], 0.0, 0.05);
  ASSERT_EQ(h.run("move 2 2\nwait 3\nscreenshot $TMP/gizmo.png\nwait 2\n"), "");
  match_slices_golden(*h.app, h.dir / "gizmo.png", "keyframes_3d_gizmo.png");
  // Scale with the square handle (corner at +half, -half of the 8-cell footprint):
  // dragged from 4 sqrt(2) to 6 sqrt(2) cells off the centre = x1.5.
  const double cx = 0.625, cy = 1 - 0.375, hx = 4.0 / 16;
  ASSERT_EQ(h.run("drag_item_at slice_view " + std::to_string(cx + hx) + " " + std::to_string(cy + hx) + " " +
                  std::to_string(cx + 1.5 * hx) + " " + std::to_string(cy + 1.5 * hx) + " 6\nwait 3\n"
                  "expect \"Scale mesh\"\n"),
            "");
  EXPECT_NEAR(mesh_transform(h.app->doc.scene(), 0).scale, 1.5, 0.03);
  EXPECT_EQ(h.app->doc.history().size(), steps + 2);
  // Undo twice: back to the dropped mesh, exactly.
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\nkey CTRL+Z\nwait 3\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  EXPECT_EQ(h.app->canvas.vol.value, v0.value);
  EXPECT_EQ(h.app->scene_error(), "");
}

// The gizmo on a top-view (XZ) slice: dragging the centre right and down moves
// the mesh +x and +z (the back is at the top), one undo step; no rotate handle.
TEST(EditorKeyframes3D, GizmoMoveOnAnXzSliceMovesTheMeshInXAndZ) {
  EditorHarness h("kf3d_gizmo_xz");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  write_cube(h.dir / "cube.obj");
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\ndrop cube.obj\nwait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item slice_axis_XZ\nwait 2\n"),
            "");
  ASSERT_TRUE(is_mesh_slot(h.app->doc.scene(), 0));
  ASSERT_EQ(h.app->canvas.tool, CanvasTool::Gizmo);
  const json before = h.app->doc.scene();
  const auto c0 = volume_centroid(h.app->canvas.vol);
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("drag_item_at slice_view 0.5 0.5 0.625 0.625 8\nwait 3\nexpect \"Move mesh\"\n"), "");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  const MeshTransform t = mesh_transform(h.app->doc.scene(), 0);
  EXPECT_NEAR(t.center[0], 0.625, 0.01);
  EXPECT_DOUBLE_EQ(t.center[1], 0.5);
  EXPECT_NEAR(t.center[2], 0.625, 0.01);
  EXPECT_DOUBLE_EQ(t.rotation_deg, 0.0);
  const auto c1 = volume_centroid(h.app->canvas.vol);
  EXPECT_NEAR(c1[0] - c0[0], 2.0, 0.2);
  EXPECT_NEAR(c1[1] - c0[1], 0.0, 0.05);
  EXPECT_NEAR(c1[2] - c0[2], 2.0, 0.2);
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
}

// The rotate handle on a top-view (XZ) slice: a counter-clockwise quarter sweep of
// the handle turns a rod (3:1:1, long along x) +90 degrees about y (the view's
// normal), so its voxels' spread moves from x to z; one undo step, undo exact.
TEST(EditorKeyframes3D, GizmoRotateOnAnXzSliceTurnsTheMeshAboutY) {
  EditorHarness h("kf3d_gizmo_rot_xz");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  std::ofstream(h.dir / "rod.obj") << "v 0 0 0\nv 3 0 0\nv 3 1 0\nv 0 1 0\nv 0 0 1\nv 3 0 1\nv 3 1 1\nv 0 1 1\n"
                                      "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                      "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\ndrop rod.obj\nwait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item slice_axis_XZ\nwait 2\n"),
            "");
  ASSERT_TRUE(is_mesh_slot(h.app->doc.scene(), 0));
  ASSERT_EQ(h.app->canvas.tool, CanvasTool::Gizmo);
  const json before = h.app->doc.scene();
  const geom::PaintedGrid v0 = h.app->canvas.vol;
  ASSERT_EQ(v0.n, (std::array<int, 3>{16, 16, 16}));
  auto spread = [](const geom::PaintedGrid& g) {  // second moments along x and z (cells^2 x mass)
    const auto c = volume_centroid(g);
    double mx = 0, mz = 0;
    for (int k = 0; k < g.n[2]; ++k)
      for (int j = 0; j < g.n[1]; ++j)
        for (int i = 0; i < g.n[0]; ++i) {
          const double w = g.value[size_t(i) + size_t(g.n[0]) * (size_t(j) + size_t(g.n[1]) * k)];
          mx += w * (i + 0.5 - c[0]) * (i + 0.5 - c[0]), mz += w * (k + 0.5 - c[2]) * (k + 0.5 - c[2]);
        }
    return std::array<double, 2>{mx, mz};
  };
  const auto s0 = spread(v0);
  EXPECT_GT(s0[0], 5 * s0[1]) << "long along x before";
  // The handle sits above the centre at half + max(1.5, 0.35 half) cells; the
  // footprint's half is 0.3 x 16 cells (default size 0.6) times the scale.
  const MeshTransform t0 = mesh_transform(before, 0);
  const json& target = before["control"]["keyframes"][0]["target"];
  const double half = 0.5 * target.value("size", 0.6) * 16 * t0.scale, r = half + std::max(1.5, 0.35 * half);
  const auto c = mesh_centre_in_slice(t0, v0.n, SliceAxis::XZ);
  auto fx = [](double u) { return std::to_string(u / 16); };
  auto fy = [](double v) { return std::to_string(1 - v / 16); };
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("drag_item_at slice_view " + fx(c[0]) + " " + fy(c[1] + r) + " " + fx(c[0] - r) + " " + fy(c[1]) +
                  " 8\nwait 3\nexpect \"Rotate mesh\"\n"),
            "");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1) << "one drag, one undo step";
  const MeshTransform t = mesh_transform(h.app->doc.scene(), 0);
  EXPECT_EQ(t.rotation_axis, (std::array<double, 3>{0, 1, 0}));
  EXPECT_NEAR(t.rotation_deg, 90.0, 2.0);
  EXPECT_EQ(t.center, t0.center);
  const geom::PaintedGrid& v1 = h.app->canvas.vol;
  EXPECT_EQ(v1.value, slot_volume(*h.app, 0).value);
  const auto s1 = spread(v1);
  EXPECT_GT(s1[1], 5 * s1[0]) << "long along z after";
  ASSERT_EQ(h.run("key CTRL+Z\nwait 3\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  EXPECT_EQ(h.app->canvas.vol.value, v0.value);
}

TEST(EditorKeyframes3D, SaveReopenKeepsPainted3DKeyframesBitForBit) {
  EditorHarness h("kf3d_save");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  h.start(scene, /*gl=*/false);
  h.app->canvas.hardness = 0.3f;  // soft edges: bytes other than 0 and 255
  ASSERT_EQ(h.run("wait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item slice_slot\nwait 2\nclick_item slot_10\nwait 2\n"
                  "drag_item_at slice_view 0.2 0.7 0.7 0.2 8\nwait 2\n"
                  // The initial density, painted the same way on another slice.
                  "click_item slice_slot\nwait 2\nclick_item slot_initial\nwait 2\n"),
            "");
  h.app->canvas.slice = 3;
  ASSERT_EQ(h.run("wait 1\ndrag_item_at slice_view 0.1 0.9 0.3 0.9 4\nwait 2\nkey CTRL+S\nwait 2\nexpect Saved\n"), "");
  const json edited = h.app->doc.scene();
  ASSERT_EQ(edited["control"]["initial_density"][0]["type"], "painted");
  ASSERT_EQ(edited["control"]["keyframes"][0]["target"]["type"], "painted");
  const geom::PaintedGrid k = slot_volume(*h.app, 0), init = slot_volume(*h.app, kInitialDensitySlot);
  size_t soft = 0;
  for (uint8_t v : k.value) soft += v > 0 && v < 255;
  EXPECT_GT(soft, 5u);
  ASSERT_TRUE(h.app->cmd_open(scene));
  EXPECT_EQ(h.app->doc.scene(), edited);
  EXPECT_EQ(slot_volume(*h.app, 0).value, k.value);
  EXPECT_EQ(slot_volume(*h.app, kInitialDensitySlot).value, init.value);
  EXPECT_EQ(h.app->scene_error(), "");
}

TEST(EditorKeyframes3D, TinySolveFromAPainted3DKeyframeRuns) {
  EditorHarness h("kf3d_solve");
  fs::path scene = h.copy_scene("keyframe_3d.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  h.app->canvas.radius_cells = 3.0f;
  ASSERT_EQ(h.run("wait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item slice_slot\nwait 2\nclick_item slot_10\nwait 2\n"
                  "drag_item_at slice_view 0.3 0.25 0.7 0.25 6\nwait 3\n"
                  "move 2 2\nwait 3\nscreenshot $TMP/paint.png\nwait 2\n"),
            "");
  ASSERT_EQ(h.app->doc.scene()["control"]["keyframes"][0]["target"]["type"], "painted");
  match_slices_golden(*h.app, h.dir / "paint.png", "keyframes_3d_paint.png");
  ASSERT_EQ(h.run("click_item Solve\nwait_job 90\nexpect \"Job 1: done\"\nwait_frames 11 10\n"), "");
  EXPECT_EQ(h.app->take.status(), "done");
  TakeReader take(h.app->take.dir());
  ASSERT_EQ(take.frame_count(), 11u);
  const Record last = take.read_frame_at(10);
  const Field* d = last.find("density");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->shape, (std::vector<uint32_t>{16, 16, 16}));
  EXPECT_EQ(take.manifest().metrics["keyframes"].size(), 1u);
}

}  // namespace pliant::editor::test
