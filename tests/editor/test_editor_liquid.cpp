// Pouring scenes in the editor (issue 7) through UI scripts: a tiny 2D pour
// (about 100 particles, 40 frames, one round of Algorithm 2) has its fill
// changed in the inspector, is planned from the jobs panel, and frame 25
// matches a golden screenshot (particles by speed, container sections); the
// fractions plot reads every frame; gizmo drags move and size the target
// container, one undo step each; a key pose is added on the timeline; the
// dropped container file replaces the target; the
// "particles" exporter plugin writes one PLY per frame that reads back equal
// to the take. A 3D frame draws the containers' marching-tetrahedra meshes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "editor_harness.h"
#include "pliant/core/take.h"
#include "render/image_compare.h"
#include "render/screenshot.h"
#include "ui/liquid_ui.h"

namespace pliant::editor::test {

using nlohmann::json;

namespace {

// Pixels clearly different from the viewport background (0.08, 0.09, 0.11).
int lit_pixels(const Image& img, int min_channel = 60) {
  int lit = 0;
  for (size_t i = 0; i + 3 < img.rgba.size(); i += 4)
    lit += img.rgba[i] > min_channel || img.rgba[i + 1] > min_channel || img.rgba[i + 2] > min_channel;
  return lit;
}

// A binary little-endian PLY written by plugins/particles_export: vertex count
// and the float rows (x y z speed).
bool read_ply(const fs::path& file, size_t* n, std::vector<float>* rows) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  *n = 0;
  while (std::getline(in, line)) {
    if (line.rfind("element vertex ", 0) == 0) *n = std::stoul(line.substr(15));
    if (line == "end_header") break;
  }
  rows->resize(4 * *n);
  in.read(reinterpret_cast<char*>(rows->data()), std::streamsize(rows->size() * sizeof(float)));
  return bool(in) && *n > 0;
}

}  // namespace

TEST(EditorLiquid, EditPlanGoldenGizmosKeysAndExport) {
  EditorHarness h("liquid_pour");
  fs::path scene = h.copy_scene("liquid_pour_tiny.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  // Fill 0.6 -> 0.5 by dragging the inspector field (the format rounds to 0.01).
  ASSERT_EQ(h.run("wait 2\ndrag_item /liquid/fill_fraction -20 0 6\nwait 2\n"), "");
  const double fill = h.app->doc.scene()["liquid"]["fill_fraction"].get<double>();
  EXPECT_LT(fill, 0.6);
  EXPECT_GT(fill, 0.3);
  ASSERT_EQ(h.run("click_item liquid_plan\n"
                  "wait_job 60\n"
                  "expect \"Job 1: done\"\n"
                  "wait_frames 41 10\nwait 3\n"
                  "set_frame 25\nwait 3\nmove 2 2\nwait 2\n"
                  "screenshot $TMP/f25.png viewport\n"),
            "");
  EXPECT_EQ(h.app->take.status(), "done");
  EXPECT_EQ(h.app->take.frame, 25);
  EXPECT_EQ(h.app->renderer.drawer_name(), "liquid");
  TakeReader take(h.app->take.dir());
  const json& metrics = take.manifest().metrics;
  EXPECT_EQ(metrics["planner"]["mode"], "correction");
  EXPECT_GT(metrics["fraction_in_target"].get<double>(), 0.3);
  // The jobs panel's series holds every frame's fractions; the last equals the metrics.
  LiquidUiState& ui = liquid_ui(*h.app);
  ASSERT_EQ(ui.in_target.size(), take.frame_count());
  EXPECT_NEAR(ui.in_target.back(), metrics["fraction_in_target"].get<double>(), 1e-6);
  EXPECT_NEAR(ui.spilled.back(), metrics["fraction_spilled"].get<double>(), 1e-6);
  EXPECT_NE(h.app->marks.find("liquid_final"), nullptr);
  match_golden(h.dir / "f25.png", "liquid_pour_frame25.png");

  // Gizmos: a drag of the target's round handle moves it right (one undo step);
  // undo restores it exactly.
  const json before = h.app->doc.scene();
  const size_t undo_before = h.app->doc.history().cursor();
  ASSERT_NE(h.app->marks.find("liquid_target_move"), nullptr);
  ASSERT_EQ(h.run("drag_item liquid_target_move 40 0 8\nwait 2\n"), "");
  const json& moved = h.app->doc.scene();
  EXPECT_GT(moved["target"]["position_m"][0].get<double>(), before["target"]["position_m"][0].get<double>() + 0.005);
  EXPECT_NEAR(moved["target"]["position_m"][1].get<double>(), 0.0, 1e-3);
  EXPECT_EQ(h.app->doc.history().cursor(), undo_before + 1);
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  // The square handle widens and deepens the target (one undo step).
  ASSERT_EQ(h.run("drag_item liquid_target_size 20 -20 6\nwait 2\n"), "");
  const json& sized = h.app->doc.scene()["target"]["container"];
  EXPECT_GT(sized["radius_m"].get<double>(), 0.065);
  EXPECT_GT(sized["height_m"].get<double>(), 0.065);
  EXPECT_EQ(h.app->doc.history().cursor(), undo_before + 1);

  // Timeline: + Key adds a key pose at the shown frame (t = 25 * 0.02 s).
  ASSERT_EQ(h.run("click_item liquid_add_key\nwait 2\n"), "");
  const json& keys = h.app->doc.scene()["source"]["trajectory"];
  ASSERT_EQ(keys.size(), 1u);
  EXPECT_NEAR(keys[0]["time_s"].get<double>(), 0.5, 1e-9);
  EXPECT_EQ(h.app->doc.history().cursor(), undo_before + 2);

  // A dropped container file becomes the target chosen in the toolbar, inline.
  std::ofstream(h.dir / "box.json") << R"({"comment": "c", "shape": "box", "radius_m": 0.05, "depth_m": 0.04,
                                          "height_m": 0.05, "wall_m": 0.01})";
  ASSERT_EQ(h.run("click_item liquid_drop_target\nwait 1\ndrop $TMP/box.json\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene()["target"]["container"]["shape"], "box");
  EXPECT_FALSE(h.app->doc.scene()["target"]["container"].contains("comment"));
  EXPECT_EQ(h.app->doc.history().cursor(), undo_before + 3);

  // The particles exporter: one PLY per frame, equal to the take's particles.
  const fs::path plugin = fs::path(PLIANT_BIN).parent_path() / "plugins" / "libparticles_export.so";
  if (!fs::exists(plugin)) GTEST_SKIP() << "build the particles_export target for the export check";
  const fs::path out = h.dir / "ply";
  const std::string cmd = std::string(PLIANT_BIN) + " export " + h.app->take.dir().string() +
                          " --format particles --out " + out.string() + " > " + (h.dir / "export.log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  int files = 0;
  for (const auto& e : fs::directory_iterator(out)) files += e.path().extension() == ".ply";
  EXPECT_EQ(size_t(files), take.frame_count());
  const Record last = take.read_frame_at(take.frame_count() - 1);
  const Field* p = last.find("particles");
  const Field* s = last.find("speed");
  ASSERT_TRUE(p && s);
  char name[40];
  std::snprintf(name, sizeof name, "particles_%05d.ply", last.index);
  size_t n = 0;
  std::vector<float> rows;
  ASSERT_TRUE(read_ply(out / name, &n, &rows)) << out / name;
  ASSERT_EQ(n, p->shape[0]);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_EQ(rows[4 * i], p->data[2 * i]);
    EXPECT_EQ(rows[4 * i + 1], p->data[2 * i + 1]);
    EXPECT_EQ(rows[4 * i + 2], 0.0f);
    EXPECT_EQ(rows[4 * i + 3], s->data[i]);
  }
  // The same exporter from the editor (File > Export particles).
  ASSERT_EQ(h.run("export particles $TMP/ply_menu\nwait_export 60\nwait 2\nexpect \"Export done\"\n"), "");
  int menu_files = 0;
  for (const auto& e : fs::directory_iterator(h.dir / "ply_menu")) menu_files += e.path().extension() == ".ply";
  EXPECT_EQ(size_t(menu_files), take.frame_count());
}

TEST(EditorLiquid, ThreeDimensionalFrameDrawsContainerMeshes) {
  EditorHarness h("liquid_3d");
  fs::path scene = h.copy_scene("liquid_cup_tiny_3d.json");
  h.start(scene, /*gl=*/true, 960, 540);
  ASSERT_EQ(h.run("wait 2\nclick_item liquid_plan\nwait_job 60\nexpect \"Job 1: done\"\n"
                  "wait_frames 6 10\nwait 3\nset_frame 5\nwait 3\nmove 2 2\nwait 2\n"
                  "screenshot $TMP/cup.png viewport\n"),
            "");
  EXPECT_EQ(h.app->renderer.drawer_name(), "liquid");
  EXPECT_EQ(h.app->renderer.frame_dim(), 3);
  std::string err;
  Image shot = read_png((h.dir / "cup.png").string(), &err);
  ASSERT_FALSE(shot.empty()) << err;
  // The see-through cup and basin and the particles cover a good part of the view.
  EXPECT_GT(lit_pixels(shot), int(shot.width * shot.height / 50));
  match_golden(h.dir / "cup.png", "liquid_cup_3d_frame5.png");
}

}  // namespace pliant::editor::test
