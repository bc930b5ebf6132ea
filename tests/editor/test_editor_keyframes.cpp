// Keyframing smoke in the editor (issue 4) through UI scripts: paint a blob at
// frame 20 and type a letter at frame 40 on the canvas, solve 32^2 x 40, scrub to
// the keyframes and match golden screenshots, export PNGs (and MP4 when ffmpeg is
// installed); undo/redo of a stroke; save/reopen and autosave keep keyframes bit
// for bit; dropped images and meshes become keyframes; cancelling a solve.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "doc/export_run.h"
#include "doc/smoke_keyframes.h"
#include "editor_harness.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "render/image_compare.h"
#include "render/screenshot.h"

namespace pliant::editor::test {

using nlohmann::json;

namespace {

// Frame k of T on the keyframe strip (smoke_timeline_markers.cpp: 0.01 + 0.98 k / T).
std::string strip_x(int k, int T) { return std::to_string(0.01 + 0.98 * k / T); }

geom::PaintedGrid slot_grid(App& app, int slot) {
  std::string err;
  geom::PaintedGrid g = rasterize_slot(app.doc.scene(), app.doc.path().parent_path(), slot, &err);
  EXPECT_EQ(err, "");
  return g;
}

}  // namespace

TEST(EditorKeyframes, PaintTypeSolveScrubMatchGoldensAndExport) {
  EditorHarness h("kf_solve");
  fs::path scene = h.copy_scene("keyframe_32.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\n"
                  "click_item view_keyframes\nwait 2\n"
                  // A soft blob at frame 20, upper left.
                  "click_item_at keyframe_strip " + strip_x(20, 40) + " 0.5\nwait 2\n"
                  "click_item add_key\nwait 2\n"
                  "expect_json /control/keyframes/0/frame 20\n"
                  "drag_item_at keyframe_canvas 0.35 0.35 0.42 0.4 6\nwait 2\n"
                  // The letter L at frame 40, typed into the text tool.
                  "click_item_at keyframe_strip " + strip_x(40, 40) + " 0.5\nwait 2\n"
                  "click_item add_key\nwait 2\n"
                  "expect_json /control/keyframes/1/frame 40\n"
                  "click_item tool_Text\nwait 2\n"
                  "click_item canvas_text\nwait 1\nkey CTRL+A\ntype L\nkey ENTER\nwait 1\n"
                  "click_item_at keyframe_canvas 0.55 0.5\nwait 2\n"
                  "expect \"(Keyframe 40)\"\n"
                  "click_item Solve\n"
                  "wait_job 90\n"
                  "expect \"Job 1: done\"\n"
                  "wait_frames 41 10\n"
                  "click_item view_result\nwait 2\n"
                  "click_item_at keyframe_strip " + strip_x(20, 40) + " 0.5\nwait 3\n"
                  "move 2 2\nwait 2\n"
                  "screenshot $TMP/f20.png viewport\n"
                  "click_item_at keyframe_strip " + strip_x(40, 40) + " 0.5\nwait 3\n"
                  "move 2 2\nwait 2\n"
                  "screenshot $TMP/f40.png viewport\n"
                  "export png $TMP/png\nwait_export 60\nwait 2\n"
                  "expect \"Export done\"\n"),
            "");
  const json& ks = h.app->doc.scene()["control"]["keyframes"];
  ASSERT_EQ(ks.size(), 2u);
  EXPECT_EQ(ks[0]["target"]["type"], "painted");
  EXPECT_GT(painted_cell_count(slot_grid(*h.app, 0)), 20u);
  EXPECT_GT(painted_cell_count(slot_grid(*h.app, 1)), 30u);
  EXPECT_EQ(h.app->take.status(), "done");
  EXPECT_EQ(h.app->take.frame, 40);
  TakeReader take(h.app->take.dir());
  EXPECT_EQ(take.manifest().metrics["keyframes"].size(), 2u);
  match_golden(h.dir / "f20.png", "keyframes_frame20.png");
  match_golden(h.dir / "f40.png", "keyframes_frame40.png");

  // 41 PNGs (frames 0..40), each with some smoke in it.
  int files = 0;
  for (const auto& e : fs::directory_iterator(h.dir / "png")) {
    ++files;
    std::string err;
    Image img = read_png(e.path().string(), &err);
    ASSERT_FALSE(img.empty()) << e.path() << ": " << err;
    int lit = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4) lit += img.rgba[i] > 20;
    EXPECT_GT(lit, 10) << e.path();
  }
  EXPECT_EQ(files, 41);

  // A/B: the same take as B draws the same smoke in the right half of the viewport.
  ASSERT_EQ(h.run("click_item ab_compare\nwait 2\n"), "");
  ASSERT_TRUE(h.app->compare.enabled);
  h.app->compare.open(h.app->take.dir());
  ASSERT_EQ(h.run("wait 3\nscreenshot $TMP/ab.png\n"), "");
  {
    const UiRect* vr = h.app->marks.find("viewport");
    ASSERT_NE(vr, nullptr);
    std::string err;
    Image ab = read_png((h.dir / "ab.png").string(), &err);
    ASSERT_FALSE(ab.empty()) << err;
    int bright[2] = {0, 0};
    const int xm = int(0.5f * (vr->x0 + vr->x1));
    for (int y = int(vr->y0); y < int(vr->y1); ++y)
      for (int x = int(vr->x0); x < int(vr->x1); ++x)
        if (ab.pixel(x, y)[0] > 120 && ab.pixel(x, y)[2] > 120) ++bright[x < xm ? 0 : 1];
    EXPECT_GT(bright[0], 200);
    EXPECT_GT(bright[1], 200);
    EXPECT_NEAR(double(bright[1]) / bright[0], 1.0, 0.35);
  }
  ASSERT_EQ(h.run("click_item ab_compare\nwait 2\n"), "");

  if (find_ffmpeg().empty()) {
    GTEST_SKIP() << "ffmpeg is not installed: MP4 export not checked";
  }
  ASSERT_EQ(h.run("export mp4 $TMP/mp4\nwait_export 60\nwait 2\nexpect \"Export done\"\n"), "");
  EXPECT_GT(fs::file_size(h.dir / "mp4" / "take.mp4"), 1000u);
}

TEST(EditorKeyframes, BrushStrokeIsOneUndoStepAndUndoRedoRestoreTheCanvasExactly) {
  EditorHarness h("kf_undo");
  fs::path scene = h.copy_scene("keyframe_32.json");
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item_at keyframe_strip " + strip_x(10, 40) + " 0.5\nwait 2\n"
                  "click_item add_key\nwait 2\n"
                  "drag_item_at keyframe_canvas 0.3 0.3 0.6 0.5 8\nwait 2\n"),
            "");
  const json before_stroke = h.app->doc.scene();
  const geom::PaintedGrid g1 = slot_grid(*h.app, 0);
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item tool_Eraser\nwait 1\ndrag_item_at keyframe_canvas 0.3 0.3 0.6 0.5 8\nwait 2\n"), "");
  const json after_stroke = h.app->doc.scene();
  const geom::PaintedGrid g2 = slot_grid(*h.app, 0);
  EXPECT_EQ(h.app->doc.history().size(), steps + 1) << "one stroke, one undo step";
  EXPECT_LT(painted_cell_count(g2), painted_cell_count(g1));
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before_stroke);
  EXPECT_EQ(slot_grid(*h.app, 0).value, g1.value);
  EXPECT_EQ(h.app->canvas.grid.value, g1.value) << "the canvas shows the restored bytes";
  ASSERT_EQ(h.run("key CTRL+SHIFT+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), after_stroke);
  EXPECT_EQ(h.app->canvas.grid.value, g2.value);
  // The other tools also make one step each: rectangle, fill, move, clear.
  const size_t n0 = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item tool_Rectangle\nwait 1\ndrag_item_at keyframe_canvas 0.1 0.1 0.3 0.2 4\nwait 1\n"
                  "click_item tool_Ellipse\nwait 1\ndrag_item_at keyframe_canvas 0.6 0.6 0.9 0.9 4\nwait 1\n"
                  "click_item tool_Move\nwait 1\ndrag_item_at keyframe_canvas 0.5 0.5 0.55 0.5 4\nwait 1\n"
                  "click_item canvas_clear\nwait 2\n"),
            "");
  EXPECT_EQ(h.app->doc.history().size(), n0 + 4);
  EXPECT_EQ(painted_cell_count(slot_grid(*h.app, 0)), 0u);
  // A rectangle at strength 0.5 writes round(127.5) = 128 in its box (cell centres
  // in x 3.2..9.6, y 25.6..28.8 on the 32^2 grid, a pixel either way), 0 elsewhere.
  h.app->canvas.strength = 0.5f;
  const json cleared = h.app->doc.scene();
  ASSERT_EQ(h.run("click_item tool_Rectangle\nwait 1\ndrag_item_at keyframe_canvas 0.1 0.1 0.3 0.2 4\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.history().size(), n0 + 5);
  const geom::PaintedGrid r = slot_grid(*h.app, 0);
  int lo[2] = {99, 99}, hi[2] = {-1, -1};
  for (int j = 0; j < r.n[1]; ++j)
    for (int i = 0; i < r.n[0]; ++i) {
      const uint8_t v = r.value[size_t(j) * r.n[0] + i];
      if (!v) continue;
      EXPECT_EQ(v, 128) << i << "," << j;
      lo[0] = std::min(lo[0], i), hi[0] = std::max(hi[0], i), lo[1] = std::min(lo[1], j), hi[1] = std::max(hi[1], j);
    }
  EXPECT_NEAR(lo[0], 3, 1);
  EXPECT_NEAR(hi[0], 9, 1);
  EXPECT_NEAR(lo[1], 26, 1);
  EXPECT_NEAR(hi[1], 28, 1);
  EXPECT_EQ(painted_cell_count(r), size_t(hi[0] - lo[0] + 1) * size_t(hi[1] - lo[1] + 1)) << "a full box";
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), cleared);
  EXPECT_EQ(painted_cell_count(h.app->canvas.grid), 0u);
}

TEST(EditorKeyframes, SaveReopenAndAutosaveKeepKeyframesBitForBit) {
  EditorHarness h("kf_save");
  fs::path scene = h.copy_scene("keyframe_32.json");
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\nclick_item view_keyframes\nwait 2\n"
                  "click_item_at keyframe_strip " + strip_x(15, 40) + " 0.5\nwait 2\nclick_item add_key\nwait 2\n"
                  "drag_item_at keyframe_canvas 0.2 0.7 0.7 0.2 10\nwait 2\n"
                  // The initial density, edited the same way.
                  "click_item canvas_slot\nwait 2\nclick_item slot_initial\nwait 2\n"
                  "drag_item_at keyframe_canvas 0.1 0.9 0.2 0.9 4\nwait 2\n"
                  "key CTRL+S\nwait 2\nexpect Saved\n"),
            "");
  const json edited = h.app->doc.scene();
  ASSERT_EQ(edited["control"]["initial_density"][0]["type"], "painted");
  const geom::PaintedGrid k = slot_grid(*h.app, 0), init = slot_grid(*h.app, kInitialDensitySlot);
  ASSERT_TRUE(h.app->autosave->write_now(h.app->doc));
  json autosaved = json::parse(std::ifstream(h.app->autosave->autosave_file()));
  EXPECT_EQ(autosaved.dump().find(edited["control"]["keyframes"][0]["target"]["data"].get<std::string>()) !=
                std::string::npos,
            true);
  ASSERT_TRUE(h.app->cmd_open(scene));
  EXPECT_EQ(h.app->doc.scene(), edited);
  EXPECT_EQ(slot_grid(*h.app, 0).value, k.value);
  EXPECT_EQ(slot_grid(*h.app, kInitialDensitySlot).value, init.value);
  EXPECT_EQ(h.app->scene_error(), "");
}

TEST(EditorKeyframes, DroppedImageAndMeshBecomeKeyframes) {
  EditorHarness h("kf_drop");
  fs::path scene = h.copy_scene("keyframe_32.json");
  // A 40x20 image with a bright disc on the left.
  Image img;
  img.width = 40;
  img.height = 20;
  img.rgba.assign(40 * 20 * 4, 0);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 40; ++x) {
      uint8_t* p = img.pixel(x, y);
      p[3] = 255;
      if ((x - 10) * (x - 10) + (y - 10) * (y - 10) < 64) p[0] = p[1] = p[2] = 255;
    }
  ASSERT_TRUE(write_png((h.dir / "disc.png").string(), img));
  h.start(scene, /*gl=*/false);
  ASSERT_EQ(h.run("wait 2\ndrop disc.png\nwait 2\nexpect \"Import image disc.png\"\n", "drop.txt"), "");
  auto ks = list_keyframes(h.app->doc.scene());
  ASSERT_EQ(ks.size(), 1u);
  EXPECT_EQ(ks[0].type, "painted");
  const geom::PaintedGrid g = slot_grid(*h.app, 0);
  EXPECT_GT(painted_cell_count(g), 20u);
  // The disc is on the left half of the grid.
  size_t left = 0;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 16; ++i) left += g.value[j * 32 + i] > 0;
  EXPECT_EQ(left, painted_cell_count(g));
  EXPECT_EQ(h.app->scene_error(), "");
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_TRUE(list_keyframes(h.app->doc.scene()).empty());

  // A mesh dropped on a 3D scene: a "mesh" keyframe that compiles (voxelised by the engine).
  fs::path scene3 = h.copy_scene("keyframe_3d.json");
  std::ofstream(h.dir / "cube.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                       "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                       "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  ASSERT_TRUE(h.app->cmd_open(scene3));
  ASSERT_EQ(h.run("wait 2\ndrop cube.obj\nwait 2\nexpect \"Import mesh cube.obj\"\n", "drop3.txt"), "");
  ks = list_keyframes(h.app->doc.scene());
  ASSERT_EQ(ks.size(), 2u);
  EXPECT_EQ(ks[0].frame, 1);
  EXPECT_EQ(ks[0].type, "mesh");
  EXPECT_EQ(h.app->doc.scene()["control"]["keyframes"][0]["target"]["file"], "cube.obj");
  EXPECT_EQ(h.app->scene_error(), "");
  // The slice view shows the voxelised cube: half the size of the 16^3 domain.
  ASSERT_EQ(h.run("click_item view_keyframes\nwait 3\n", "slices.txt"), "");
  EXPECT_EQ(h.app->canvas.volume_dims, (std::array<int, 3>{16, 16, 16}));
  double filled = 0;
  for (float v : h.app->canvas.volume) filled += v;
  EXPECT_NEAR(filled, 8 * 8 * 8, 8 * 8 * 8 * 0.15);
  // + Key on a 3D scene adds a sphere keyframe that compiles.
  ASSERT_EQ(h.run("click_item_at keyframe_strip " + strip_x(5, 10) + " 0.5\nwait 2\nclick_item add_key\nwait 2\n",
                  "addkey3d.txt"),
            "");
  EXPECT_EQ(list_keyframes(h.app->doc.scene()).size(), 3u);
  EXPECT_EQ(h.app->scene_error(), "");
}

TEST(EditorKeyframes, CancellingASolveLeavesACancelledTakeAndAResponsiveEditor) {
  EditorHarness h("kf_cancel");
  fs::path scene = h.copy_scene("keyframe_cancel_64.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\nclick_item Solve\nwait 2\n"), "");
  // Until the solver has reported an iteration (the job is really working).
  for (int k = 0; k < 400; ++k) {
    JobStatus st = h.app->newest_job()->snapshot();
    if (st.iter > 0 || st.ended()) break;
    ASSERT_EQ(h.run("wait 5\n"), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(h.app->newest_job()->snapshot().ended());
  ASSERT_EQ(h.run("click_item \"Cancel solve\"\nwait_job 30\nexpect \"Job 1: cancelled\"\n"), "");
  JobStatus st = h.app->newest_job()->snapshot();
  EXPECT_EQ(st.state, JobState::Cancelled);
  EXPECT_EQ(st.exit_code, 3);
  TakeReader take(h.app->take.dir());
  EXPECT_EQ(take.manifest().status, "cancelled");
  EXPECT_FALSE(take.torn_tail());
  // Responsive: frames keep coming quickly, and the canvas still edits.
  uint64_t before = h.app->frame_count();
  auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(h.run("wait 30\nclick_item view_keyframes\nwait 2\nclick_item canvas_slot\nwait 2\n"), "");
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(h.app->frame_count(), before + 30);
  EXPECT_LT(s, 10.0);
  EXPECT_EQ(h.app->take.status(), "cancelled");

  // Resume continues the same take with `pliant run --resume`; cancel it again.
  const fs::path take_dir = h.app->take.dir();
  ASSERT_EQ(h.run("click_item slot_initial\nwait 2\nclick_item Resume\nwait 3\nexpect \"Job 2 started\"\n"), "");
  JobProcess* j2 = h.app->newest_job();
  EXPECT_TRUE(j2->spec().resume);
  EXPECT_EQ(j2->spec().take, take_dir);
  for (int k = 0; k < 400 && j2->snapshot().iter == 0 && !j2->snapshot().ended(); ++k) {
    ASSERT_EQ(h.run("wait 5\n"), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(h.run("click_item \"Cancel solve\"\nwait_job 30\nexpect \"Job 2: cancelled\"\n"), "");
  EXPECT_EQ(TakeReader(take_dir).manifest().status, "cancelled");
}

}  // namespace pliant::editor::test
