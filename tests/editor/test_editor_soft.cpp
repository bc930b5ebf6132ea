// The soft character workflow in the editor (issue 5): load a small spider
// scene (lattice resolution 4, 4 modes, 1 LM iteration over 8 frames, 16
// frames 0..15, --threads 1), Optimize, scrub to the end and match a golden
// screenshot; export the take as OBJ files through the "obj" plugin; in the
// Character mode a mode slider deforms the preview (pixels change) without
// editing the document; a vertex pin and a gizmo drag are one undo step each;
// a pin's target is dragged afterwards (one undo step); the body compiles off
// the UI thread (frames keep coming, a newer edit supersedes an older one); live
// playback of the take's controller replays the take, takes a push and a
// click-and-drag push along the drag.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "doc/soft_scene.h"
#include "editor_harness.h"
#include "pliant/core/take.h"
#include "render/image_compare.h"
#include "render/screenshot.h"
#include "ui/soft_ui.h"
#ifdef PLIANT_HAVE_SOFT
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor::test {

using nlohmann::json;

namespace {

// The test scene with the spider mesh's absolute path (jobs of unsaved edits
// run a copy of the scene from another folder).
fs::path spider_scene(EditorHarness& h) {
  fs::path scene = h.copy_scene("soft_spider.json");
  json s = json::parse(std::ifstream(scene));
  s["character"]["mesh"] = fs::absolute(test_data("../../assets/characters/spider.obj")).lexically_normal().string();
  std::ofstream(scene) << s.dump(2);
  return scene;
}

// Pixels inside `r` (window coordinates) that differ by more than 24 in any channel.
int changed_pixels(const Image& a, const Image& b, const UiRect& r) {
  int n = 0;
  for (int y = int(r.y0); y < int(r.y1); ++y)
    for (int x = int(r.x0); x < int(r.x1); ++x)
      for (int c = 0; c < 3; ++c)
        if (std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c])) > 24) {
          ++n;
          break;
        }
  return n;
}

Image shot(EditorHarness& h, const std::string& name) {
  EXPECT_EQ(h.run("wait 3\nscreenshot $TMP/" + name + "\n"), "");
  std::string err;
  Image img = read_png((h.dir / name).string(), &err);
  EXPECT_FALSE(img.empty()) << err;
  return img;
}

std::string num(float v) { return std::to_string(int(std::lround(v))); }

// Runs frames until the Character mode's body build has finished (at most ~30 s).
bool wait_body(EditorHarness& h) {
  SoftUi& ui = soft_ui(*h.app);
  for (int i = 0; i < 300 && (ui.preview.building() || !(ui.preview.model || !ui.preview.error.empty())); ++i)
    if (!h.run("wait 0.1\n").empty()) return false;
  return !ui.preview.building();
}

}  // namespace

TEST(EditorSoft, OptimizeWalkMatchesGoldenAndExportsObj) {
  EditorHarness h("soft_walk");
  h.start(spider_scene(h), /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\n"
                  "click_item soft_optimize\n"
                  "wait_job 90\n"
                  "expect \"Job 1: done\"\n"
                  "wait_frames 16 10\n"
                  "set_frame 15\n"
                  "wait 3\nmove 2 2\nwait 3\n"
                  "screenshot $TMP/walk15.png viewport\n"),
            "");
  EXPECT_EQ(h.app->take.status(), "done");
  EXPECT_EQ(h.app->take.frame, 15);
  EXPECT_EQ(h.app->renderer.drawer_name(), "soft");
  TakeReader take(h.app->take.dir());
  const json& metrics = take.manifest().metrics;
  ASSERT_TRUE(metrics.contains("objective_history"));
  EXPECT_EQ(metrics["objective_history"].size(), 2u);  // initial + 1 iteration
  // The optimizer never accepts an increase.
  EXPECT_LE(metrics["objective_final"].get<double>(), metrics["objective_initial"].get<double>());
  // The live plot saw the objective.
  EXPECT_FALSE(h.app->newest_job()->snapshot().objective.empty());
  match_golden(h.dir / "walk15.png", "soft_walk_frame15.png");

  // A/B: a second optimization beside the first draws a character in each half.
  const fs::path first_take = h.app->take.dir();
  ASSERT_EQ(h.run("click_item soft_optimize\nwait_job 90\nexpect \"Job 2: done\"\nwait_frames 16 10\n"
                  "click_item ab_compare\nwait 2\n"),
            "");
  ASSERT_TRUE(h.app->compare.enabled);
  EXPECT_EQ(h.app->compare.dir, first_take);
  ASSERT_EQ(h.run("set_frame 15\nwait 3\nscreenshot $TMP/ab.png\nclick_item ab_compare\nwait 2\n"), "");
  {
    const UiRect* vr = h.app->marks.find("viewport");
    ASSERT_NE(vr, nullptr);
    std::string err;
    Image ab = read_png((h.dir / "ab.png").string(), &err);
    ASSERT_FALSE(ab.empty()) << err;
    int body[2] = {0, 0};  // the character's orange
    const int xm = int(vr->cx());
    for (int y = int(vr->y0); y < int(vr->y1); ++y)
      for (int x = int(vr->x0); x < int(vr->x1); ++x) {
        const auto* p = ab.pixel(x, y);
        if (p[0] > 120 && p[0] > p[2] + 50) ++body[x < xm ? 0 : 1];
      }
    EXPECT_GT(body[0], 300);
    EXPECT_GT(body[1], 300);
    EXPECT_NEAR(double(body[1]) / body[0], 1.0, 0.35);
  }

  // OBJ export: one file per frame, frame 0's triangles in every file.
  const fs::path plugin = fs::path(PLIANT_BIN).parent_path() / "plugins" / "libobj_sequence.so";
  if (!fs::exists(plugin)) GTEST_SKIP() << "obj_sequence plugin not built: " << plugin;
  const fs::path out = h.dir / "obj";
  const std::string cmd = std::string("\"") + PLIANT_BIN + "\" export \"" + h.app->take.dir().string() +
                          "\" --format obj --out \"" + out.string() + "\" > \"" + (h.dir / "export.log").string() +
                          "\" 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(h.dir / "export.log").rdbuf();
  const Record f0 = take.read_frame_at(0), f15 = take.read_frame_at(15);
  const size_t nverts = f0.find("vertices")->shape[0], ntris = f0.find("triangles")->shape[0];
  int files = 0;
  for (const auto& e : fs::directory_iterator(out)) files += e.path().extension() == ".obj";
  EXPECT_EQ(files, 16);
  std::ifstream obj(out / "frame_00015.obj");
  ASSERT_TRUE(obj.good());
  size_t v = 0, f = 0;
  double x0 = 0;
  std::string line;
  while (std::getline(obj, line)) {
    if (line.rfind("v ", 0) == 0) {
      if (v == 0) x0 = std::stod(line.substr(2));
      ++v;
    }
    f += line.rfind("f ", 0) == 0;
  }
  EXPECT_EQ(v, nverts);
  EXPECT_EQ(f, ntris);
  EXPECT_NEAR(x0, f15.find("vertices")->data[0], 1e-5);  // frame 15's positions, not frame 0's
}

// Live playback: the engine's realtime simulation of the take's controller replays
// the take (same centre of mass frame by frame), runs past its end, and a push
// moves the body sideways; Tracking and Restart are UI state only.
// Where the ray through window pixel (sx, sy) of the image (x0, y0, w, h) meets the
// plane y = py (the drag push's ground plane), for the test's expected direction.
std::array<float, 3> live_test_ground_hit(const Mat4& m, float sx, float sy, const UiRect& r, int w, int h, float py) {
  const Mat4 inv = mat4_inverse(m);
  const float nx = 2 * (sx - r.x0) / w - 1, ny = 1 - 2 * (sy - r.y0) / h;
  const auto a = mat4_apply(inv, {nx, ny, -1, 1}), b = mat4_apply(inv, {nx, ny, 1, 1});
  std::array<float, 3> p, q;
  for (int i = 0; i < 3; ++i) p[i] = a[i] / a[3], q[i] = b[i] / b[3];
  const float t = (py - p[1]) / (q[1] - p[1]);
  return {p[0] + t * (q[0] - p[0]), py, p[2] + t * (q[2] - p[2])};
}

TEST(EditorSoft, LivePlaybackReplaysTheTakeAndTakesAPushAndADrag) {
  EditorHarness h("soft_live");
  h.start(spider_scene(h), /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\nclick_item soft_optimize\nwait_job 90\nexpect \"Job 1: done\"\nwait_frames 16 10\n"), "");
  std::vector<std::array<float, 3>> take_com;
  {
    TakeReader take(h.app->take.dir());
    for (size_t i = 0; i < take.frame_count(); ++i) {
      const Record r = take.read_frame_at(i);
      const Field* c = r.find("com");
      ASSERT_NE(c, nullptr);
      take_com.push_back({c->data[0], c->data[1], c->data[2]});
    }
  }
  ASSERT_EQ(take_com.size(), 16u);
  SoftLive& live = soft_ui(*h.app).live;
  const uint64_t uploads = h.app->viewport.uploads;
  ASSERT_EQ(h.run("click_item soft_live\n"), "");
  ASSERT_TRUE(live.on) << live.error;
  // The body compiles off the UI thread, then one step per 1/dt of UI time.
  for (int i = 0; i < 300 && live.frame() < 20 && live.on; ++i) ASSERT_EQ(h.run("wait 0.1\n"), "");
  ASSERT_TRUE(live.on) << live.error;
  ASSERT_GE(live.frame(), 20);  // past the take's last frame (15)
  EXPECT_GT(h.app->viewport.uploads, uploads + 10);
  EXPECT_EQ(h.app->renderer.drawer_name(), "soft");
  ASSERT_GE(live.com.size(), 16u);
  double travel = 0;  // the take moves: the comparison is not between two resting bodies
  for (size_t f = 0; f < 16; ++f)
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(live.com[f][i], take_com[f][i], 1e-4) << "frame " << f << " axis " << i;
  for (int i = 0; i < 3; ++i) travel = std::max(travel, double(std::abs(take_com[15][i] - take_com[0][i])));
  EXPECT_GT(travel, 1e-3) << take_com[0][0] << " " << take_com[0][1] << " " << take_com[0][2] << " -> "
                          << take_com[15][0] << " " << take_com[15][1] << " " << take_com[15][2];
  const std::vector<std::array<float, 3>> undisturbed = live.com;  // frames 0..>=20, no push

  const std::vector<float> undisturbed_yaw = live.yaw;
  ASSERT_EQ(undisturbed_yaw.size(), undisturbed.size());

  // Restart and drag the body 160 px to the right on screen, grabbed at a leg tip:
  // the surface vertex (away from the gizmo handles) whose moment arm about the
  // centre of mass turns the body most under that drag. Release after 20 UI frames
  // (~10 steps). At frame 20 the centre of mass has moved along the drag's ground
  // direction against the undisturbed run, and the body has turned (yaw about +y)
  // in the sign of (r x F)_y; the whole-body push (every node by mass, the former
  // drag) with the same drag moves it alike but turns it less.
  ASSERT_EQ(h.run("click_item soft_live_restart\nwait 2\n"), "");
  Mat4 m;
  int vw = 0, vh = 0;
  ASSERT_TRUE(soft_drawer_primary_view(&m, &vw, &vh));
  ASSERT_NE(h.app->marks.find("viewport"), nullptr);
  const UiRect vr = *h.app->marks.find("viewport");  // a copy: marks change every frame
  auto screen = [&](const std::array<float, 3>& p) {
    const auto c = mat4_apply(m, {p[0], p[1], p[2], 1});
    return std::array<float, 2>{vr.x0 + 0.5f * (c[0] / c[3] + 1) * vw, vr.y0 + 0.5f * (1 - c[1] / c[3]) * vh};
  };
  const std::array<float, 3> com_press = live.com.back();
  const int frame_press = live.frame();
  int pick = -1;
  float best = 0;
  for (size_t i = 0; 3 * i + 2 < live.vertices.size(); ++i) {
    const std::array<float, 3> v{live.vertices[3 * i], live.vertices[3 * i + 1], live.vertices[3 * i + 2]};
    const auto p = screen(v);
    bool near_handle = false;
    for (const auto& hd : soft_ui(*h.app).handles)
      near_handle = near_handle || std::hypot(hd.x - p[0], hd.y - p[1]) < 30;
    if (near_handle || p[0] < vr.x0 + 20 || p[0] > vr.x1 - 200 || p[1] < vr.y0 + 20 || p[1] > vr.y1 - 20) continue;
    const auto g0 = live_test_ground_hit(m, p[0], p[1], vr, vw, vh, v[1]);
    const auto g1 = live_test_ground_hit(m, p[0] + 160, p[1], vr, vw, vh, v[1]);
    const float ex = g1[0] - g0[0], ez = g1[2] - g0[2], el = std::hypot(ex, ez);
    const float arm = std::abs((v[2] - com_press[2]) * ex - (v[0] - com_press[0]) * ez) / el;  // |(r x e)_y|
    if (arm > best) best = arm, pick = int(i);
  }
  ASSERT_GE(pick, 0);
  const std::array<float, 3> pv{live.vertices[3 * pick], live.vertices[3 * pick + 1], live.vertices[3 * pick + 2]};
  const auto p0 = screen(pv);
  const float x1 = p0[0] + 160, y1 = p0[1];
  const auto g0 = live_test_ground_hit(m, p0[0], p0[1], vr, vw, vh, pv[1]);
  const auto g1 = live_test_ground_hit(m, x1, y1, vr, vw, vh, pv[1]);
  const float ex = g1[0] - g0[0], ez = g1[2] - g0[2], el = std::hypot(ex, ez);
  const float turn_sign = (pv[2] - com_press[2]) * ex - (pv[0] - com_press[0]) * ez > 0 ? 1.0f : -1.0f;  // (r x F)_y
  const std::string drag = "drag " + num(p0[0]) + " " + num(p0[1]) + " " + num(x1) + " " + num(y1) + " 20\n";
  ASSERT_EQ(h.run(drag), "");
  EXPECT_GT(live.drag_steps, 3);
  EXPECT_EQ(live.drag_vertex, -1);  // released
  EXPECT_GE(live.drag_patch.size(), 1u);
  for (int i = 0; i < 300 && live.frame() < 20 && live.on; ++i) ASSERT_EQ(h.run("wait 0.1\n"), "");
  ASSERT_GE(live.com.size(), 21u);
  ASSERT_GE(undisturbed.size(), 21u);
  const float dx = live.com[20][0] - undisturbed[20][0], dz = live.com[20][2] - undisturbed[20][2];
  const float moved = std::hypot(dx, dz);
  EXPECT_GT(moved, 1e-3) << dx << " " << dz;
  EXPECT_GT((dx * ex + dz * ez) / (moved * el), 0.9) << "moved (" << dx << ", " << dz << "), drag (" << ex << ", "
                                                      << ez << ")";
  const float yaw_local = live.yaw[20] - undisturbed_yaw[20];
  // The same drag, the whole-body push.
  live.drag_whole_body = true;
  ASSERT_EQ(h.run("click_item soft_live_restart\nwait 2\n"), "");
  ASSERT_EQ(h.run(drag), "");
  EXPECT_GT(live.drag_steps, 3);
  for (int i = 0; i < 300 && live.frame() < 20 && live.on; ++i) ASSERT_EQ(h.run("wait 0.1\n"), "");
  live.drag_whole_body = false;
  ASSERT_GE(live.yaw.size(), 21u);
  const float yaw_whole = live.yaw[20] - undisturbed_yaw[20];
  std::printf("leg-tip drag (vertex %d, pressed at frame %d, arm %.3f m): yaw change at frame 20 local %.4f rad, "
              "whole-body %.4f rad, expected sign %+.0f\n",
              pick, frame_press, best, yaw_local, yaw_whole, turn_sign);
  EXPECT_GT(turn_sign * yaw_local, 0.01f);
  EXPECT_GT(turn_sign * (yaw_local - yaw_whole), 0.01f);
  // Restart and push at once: the centre of mass leaves the take's path sideways (+z).
  ASSERT_EQ(h.run("click_item soft_live_restart\nclick_item soft_live_push\n"), "");
  for (int i = 0; i < 300 && live.frame() < 15 && live.on; ++i) ASSERT_EQ(h.run("wait 0.1\n"), "");
  ASSERT_GE(live.com.size(), 16u);
  EXPECT_GT(live.com[15][2] - take_com[15][2], 1e-3);
  EXPECT_EQ(live.drag_steps, 0);  // the button pushes without a drag
  // Tracking toggles the engine's feedback gains; Live off shows the take again.
  ASSERT_EQ(h.run("click_item soft_live_tracking\nwait 0.5\n"), "");
  EXPECT_TRUE(live.tracking);
  ASSERT_EQ(h.run("click_item soft_live\nwait 0.5\n"), "");
  EXPECT_FALSE(live.on);
  EXPECT_EQ(h.app->viewport.shown_frame, h.app->take.frame);
}

TEST(EditorSoft, ModeSliderDeformsPreviewAndPinsAndGizmosAreOneUndoStep) {
  EditorHarness h("soft_character");
  h.start(spider_scene(h), /*gl=*/true, 1280, 720);
  // No take yet: the Character view shows by itself (the mode flag stays off, so the
  // result view returns once a take exists).
  ASSERT_EQ(h.run("wait 2\nwait 1\n"), "");
  SoftUi& ui = soft_ui(*h.app);
  EXPECT_FALSE(ui.character_mode);
  ASSERT_NE(h.app->marks.find("soft_lattice"), nullptr);  // the view's toolbar
  EXPECT_EQ(h.app->marks.find("soft_result"), nullptr);  // nothing to go back to
  ASSERT_TRUE(wait_body(h));
  ASSERT_EQ(h.run("wait 2\n"), "");
  ASSERT_TRUE(ui.preview.model) << ui.preview.error;
  ASSERT_GE(ui.amplitude_m.size(), 1u);
  const UiRect* canvas = h.app->marks.find("soft_character_canvas");
  ASSERT_NE(canvas, nullptr);
  const UiRect area = *canvas;

  // A mode slider deforms the preview, the document stays as it was.
  const json scene0 = h.app->doc.scene();
  const size_t steps0 = h.app->doc.history().size();
  Image before = shot(h, "rest.png");
  ASSERT_EQ(h.run("drag_item_at mode_slider_0 0.5 0.5 0.98 0.5 6\nwait 3\n"), "");
  EXPECT_GT(std::abs(ui.amplitude_m[0]), 1e-4f);
  Image after = shot(h, "mode0.png");
  EXPECT_GT(changed_pixels(before, after, area), 200);
  EXPECT_EQ(h.app->doc.scene(), scene0);
  EXPECT_EQ(h.app->doc.history().size(), steps0);
  ASSERT_EQ(h.run("click_item soft_rest_shape\nwait 3\n"), "");

  // Clicking a surface vertex pins it at frame 1 (no take yet): one undo step.
  // Aim at the vertex nearest the canvas centre.
  int best = -1;
  float bx = 0, by = 0, bd = 1e30f;
  for (size_t i = 0; 3 * i + 2 < ui.surface.size(); ++i) {
    const auto c = mat4_apply(ui.world_to_clip, {ui.surface[3 * i], ui.surface[3 * i + 1], ui.surface[3 * i + 2], 1});
    const float sx = area.x0 + 0.5f * (c[0] / c[3] + 1) * (area.x1 - area.x0);
    const float sy = area.y0 + 0.5f * (1 - c[1] / c[3]) * (area.y1 - area.y0);
    const float d = std::hypot(sx - area.cx(), sy - area.cy());
    if (d < bd) {
      bd = d;
      best = int(i);
      bx = sx;
      by = sy;
    }
  }
  ASSERT_GE(best, 0);
  ASSERT_EQ(h.run("move " + num(bx) + " " + num(by) + "\nwait 2\nclick " + num(bx) + " " + num(by) + "\nwait 3\n"), "");
  auto pins = soft_pins(h.app->doc.scene());
  ASSERT_EQ(pins.size(), 1u);
  EXPECT_EQ(pins[0].frame, 1);
  EXPECT_EQ(h.app->doc.history().size(), steps0 + 1);
  h.app->cmd_undo();
  EXPECT_TRUE(soft_pins(h.app->doc.scene()).empty());
  EXPECT_EQ(h.app->doc.scene(), scene0);
  h.app->cmd_redo();
  EXPECT_EQ(soft_pins(h.app->doc.scene()).size(), 1u);

  // The pin's target (red square) drags in its horizontal plane: offset x/z
  // change, y stays; one undo step; undo restores the pin.
  ASSERT_EQ(h.run("wait 2\n"), "");
  const SoftPin pin0 = soft_pins(h.app->doc.scene())[0];
  const SoftUi::Handle* pin_handle = nullptr;
  for (const auto& hd : ui.handles)
    if (hd.id == 4 && hd.vertex == pin0.vertex) pin_handle = &hd;
  ASSERT_NE(pin_handle, nullptr);
  EXPECT_NE(h.app->marks.find("soft_pin_" + std::to_string(pin0.vertex)), nullptr);
  const float px = pin_handle->x, py = pin_handle->y;
  const size_t steps_pin = h.app->doc.history().size();
  const json pinned_scene = h.app->doc.scene();
  ASSERT_EQ(h.run("drag " + num(px) + " " + num(py) + " " + num(px + 40) + " " + num(py + 10) + " 8\nwait 3\n"), "");
  const auto moved_pins = soft_pins(h.app->doc.scene());
  ASSERT_EQ(moved_pins.size(), 1u);
  EXPECT_EQ(moved_pins[0].vertex, pin0.vertex);
  EXPECT_EQ(moved_pins[0].frame, pin0.frame);
  EXPECT_GT(std::hypot(moved_pins[0].offset[0] - pin0.offset[0], moved_pins[0].offset[2] - pin0.offset[2]), 1e-3);
  EXPECT_NEAR(moved_pins[0].offset[1], pin0.offset[1], 1e-9);
  EXPECT_EQ(h.app->doc.history().size(), steps_pin + 1);
  h.app->cmd_undo();
  EXPECT_EQ(h.app->doc.scene(), pinned_scene);
  h.app->cmd_redo();

  // Dragging the heading arrow's tip turns the heading: one undo step.
  ASSERT_EQ(h.run("wait 2\n"), "");
  const SoftUi::Handle* heading = nullptr;
  for (const auto& hd : ui.handles)
    if (hd.id == 2) heading = &hd;
  ASSERT_NE(heading, nullptr);
  const float hx = heading->x, hy = heading->y;
  const json dir0 = h.app->doc.scene()["objectives"]["heading"]["direction"];
  const size_t steps1 = h.app->doc.history().size();
  const OrbitCamera cam0 = h.app->viewport.camera;
  ASSERT_EQ(h.run("drag " + num(hx) + " " + num(hy) + " " + num(hx - 10) + " " + num(hy + 60) + " 8\nwait 3\n"), "");
  EXPECT_NE(h.app->doc.scene()["objectives"]["heading"]["direction"], dir0);
  EXPECT_EQ(h.app->doc.history().size(), steps1 + 1);
  EXPECT_EQ(h.app->viewport.camera.yaw_deg, cam0.yaw_deg) << "the camera stays while a handle is dragged";
  h.app->cmd_undo();
  EXPECT_EQ(h.app->doc.scene()["objectives"]["heading"]["direction"], dir0);
}

}  // namespace pliant::editor::test

namespace pliant::editor::test {

#ifdef PLIANT_HAVE_SOFT
// The Character mode's body is compiled by a worker: the UI keeps drawing
// frames meanwhile, the body shows when it is done, and of two quick edits
// only the newest is shown.
TEST(EditorSoft, CharacterBodyCompilesOffTheUiThread) {
  EditorHarness h("soft_async");
  h.start(spider_scene(h), /*gl=*/true, 960, 540);
  SoftUi& ui = soft_ui(*h.app);
  ASSERT_EQ(h.run("wait 1\n"), "");  // no take: the Character view is shown
  ASSERT_NE(h.app->marks.find("soft_lattice"), nullptr);  // the view's toolbar
  ASSERT_TRUE(wait_body(h));
  ASSERT_TRUE(ui.preview.model) << ui.preview.error;
  // Frames were drawn while the worker compiled (the compile takes 0.2 s or
  // more; a frame of this small window a few ms).
  EXPECT_GE(ui.preview.frames_while_building, 2u);
  EXPECT_EQ(ui.preview.builds, 1);
  ASSERT_EQ(h.run("wait 1\n"), "");
  EXPECT_GT(ui.redraws, 0u);
  EXPECT_FALSE(ui.surface.empty());
  const size_t cells4 = ui.preview.model->character.lattice.cells.size();

  // Two edits in quick succession: resolution 3, then 5 the next frame.
  h.app->doc.set("/character/resolution", 3);
  ASSERT_EQ(h.run("wait 0.02\n"), "");
  EXPECT_TRUE(ui.preview.building());
  h.app->doc.set("/character/resolution", 5);
  ASSERT_TRUE(wait_body(h));
  ASSERT_EQ(h.run("wait 0.1\n"), "");
  ASSERT_TRUE(wait_body(h));
  ASSERT_TRUE(ui.preview.model) << ui.preview.error;
  EXPECT_EQ(ui.preview.key, ui.preview.wanted);
  EXPECT_GT(ui.preview.model->character.lattice.cells.size(), cells4);
  EXPECT_LE(ui.preview.builds, 3);
}
#endif  // PLIANT_HAVE_SOFT

TEST(EditorSoft, DroppedMeshBecomesTheCharacter) {
  EditorHarness h("soft_drop");
  h.start(spider_scene(h), /*gl=*/false);
  const fs::path mesh = h.dir / "meshes" / "bunny.obj";
  fs::create_directories(mesh.parent_path());
  fs::copy_file(test_data("../../assets/characters/worm.obj"), mesh);
  const size_t steps = h.app->doc.history().size();
  h.app->handle_drops({mesh.string()});
  EXPECT_EQ(h.app->doc.scene()["character"]["mesh"], "meshes/bunny.obj");  // relative to the scene
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  // Not a mesh: left to the generic handling, the character stays.
  const fs::path txt = h.dir / "notes.txt";
  std::ofstream(txt) << "x";
  h.app->handle_drops({txt.string()});
  EXPECT_EQ(h.app->doc.scene()["character"]["mesh"], "meshes/bunny.obj");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
}

// The steady objective's typed widgets: the checkbox adds the term with its
// defaults (one undo step), dragging its weight writes /objectives/steady/weight
// (one more step, the drag merged), undo takes the edit back.
TEST(EditorSoft, SteadyObjectiveWidgetsWriteTheSceneKey) {
  EditorHarness h("soft_steady");
  h.start(spider_scene(h), /*gl=*/false, 1280, 1600);  // tall: the objectives panel needs no scrolling
  const size_t steps = h.app->doc.history().size();
  ASSERT_FALSE(h.app->doc.scene()["objectives"].contains("steady"));
  ASSERT_EQ(h.run("wait 1\nclick_item objective_steady\nwait 1\n"), "");
  ASSERT_TRUE(h.app->doc.scene()["objectives"].contains("steady"));
  const json added = h.app->doc.scene()["objectives"]["steady"];
  EXPECT_EQ(added["weight"], 5);
  EXPECT_EQ(added["periods"], 1);
  EXPECT_EQ(added["periodicity_weight"], 0);
  EXPECT_EQ(added["direction"], json({1, 0, 0}));
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  ASSERT_EQ(h.run("drag_item /objectives/steady/weight 40 0 6\nwait 1\n"), "");
  const double w = h.app->doc.scene()["objectives"]["steady"]["weight"].get<double>();
  EXPECT_GT(w, 5.5);
  EXPECT_EQ(h.app->doc.history().size(), steps + 2);
  ASSERT_EQ(h.run("drag_item /objectives/steady/periodicity_weight 20 0 4\nwait 1\n"), "");
  EXPECT_GT(h.app->doc.scene()["objectives"]["steady"]["periodicity_weight"].get<double>(), 0.0);
  EXPECT_EQ(h.app->doc.history().size(), steps + 3);
  h.app->cmd_undo();
  h.app->cmd_undo();
  EXPECT_EQ(h.app->doc.scene()["objectives"]["steady"], added);
}

// The upright objective: the checkbox adds it (+y body axis, weight 10), a drag on
// its weight writes /objectives/upright/weight, each one undo step; unchecking
// removes it.
TEST(EditorSoft, UprightObjectiveWidgetsWriteTheSceneKey) {
  EditorHarness h("soft_upright");
  h.start(spider_scene(h), /*gl=*/false, 1280, 1600);
  const size_t steps = h.app->doc.history().size();
  ASSERT_FALSE(h.app->doc.scene()["objectives"].contains("upright"));
  ASSERT_EQ(h.run("wait 1\nclick_item objective_upright\nwait 1\n"), "");
  ASSERT_TRUE(h.app->doc.scene()["objectives"].contains("upright"));
  EXPECT_EQ(h.app->doc.scene()["objectives"]["upright"]["body_axis"], json({0, 1, 0}));
  EXPECT_EQ(h.app->doc.scene()["objectives"]["upright"]["weight"], 10);
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  ASSERT_EQ(h.run("drag_item /objectives/upright/weight 40 0 6\nwait 1\n"), "");
  EXPECT_GT(h.app->doc.scene()["objectives"]["upright"]["weight"].get<double>(), 10.5);
  EXPECT_EQ(h.app->doc.history().size(), steps + 2);
  ASSERT_EQ(h.run("click_item objective_upright\nwait 1\n"), "");
  EXPECT_FALSE(h.app->doc.scene()["objectives"].contains("upright"));
  EXPECT_EQ(h.app->doc.history().size(), steps + 3);
}

// Pure L-BFGS's variant keys (soft_worm_crawl.json pins them): the Optimizer panel
// shows them only once the method is lbfgs, picked in its combo; a drag writes
// /optimizer/lbfgs_memory, the line-search combo /optimizer/lbfgs_line_search,
// each one undo step.
TEST(EditorSoft, LbfgsOptimizerKeysAppearForPureLbfgsAndWriteTheScene) {
  EditorHarness h("soft_lbfgs_keys");
  h.start(spider_scene(h), /*gl=*/false, 1280, 2400);  // tall: the Optimizer panel needs no scrolling
  ASSERT_EQ(h.run("wait 2\n"), "");
  ASSERT_NE(h.app->marks.find("/optimizer/method"), nullptr);
  EXPECT_EQ(h.app->marks.find("/optimizer/lbfgs_memory"), nullptr);  // lm: hidden
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item /optimizer/method\nwait 1\nclick_item /optimizer/method=lbfgs\nwait 2\n"), "");
  ASSERT_EQ(h.app->doc.scene()["optimizer"]["method"], "lbfgs");
  ASSERT_NE(h.app->marks.find("/optimizer/lbfgs_memory"), nullptr);
  EXPECT_NE(h.app->marks.find("/optimizer/lbfgs_initial_step"), nullptr);
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  ASSERT_EQ(h.run("drag_item /optimizer/lbfgs_memory 60 0 6\nwait 1\n"), "");
  ASSERT_TRUE(h.app->doc.scene()["optimizer"].contains("lbfgs_memory"));
  EXPECT_GT(h.app->doc.scene()["optimizer"]["lbfgs_memory"].get<int>(), 8);
  EXPECT_EQ(h.app->doc.history().size(), steps + 2);
  ASSERT_EQ(h.run("click_item /optimizer/lbfgs_line_search\nwait 1\n"
                  "click_item /optimizer/lbfgs_line_search=wolfe\nwait 1\n"), "");
  EXPECT_EQ(h.app->doc.scene()["optimizer"]["lbfgs_line_search"], "wolfe");
  EXPECT_EQ(h.app->doc.history().size(), steps + 3);
  h.app->cmd_undo();
  h.app->cmd_undo();
  EXPECT_FALSE(h.app->doc.scene()["optimizer"].contains("lbfgs_memory"));
  h.app->cmd_undo();
  EXPECT_EQ(h.app->doc.scene()["optimizer"].value("method", std::string("hybrid")), "lm");
  ASSERT_EQ(h.run("wait 2\n"), "");
  EXPECT_EQ(h.app->marks.find("/optimizer/lbfgs_memory"), nullptr);
}

}  // namespace pliant::editor::test
