// Pouring scenes in the editor (issue 7) through UI scripts: a tiny 2D pour
// (about 100 particles, 40 frames, one round of Algorithm 2) has its fill
// changed in the inspector, is planned from the jobs panel, and frame 25
// matches a golden screenshot (particles by speed, container sections); the
// fractions plot reads every frame; gizmo drags move and size the target
// container, one undo step each; a key pose is added on the timeline; the
// dropped container file replaces the target; the
// "particles" exporter plugin writes one PLY per frame that reads back equal
// to the take. A 3D frame draws the containers' marching-tetrahedra meshes.
// Before any run the placement view draws the scene's start (containers, the
// initial liquid, the key-pose path) and its gizmos move containers and key
// poses by the dragged distance; a planned take's key poses become the
// scene's with "Use plan" and are then dragged in the viewport.
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

// A closed box-shaped cup (OBJ, metres, outward normals): outer half width
// `inner_half` + `wall`, cavity half width `inner_half`, cavity floor at y = 0, rim at y = height, a floor
// `wall` thick under the cavity; the cavity is open at the top.
void write_box_cup_obj(const fs::path& file, double inner_half, double height, double wall) {
  const double a = inner_half + wall, c = inner_half, h = height, b = -wall;
  std::ofstream out(file);
  // 1-4 outer bottom, 5-8 outer top (rim outer), 9-12 inner top (rim inner), 13-16 cavity floor.
  const double ring[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i) out << "v " << a * ring[i][0] << " " << b << " " << a * ring[i][1] << "\n";
  for (int i = 0; i < 4; ++i) out << "v " << a * ring[i][0] << " " << h << " " << a * ring[i][1] << "\n";
  for (int i = 0; i < 4; ++i) out << "v " << c * ring[i][0] << " " << h << " " << c * ring[i][1] << "\n";
  for (int i = 0; i < 4; ++i) out << "v " << c * ring[i][0] << " " << 0.0 << " " << c * ring[i][1] << "\n";
  auto quad = [&](int p, int q, int r, int s) { out << "f " << p << " " << q << " " << r << "\nf " << p << " " << r << " " << s << "\n"; };
  quad(1, 2, 3, 4);  // outer bottom, facing -y
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    quad(1 + i, 5 + i, 5 + j, 1 + j);    // outer side, facing out
    quad(5 + i, 9 + i, 9 + j, 5 + j);    // rim, facing +y
    quad(9 + i, 13 + i, 13 + j, 9 + j);  // inner side, facing the cavity
  }
  quad(13, 16, 15, 14);  // cavity floor, facing +y
}

// Screen pixels per metre along x at world point (x, y, z) of a view (2D: uniform).
double pixels_per_metre_x(const LiquidViewTransform& v, double x, double y, double z) {
  auto sx = [&](double wx) {
    const auto c = mat4_apply(v.world_to_clip, {float(wx), float(y), float(z), 1.0f});
    return 0.5 * c[0] / c[3] * v.width;
  };
  return (sx(x + 0.1) - sx(x)) / 0.1;
}

}  // namespace

TEST(EditorLiquid, PlacementViewBeforeTheFirstRunMovesTargetAndKeyPoses) {
  EditorHarness h("liquid_place");
  fs::path scene = h.copy_scene("liquid_place_keys.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 3\nmove 2 2\nwait 2\nscreenshot $TMP/place.png viewport\n"), "");
  LiquidUiState& ui = liquid_ui(*h.app);
  EXPECT_EQ(h.app->take.frame_count(), 0);
  ASSERT_TRUE(ui.place_ok) << ui.place_error;
  ASSERT_TRUE(ui.place_view.valid);
  EXPECT_EQ(ui.place_view.dim, 2);
  // The initial liquid region: particles inside the source (x within its cavity).
  const Field* p = ui.place_record.find("particles");
  ASSERT_TRUE(p && p->shape.size() == 2 && p->shape[0] > 20);
  for (size_t i = 0; i < p->shape[0]; ++i) EXPECT_LT(std::abs(p->data[2 * i]), 0.036f);
  std::string err;
  Image shot = read_png((h.dir / "place.png").string(), &err);
  ASSERT_FALSE(shot.empty()) << err;
  EXPECT_GT(lit_pixels(shot), 300);
  match_golden(h.dir / "place.png", "liquid_place_frame0.png");

  // The target's move handle: the document moves by the dragged distance.
  const json before = h.app->doc.scene();
  const size_t undo0 = h.app->doc.history().cursor();
  ASSERT_NE(h.app->marks.find("liquid_target_move"), nullptr);
  const double ppm = pixels_per_metre_x(ui.place_view, 0.17, 0.0, 0.0);
  ASSERT_GT(ppm, 100.0);
  ASSERT_EQ(h.run("drag_item liquid_target_move 40 0 8\nwait 2\n"), "");
  const json& moved = h.app->doc.scene();
  EXPECT_NEAR(moved["target"]["position_m"][0].get<double>(), 0.17 + 40.0 / ppm, 1.5 / ppm);
  EXPECT_NEAR(moved["target"]["position_m"][1].get<double>(), 0.0, 1.5 / ppm);
  EXPECT_EQ(h.app->doc.history().cursor(), undo0 + 1);
  EXPECT_EQ(moved["source"], before["source"]);
  EXPECT_EQ(h.app->take.frame_count(), 0);  // nothing ran
  EXPECT_NE(h.app->marks.find("/target/velocity_mps"), nullptr);  // a moving target's field

  // Key pose 1's diamond: that key moves (up by 30 px), the others stay.
  ASSERT_NE(h.app->marks.find("liquid_key_pose_1"), nullptr);
  ASSERT_EQ(h.run("drag_item liquid_key_pose_1 0 -30 6\nwait 2\n"), "");
  const json& keys = h.app->doc.scene()["source"]["trajectory"];
  EXPECT_NEAR(keys[1]["position_m"][0].get<double>(), 0.05, 1.5 / ppm);
  EXPECT_NEAR(keys[1]["position_m"][1].get<double>(), 0.16 + 30.0 / ppm, 1.5 / ppm);
  EXPECT_EQ(keys[1]["tilt_deg"], 60);
  EXPECT_EQ(keys[0], before["source"]["trajectory"][0]);
  EXPECT_EQ(keys[2], before["source"]["trajectory"][2]);
  EXPECT_EQ(h.app->doc.history().cursor(), undo0 + 2);
  // The dragged key is selected: its tilt lever (up the container's axis, 60
  // deg toward +x) dragged to straight above the key sets the tilt to ~0.
  EXPECT_EQ(ui.selected_key, 1);
  const UiRect* lever = h.app->marks.find("liquid_key_tilt");
  const UiRect* key1 = h.app->marks.find("liquid_key_pose_1");
  ASSERT_TRUE(lever && key1);
  EXPECT_GT(lever->cx(), key1->cx() + 5);  // leaning toward +x
  const float lever_len = std::hypot(lever->cx() - key1->cx(), lever->cy() - key1->cy());
  ASSERT_EQ(h.run("drag_item liquid_key_tilt " + std::to_string(int(std::lround(key1->cx() - lever->cx()))) + " " +
                  std::to_string(int(std::lround(key1->cy() - lever_len - lever->cy()))) + " 6\nwait 2\n"),
            "");
  EXPECT_NEAR(h.app->doc.scene()["source"]["trajectory"][1]["tilt_deg"].get<double>(), 0.0, 3.0);
  EXPECT_EQ(h.app->doc.history().cursor(), undo0 + 3);
  // The view follows the document: the record was rebuilt and redrawn.
  ASSERT_EQ(h.run("key CTRL+Z\nwait 2\nkey CTRL+Z\nwait 2\nkey CTRL+Z\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);

  // A dropped closed mesh becomes the target container (one undo step), path
  // relative to the scene; the engine compiles it and the view draws it.
  write_box_cup_obj(h.dir / "cup.obj", 0.05, 0.04, 0.012);
  const size_t undo1 = h.app->doc.history().cursor();
  ASSERT_EQ(h.run("click_item liquid_drop_target\nwait 1\ndrop $TMP/cup.obj\nwait 3\n"), "");
  EXPECT_EQ(h.app->doc.scene()["target"]["container"], json({{"shape", "mesh"}, {"file", "cup.obj"}}));
  EXPECT_EQ(h.app->doc.history().cursor(), undo1 + 1);
  EXPECT_TRUE(ui.place_ok) << "the engine did not compile the mesh container: " << ui.place_error;
  EXPECT_NE(h.app->marks.find("liquid_target_move"), nullptr);
  EXPECT_EQ(h.app->marks.find("liquid_target_size"), nullptr);  // a mesh is sized by its file
}

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

  // The plan's key poses (metrics "trajectory") are drawn as markers on the
  // engine's curve through them; "Use plan" makes them the scene's keys
  // (planner none, one undo step), and a key's diamond then drags that key.
  const json& planned = metrics["trajectory"];
  ASSERT_TRUE(planned.is_array() && planned.size() >= 2);
  EXPECT_EQ(ui.plan_keys, planned);
  EXPECT_EQ(ui.plan_path.size(), take.frame_count());
  EXPECT_NE(h.app->marks.find("liquid_plan_key_1"), nullptr);
  ASSERT_EQ(h.run("click_item liquid_use_plan\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene()["planner"]["mode"], "none");
  ASSERT_EQ(h.app->doc.scene()["source"]["trajectory"].size(), planned.size());
  EXPECT_EQ(h.app->doc.history().cursor(), undo_before + 4);
  const double key_x = h.app->doc.scene()["source"]["trajectory"][1]["position_m"][0].get<double>();
  ASSERT_NE(h.app->marks.find("liquid_key_pose_1"), nullptr);
  ASSERT_EQ(h.run("drag_item liquid_key_pose_1 30 0 6\nwait 2\n"), "");
  EXPECT_GT(h.app->doc.scene()["source"]["trajectory"][1]["position_m"][0].get<double>(), key_x + 0.005);
  EXPECT_EQ(h.app->doc.history().cursor(), undo_before + 5);

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
