// Articulated scenes in the editor (issue 6): a chain swinging onto a floor is
// simulated from the jobs panel and its contact frame matches a golden
// screenshot; "Compare integrators" runs one job per integrator and reads every
// run's energy curve; the hopper MPC scene (MJCF model by relative path, edited
// so the job runs from a copy) simulates and plays; a dropped model file becomes
// the scene's model in one undo step; mesh geoms are drawn as their meshes; a
// click on a body selects it and the inspector shows its joint and contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "editor_harness.h"
#include "pliant/core/take.h"
#include "render/articulated_drawer.h"
#include "render/image_compare.h"
#include "render/screenshot.h"
#include "render/articulated_drawer.h"
#include "ui/articulated_panels.h"
#include "ui/articulated_select.h"
#ifdef PLIANT_HAVE_ARTICULATED
#include "pliant/articulated/articulated.h"
#endif

namespace pliant::editor::test {

using nlohmann::json;

namespace {

fs::path source_asset(const std::string& rel) { return test_data("../../assets/" + rel); }

// A short hopper MPC scene beside a copy of the hopper MJCF (relative path).
fs::path write_hopper_scene(const fs::path& dir) {
  fs::copy_file(source_asset("models/hopper2d.xml"), dir / "hopper2d.xml", fs::copy_options::overwrite_existing);
  json s = {{"pliant", 1},
            {"kind", "articulated"},
            {"name", "hopper MPC (short)"},
            {"model", "hopper2d.xml"},
            {"integrator", "pbad2"},
            {"dt", 0.01},
            {"duration_s", 0.3},
            {"contact", {{"stiffness", 50000}, {"friction", "coulomb"}, {"mu", 0.9}}},
            {"mpc",
             {{"horizon", 4}, {"substeps", 2}, {"samples", 8}, {"elites", 2}, {"iterations", 1}, {"noise", 0.6},
              {"seed", 1}}}};
  fs::path p = dir / "hopper_short.json";
  std::ofstream(p) << s.dump(2);
  return p;
}

bool all_jobs_ended(App& app) {
  for (const auto& j : app.jobs) {
    JobStatus st = j->snapshot();
    if (!st.ended() || st.exit_code < 0) return false;
  }
  return true;
}

}  // namespace

TEST(EditorArticulated, SimulateChainAndContactFrameMatchesGolden) {
  EditorHarness h("art_chain");
  fs::path scene = h.copy_scene("articulated_chain.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\n"
                  "click_item Simulate\n"
                  "wait_job 60\n"
                  "expect \": done\"\n"
                  "wait_frames 61 10\n"
                  "set_frame 21\n"
                  "wait 3\n"
                  "screenshot $TMP/chain21.png viewport\n"),
            "");
  EXPECT_EQ(h.app->take.status(), "done");
  EXPECT_EQ(h.app->take.frame, 21);
  EXPECT_EQ(h.app->renderer.drawer_name(), "articulated");
  const ArticulatedFrameInfo& info = articulated_last_frame_info();
  EXPECT_EQ(info.model_error, "");
  EXPECT_EQ(info.bodies, 3);
  EXPECT_EQ(info.geoms, 4);  // three capsules and the box at the tip
  EXPECT_GE(info.contacts, 1);  // the box hits the floor at frame 20-22
  EXPECT_GT(info.max_force, 1.0f);
  EXPECT_TRUE(info.has_energy);
  match_golden(h.dir / "chain21.png", "articulated_chain_frame21.png");

  // Contacts off: the frame is uploaded again and the arrow (red-orange lines) goes.
  std::string err;
  Image with = read_png((h.dir / "chain21.png").string(), &err);
  ASSERT_EQ(h.run("click_item show_contacts\nwait 3\nscreenshot $TMP/chain21_off.png viewport\n"), "");
  EXPECT_FALSE(articulated_draw_options().show_contacts);
  Image without = read_png((h.dir / "chain21_off.png").string(), &err);
  ASSERT_FALSE(without.empty()) << err;
  auto arrow_pixels = [](const Image& img) {
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const auto* p = img.pixel(x, y);
        n += p[0] > 230 && p[1] > 60 && p[1] < 120 && p[2] < 90;  // (255, 89, 64)
      }
    return n;
  };
  EXPECT_GT(arrow_pixels(with), 10);
  EXPECT_EQ(arrow_pixels(without), 0);
  articulated_draw_options() = ArticulatedDrawOptions{};

  // File > Export Table (CSV): one row per frame, the take's energies in its columns.
  const fs::path plugin = fs::path(PLIANT_BIN).parent_path() / "plugins" / "libcsv_table.so";
  ASSERT_TRUE(fs::exists(plugin)) << plugin;  // built with no optional dependency
  ASSERT_EQ(h.run("export csv $TMP/table\nwait_export 60\nwait 2\nexpect \"Export done\"\n"), "");
  std::ifstream csv(h.dir / "table" / "frames.csv");
  std::string header, line, cell;
  ASSERT_TRUE(std::getline(csv, header));
  std::vector<std::string> names;
  for (std::stringstream hs(header); std::getline(hs, cell, ',');) names.push_back(cell);
  const size_t total = std::find(names.begin(), names.end(), "energy[2]") - names.begin();
  ASSERT_LT(total, names.size()) << header;
  TakeReader take(h.app->take.dir());
  size_t rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    for (std::stringstream ls(line); std::getline(ls, cell, ',');) cells.push_back(cell);
    ASSERT_GT(cells.size(), total) << line;
    EXPECT_FLOAT_EQ(std::stof(cells[total]), take.read_frame_at(rows).find("energy")->data[2]) << line;
    ++rows;
  }
  EXPECT_EQ(rows, take.frame_count());
}

// Mesh geoms are drawn as their triangles (they were boxes of the geom's unused
// size): two mesh tiles resting on a sphere and on a box corner.
TEST(EditorArticulated, MeshTilesAreDrawnAsTheirMeshes) {
  EditorHarness h("art_mesh");
  fs::create_directories(h.dir / "scenes");
  fs::create_directories(h.dir / "models");
  fs::copy_file(source_asset("models/tile.obj"), h.dir / "models" / "tile.obj");
  json s;
  {
    std::ifstream in(source_asset("scenes/articulated_mesh_tile.json"));
    s = json::parse(in);
  }
  s["duration_s"] = 0.4;
  const fs::path scene = h.dir / "scenes" / "mesh_tile.json";
  std::ofstream(scene) << s.dump(2);
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\n"
                  "click_item Simulate\n"
                  "wait_job 60\n"
                  "expect \": done\"\n"
                  "wait_frames 41 10\n"
                  "set_frame 40\n"
                  "wait 3\n"
                  "screenshot $TMP/tiles40.png viewport\n"),
            "");
  EXPECT_EQ(h.app->take.status(), "done");
  const ArticulatedFrameInfo& info = articulated_last_frame_info();
  EXPECT_EQ(info.model_error, "");
  EXPECT_EQ(info.bodies, 2);
  EXPECT_EQ(info.geoms, 2);     // the two tiles
  EXPECT_GE(info.contacts, 2);  // each rests on its obstacle
  match_golden(h.dir / "tiles40.png", "articulated_mesh_tiles_frame40.png");
}

#ifdef PLIANT_HAVE_ARTICULATED
namespace {

// Window pixel where the primary articulated view draws world point p (engine
// frame), the image's top-left corner at (x0, y0).
std::array<float, 2> sel_test_pixel(const ArticulatedView& v, float x0, float y0, const Eigen::Vector3d& p) {
  const auto c = mat4_apply(v.world_to_clip, {float(p.x()), float(p.y()), float(p.z()), 1.0f});
  return {x0 + 0.5f * (c[0] / c[3] + 1) * v.width, y0 + 0.5f * (1 - c[1] / c[3]) * v.height};
}

}  // namespace

// Click a body of the swinging chain at frame 21: it is selected, the inspector's
// joint value is the engine's qpos at that frame (the same scene stepped here),
// the contacts touching it are listed; scrubbing keeps it; empty space and Esc clear it.
TEST(EditorArticulated, ClickedBodyIsSelectedWithItsJointValueAndContacts) {
  EditorHarness h("art_select");
  fs::path scene = h.copy_scene("articulated_chain.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\nclick_item Simulate\nwait_job 60\nexpect \": done\"\nwait_frames 61 10\n"
                  "set_frame 21\nwait 3\n"),
            "");
  const size_t steps0 = h.app->doc.history().size();
  // The engine's qpos per frame: the take's scene stepped like the job does.
  TakeReader take(h.app->take.dir());
  Scene sc;
  sc.file = "scene";
  sc.dir = h.dir;
  sc.kind = "articulated";
  sc.doc = take.manifest().scene;
  const articulated::ArticulatedScene a = articulated::articulated_compile(sc);
  std::vector<Eigen::VectorXd> qref = {a.initial.qpos};
  {
    articulated::State s = a.initial;
    articulated::SimWorkspace ws;
    for (int i = 1; i <= 30; ++i) {
      ASSERT_TRUE(articulated::sim_step(a.model, a.options, s, ws));
      qref.push_back(s.qpos);
    }
  }
  articulated::Kinematics kin;
  articulated::kinematics(a.model, qref[21], &kin, true);

  const ArticulatedView* view = articulated_primary_view();
  ASSERT_NE(view, nullptr);
  ASSERT_NE(h.app->marks.find("viewport"), nullptr);
  const UiRect vr = *h.app->marks.find("viewport");  // a copy: marks change every frame
  const UiRect* vp = &vr;
  // The middle of link2's capsule (body 2, from (0,0,0) to (0.1,0,0) in its frame).
  const Eigen::Vector3d mid2 = kin.xpos[2] + kin.xmat[2] * Eigen::Vector3d(0.05, 0, 0);
  auto px = sel_test_pixel(*view, vp->x0, vp->y0, mid2);
  ASSERT_EQ(h.run("click " + std::to_string(px[0]) + " " + std::to_string(px[1]) + "\nwait 3\n"), "");
  auto& st = h.app->kind_ui.get<ArticulatedUiState>("articulated");
  EXPECT_EQ(st.selected_body, 2);
  EXPECT_EQ(st.selected_name, "link2");
  const ArticulatedSelection* sel = articulated_selection(*h.app);
  ASSERT_NE(sel, nullptr);
  EXPECT_EQ(sel->error, "");
  EXPECT_EQ(sel->body_name, "link2");
  EXPECT_EQ(sel->frame, 21);
  ASSERT_EQ(sel->joints.size(), 1u);
  EXPECT_EQ(sel->joints[0].type, "hinge");
  const int qadr = a.model.joints[a.model.bodies[2].joints[0]].qadr;
  ASSERT_EQ(sel->joints[0].qpos.size(), 1u);
  EXPECT_NEAR(sel->joints[0].qpos[0], qref[21][qadr], 1e-4);
  EXPECT_GT(std::abs(qref[21][qadr] - qref[0][qadr]), 0.05);  // the joint has moved: not the initial value
  // qvel: the central difference of the engine's qpos.
  EXPECT_NEAR(sel->joints[0].qvel[0], (qref[22][qadr] - qref[20][qadr]) / (2 * a.options.dt), 1e-2);
  EXPECT_NEAR(sel->mass, a.model.bodies[2].mass, 1e-9);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(sel->world_pos[i], kin.xpos[2][i], 1e-4);
  EXPECT_NE(h.app->marks.find("selected_body"), nullptr);  // the inspector section is drawn
  EXPECT_TRUE(sel->contacts.empty());  // link2 hangs in the air

  // The box at link3's tip is on the floor at frame 21: its contacts, depth = |f| / k.
  const Eigen::Vector3d box3 = kin.xpos[3] + kin.xmat[3] * Eigen::Vector3d(0.12, 0, 0);
  px = sel_test_pixel(*view, vp->x0, vp->y0, box3);
  ASSERT_EQ(h.run("click " + std::to_string(px[0]) + " " + std::to_string(px[1]) + "\nwait 3\n"), "");
  EXPECT_EQ(st.selected_name, "link3");
  sel = articulated_selection(*h.app);
  ASSERT_NE(sel, nullptr);
  ASSERT_EQ(sel->joints.size(), 1u);
  EXPECT_NEAR(sel->joints[0].qpos[0], qref[21][a.model.joints[a.model.bodies[3].joints[0]].qadr], 1e-4);
  const ArticulatedFrameInfo& info = articulated_last_frame_info();
  ASSERT_GE(info.contacts, 1);
  EXPECT_EQ(int(sel->contacts.size()), info.contacts);  // every contact of the frame is the box's
  for (const ArticulatedContactInfo& c : sel->contacts) {
    EXPECT_EQ(c.other, "plane obstacle");
    EXPECT_NEAR(c.point[2], -0.22, 0.01);
    EXPECT_NEAR(c.depth, c.magnitude / a.options.contact.stiffness, 1e-12);
    EXPECT_GT(c.depth, 0);
  }

  // Scrubbing keeps the selection and follows the frame.
  ASSERT_EQ(h.run("set_frame 30\nwait 3\n"), "");
  sel = articulated_selection(*h.app);
  ASSERT_NE(sel, nullptr);
  EXPECT_EQ(sel->frame, 30);
  EXPECT_NEAR(sel->joints[0].qpos[0], qref[30][a.model.joints[a.model.bodies[3].joints[0]].qadr], 1e-4);

  // Empty space (the viewport's bottom-left corner) clears; Esc clears too.
  ASSERT_EQ(h.run("click " + std::to_string(vp->x0 + 4) + " " + std::to_string(vp->y1 - 4) + "\nwait 2\n"), "");
  EXPECT_EQ(st.selected_body, 0);
  EXPECT_EQ(articulated_selection(*h.app), nullptr);
  ASSERT_TRUE(articulated_select_body(*h.app, 1));
  ASSERT_EQ(h.run("wait 2\nkey ESCAPE\nwait 2\n"), "");
  EXPECT_EQ(st.selected_body, 0);
  EXPECT_EQ(h.app->doc.history().size(), steps0);  // never a document edit
}
#endif

TEST(EditorArticulated, CompareIntegratorsReadsAnEnergyCurvePerIntegrator) {
  EditorHarness h("art_compare");
  fs::path scene = h.copy_scene("articulated_chain.json");
  h.start(scene, /*gl=*/false);
  // Untick rk4: three runs (pbad2, pbad3, euler).
  ASSERT_EQ(h.run("wait 2\nclick_item pick_rk4\nwait 2\nclick_item compare_integrators\nwait 2\n"), "");
  auto& st = h.app->kind_ui.get<ArticulatedUiState>("articulated");
  ASSERT_EQ(st.compare_error, "");
  ASSERT_EQ(st.runs.size(), 3u);
  EXPECT_EQ(h.app->jobs.size(), 3u);
  const auto t0 = std::chrono::steady_clock::now();
  while (!all_jobs_ended(*h.app) && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    ASSERT_EQ(h.run("wait 5\n"), "");
  ASSERT_TRUE(all_jobs_ended(*h.app));
  ASSERT_EQ(h.run("wait 3\n"), "");  // the jobs panel reads the last frames
  const char* names[] = {"pbad2", "pbad3", "euler"};
  for (size_t i = 0; i < 3; ++i) {
    const IntegratorRun& r = st.runs[i];
    EXPECT_EQ(r.integrator, names[i]);
    EXPECT_EQ(r.job->snapshot().state, JobState::Done) << r.job->snapshot().error;
    EXPECT_EQ(r.total.size(), 61u) << r.integrator;
    EXPECT_GE(r.drift_percent(), 0) << r.integrator;
    EXPECT_NE(h.app->marks.find("legend_" + r.integrator), nullptr);
    // The variant beside the take runs this integrator.
    std::ifstream in(r.take.string() + ".scene.json");
    EXPECT_EQ(json::parse(in)["integrator"], names[i]);
    TakeReader take(r.take);
    EXPECT_EQ(take.manifest().metrics["integrator"], names[i]);
  }
  EXPECT_NE(h.app->marks.find("energy_plot"), nullptr);
  // Same initial state, different schemes: equal first energy, different curves.
  EXPECT_FLOAT_EQ(st.runs[0].total.front(), st.runs[2].total.front());
  EXPECT_NE(st.runs[0].total[15], st.runs[2].total[15]);
  // A legend click shows that run's take; a selected body stays selected there
  // (by name) and is read from that take.
  ASSERT_EQ(h.run("click_item legend_pbad2\nwait 2\n"), "");
  ASSERT_TRUE(articulated_select_body(*h.app, 3));
  ASSERT_EQ(h.run("set_frame 40\nwait 2\n"), "");
  const ArticulatedSelection* sel = articulated_selection(*h.app);
  ASSERT_NE(sel, nullptr);
  EXPECT_EQ(sel->take_dir, st.runs[0].take.string());
  ASSERT_EQ(sel->joints.size(), 1u);
  const double q_pbad2 = sel->joints[0].qpos[0];
  ASSERT_EQ(h.run("click_item legend_euler\nwait 2\n"), "");
  EXPECT_EQ(h.app->take.dir(), st.runs[2].take);
  ASSERT_EQ(h.run("set_frame 40\nwait 2\n"), "");
  sel = articulated_selection(*h.app);
  ASSERT_NE(sel, nullptr);
  EXPECT_EQ(sel->body_name, "link3");
  EXPECT_EQ(sel->take_dir, st.runs[2].take.string());
  EXPECT_EQ(sel->frame, 40);
  ASSERT_EQ(sel->joints.size(), 1u);
  EXPECT_NE(sel->joints[0].qpos[0], q_pbad2);  // another scheme, another trajectory
  // A second comparison right away gets takes of its own.
  const fs::path first = st.runs[0].take;
  ASSERT_TRUE(articulated_compare_integrators(*h.app, {"pbad2"}));
  ASSERT_EQ(st.runs.size(), 1u);
  EXPECT_NE(st.runs[0].take, first);
  while (!all_jobs_ended(*h.app) && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    ASSERT_EQ(h.run("wait 5\n"), "");
}

TEST(EditorArticulated, HopperMpcFromAnEditedSceneSimulatesAndPlays) {
  EditorHarness h("art_hopper");
  fs::path scene = write_hopper_scene(h.dir);
  h.start(scene, /*gl=*/true, 1280, 720);
  // An unsaved edit: the job runs a copy beside its take, with the model path made absolute.
  h.app->doc.set("/mpc/seed", 2);
  ASSERT_TRUE(h.app->doc.dirty());
  ASSERT_EQ(h.run("wait 2\nclick_item Simulate\nwait_job 60\nexpect \": done\"\nwait_frames 31 10\n"
                  "click_item play_from_start\nwait 12\n"),
            "");
  EXPECT_EQ(h.app->take.status(), "done");
  EXPECT_TRUE(h.app->take.playing);
  EXPECT_GT(h.app->take.frame, 0);
  EXPECT_EQ(h.app->doc.scene()["model"], "hopper2d.xml");  // the document keeps its relative path
  TakeReader take(h.app->take.dir());
  EXPECT_TRUE(take.manifest().metrics.contains("distance_m"));
  const ArticulatedFrameInfo& info = articulated_last_frame_info();
  EXPECT_EQ(info.model_error, "");
  EXPECT_EQ(info.bodies, 4);
  EXPECT_EQ(info.geoms, 4);
  EXPECT_EQ(h.app->renderer.drawer_name(), "articulated");
}

TEST(EditorArticulated, DroppedModelFileBecomesTheModel) {
  EditorHarness h("art_drop");
  fs::path scene = h.copy_scene("articulated_chain.json");
  fs::create_directories(h.dir / "models");
  fs::copy_file(source_asset("models/hopper2d.xml"), h.dir / "models" / "hopper2d.xml");
  std::ofstream(h.dir / "models" / "broken.xml") << "<mujoco><worldbody><body><geom type=\"box\"/></body>";
  h.start(scene, /*gl=*/false);
  const json before = h.app->doc.scene()["model"];
  EXPECT_TRUE(articulated_on_drop(*h.app, (h.dir / "models" / "hopper2d.xml").string()));
  EXPECT_EQ(h.app->doc.scene()["model"], "models/hopper2d.xml");
  // The chain's initial qvel (4 values) does not fit the hopper (6): dropped with it.
  EXPECT_FALSE(h.app->doc.scene().contains("initial"));
  EXPECT_EQ(h.app->scene_error(), "");
  h.app->cmd_undo();
  EXPECT_EQ(h.app->doc.scene()["model"], before);
  EXPECT_TRUE(h.app->doc.scene().contains("initial"));
  // A broken model is refused with a message; the document is unchanged.
  EXPECT_TRUE(articulated_on_drop(*h.app, (h.dir / "models" / "broken.xml").string()));
  EXPECT_TRUE(h.app->status_is_error());
  EXPECT_EQ(h.app->doc.scene()["model"], before);
  // Scenes are not models: the App opens them itself.
  EXPECT_FALSE(articulated_on_drop(*h.app, scene.string()));
}

// A gym-style MJCF (geom solref / solimp in its defaults) is refused by the engine
// unless the scene sets mjcf.ignore_solver_params: a drop loads it with the key
// set and says so, the inspector's checkbox shows and clears it (the model summary
// then shows the engine's refusal), and one undo puts the old model back.
TEST(EditorArticulated, DroppedGymStyleMjcfLoadsIgnoringItsSolverParameters) {
  EditorHarness h("art_drop_solref");
  fs::path scene = h.copy_scene("articulated_chain.json");
  std::ofstream(h.dir / "gym_pendulum.xml")
      << "<mujoco><default><geom solref=\"0.02 1\" solimp=\"0.9 0.95 0.001\"/></default>"
         "<worldbody><body name=\"b\" pos=\"0 0 1\"><joint name=\"h\" type=\"hinge\" axis=\"0 1 0\"/>"
         "<geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.5\" size=\"0.05\"/></body></worldbody></mujoco>";
  h.start(scene, /*gl=*/false, 1280, 1600);
  ASSERT_EQ(h.run("wait 1\n"), "");
  EXPECT_EQ(h.app->marks.find("/mjcf/ignore_solver_params"), nullptr);  // inline chain: no MJCF switch
  const json before = h.app->doc.scene()["model"];
  const size_t steps = h.app->doc.history().size();
  ASSERT_TRUE(articulated_on_drop(*h.app, (h.dir / "gym_pendulum.xml").string()));
  EXPECT_FALSE(h.app->status_is_error());
  EXPECT_NE(h.app->status().find("ignoring its MuJoCo solver parameters"), std::string::npos) << h.app->status();
  EXPECT_EQ(h.app->doc.scene()["model"], "gym_pendulum.xml");
  EXPECT_EQ(h.app->doc.scene()["mjcf"]["ignore_solver_params"], true);
  EXPECT_EQ(h.app->scene_error(), "");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  ASSERT_EQ(h.run("wait 2\n"), "");
  ASSERT_NE(h.app->marks.find("/mjcf/ignore_solver_params"), nullptr);
  EXPECT_NE(h.app->kind_ui.get<ArticulatedUiState>("articulated").summary.find("2 MuJoCo solver parameters ignored"), std::string::npos)
      << h.app->kind_ui.get<ArticulatedUiState>("articulated").summary;
  // Unticked, the engine refuses the model again, naming the attribute and the key.
  ASSERT_EQ(h.run("click_item /mjcf/ignore_solver_params\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene()["mjcf"]["ignore_solver_params"], false);
  const std::string& refused = h.app->kind_ui.get<ArticulatedUiState>("articulated").summary;
  EXPECT_NE(refused.find("solref"), std::string::npos) << refused;
  EXPECT_NE(refused.find("ignore_solver_params"), std::string::npos) << refused;
  h.app->cmd_undo();
  h.app->cmd_undo();
  EXPECT_EQ(h.app->doc.scene()["model"], before);
  EXPECT_FALSE(h.app->doc.scene().contains("mjcf"));
}

#ifdef PLIANT_HAVE_ARTICULATED
// An MJCF mesh geom's mass: the "mesh inertia" combo of an MJCF model switches
// /mjcf/mesh_inertia from the enclosed solid's (an L prism of volume 3/512 m^3: 5.86
// kg) to libmujoco 2.2.2's rule (sqrt(35/3)/512 m^3: 6.67 kg) in one undo step, and the
// model summary's total mass follows.
TEST(EditorArticulated, MeshInertiaComboSwitchesToMuJoCosMeshMass) {
  EditorHarness h("art_mesh_inertia");
  fs::path scene = h.copy_scene("articulated_chain.json");
  {
    std::ofstream obj(h.dir / "L.obj");
    const int p[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    for (int z : {0, 1})
      for (const auto& v : p) obj << "v " << v[0] << " " << v[1] << " " << z << "\n";
    const int cap[4][3] = {{3, 4, 5}, {3, 5, 0}, {3, 0, 1}, {3, 1, 2}};
    for (const auto& t : cap) obj << "f " << t[0] + 1 << " " << t[2] + 1 << " " << t[1] + 1 << "\nf " << t[0] + 7 << " "
                                  << t[1] + 7 << " " << t[2] + 7 << "\n";
    for (int i = 0; i < 6; ++i) {
      const int j = (i + 1) % 6;
      obj << "f " << i + 1 << " " << j + 1 << " " << j + 7 << "\nf " << i + 1 << " " << j + 7 << " " << i + 7 << "\n";
    }
  }
  std::ofstream(h.dir / "l.xml") << "<mujoco><asset><mesh file=\"L.obj\" scale=\"0.125 0.125 0.125\"/></asset>"
                                    "<worldbody><body name=\"l\" pos=\"0 0 1\"><freejoint/>"
                                    "<geom type=\"mesh\" mesh=\"L\"/></body></worldbody></mujoco>";
  h.start(scene, /*gl=*/false, 1280, 1600);
  ASSERT_EQ(h.run("wait 1\n"), "");
  EXPECT_EQ(h.app->marks.find("/mjcf/mesh_inertia"), nullptr);  // inline chain: no MJCF keys
  ASSERT_TRUE(articulated_on_drop(*h.app, (h.dir / "l.xml").string()));
  ASSERT_EQ(h.run("wait 2\n"), "");
  const auto summary = [&] { return h.app->kind_ui.get<ArticulatedUiState>("articulated").summary; };
  EXPECT_NE(summary().find("5.86 kg"), std::string::npos) << summary();
  ASSERT_NE(h.app->marks.find("/mjcf/mesh_inertia"), nullptr);
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item /mjcf/mesh_inertia\nwait 1\nclick_item /mjcf/mesh_inertia=mujoco-2.2.2\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene()["mjcf"]["mesh_inertia"], "mujoco-2.2.2");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  EXPECT_NE(summary().find("6.67 kg"), std::string::npos) << summary();
  h.app->cmd_undo();
  ASSERT_EQ(h.run("wait 2\n"), "");
  EXPECT_NE(summary().find("5.86 kg"), std::string::npos) << summary();
}

// Cylinders and ellipsoids against planes: the "curved contact" combo switches
// /mjcf/curved_contact from the exact surface (a cylinder's two rims' support points
// and its two cap rings of kCapRingPoints) to the tessellation alone, in one undo step;
// the summary's contact point count follows.
TEST(EditorArticulated, CurvedContactComboSwitchesCylindersToTheirTessellation) {
  EditorHarness h("art_curved_contact");
  fs::path scene = h.copy_scene("articulated_chain.json");
  std::ofstream(h.dir / "c.xml") << "<mujoco><worldbody><geom type=\"plane\"/><body name=\"c\" pos=\"0 0 1\">"
                                    "<freejoint/><geom type=\"cylinder\" size=\"0.05 0.1\"/></body></worldbody></mujoco>";
  h.start(scene, /*gl=*/false, 1280, 1600);
  ASSERT_EQ(h.run("wait 1\n"), "");
  ASSERT_TRUE(articulated_on_drop(*h.app, (h.dir / "c.xml").string()));
  ASSERT_EQ(h.run("wait 2\n"), "");
  const auto points = [&] {
    const std::string s = h.app->kind_ui.get<ArticulatedUiState>("articulated").summary;
    const size_t at = s.find(" contact points");
    EXPECT_NE(at, std::string::npos) << s;
    return at == std::string::npos ? -1 : std::stoi(s.substr(s.rfind(' ', at - 1) + 1));
  };
  const int exact = points();
  ASSERT_NE(h.app->marks.find("/mjcf/curved_contact"), nullptr);
  const size_t steps = h.app->doc.history().size();
  ASSERT_EQ(h.run("click_item /mjcf/curved_contact\nwait 1\nclick_item /mjcf/curved_contact=tessellated\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene()["mjcf"]["curved_contact"], "tessellated");
  EXPECT_EQ(h.app->doc.history().size(), steps + 1);
  EXPECT_EQ(exact - points(), 2 + 2 * articulated::kCapRingPoints);
  h.app->cmd_undo();
  ASSERT_EQ(h.run("wait 2\n"), "");
  EXPECT_EQ(points(), exact);
}

// With no take the viewport shows the model at its initial state (the record a run
// writes as frame 0, energies the engine's); an edit of the initial pose redraws it;
// Simulate's take replaces it.
TEST(EditorArticulated, SceneWithNoTakeShowsItsInitialState) {
  EditorHarness h("art_initial");
  fs::path scene = h.copy_scene("articulated_chain.json");
  h.start(scene, /*gl=*/true, 960, 540);
  ASSERT_EQ(h.run("wait 2\nscreenshot $TMP/initial.png viewport\n"), "");
  EXPECT_TRUE(h.app->take.dir().empty());
  ASSERT_TRUE(h.app->renderer.has_frame());
  EXPECT_EQ(h.app->renderer.drawer_name(), "articulated");
  const ArticulatedFrameInfo& info = articulated_last_frame_info();
  EXPECT_EQ(info.model_error, "");
  EXPECT_EQ(info.bodies, 3);
  Scene sc;
  sc.file = "scene";
  sc.dir = scene.parent_path();
  sc.kind = "articulated";
  sc.doc = h.app->doc.scene();
  const articulated::ArticulatedScene a = articulated::articulated_compile(sc);
  articulated::SimWorkspace ws;
  const articulated::Energy e = articulated::state_energy(a.model, a.options, a.initial, ws);
  EXPECT_GT(e.kinetic, 1e-3);  // qvel 1.5 rad/s about link1's z hinge
  EXPECT_NEAR(info.energy[0], e.kinetic, 1e-5);
  EXPECT_NEAR(info.energy[1], e.potential, 1e-5);
  const float potential0 = info.energy[1];

  // Raise the chain (first hinge -0.5 rad about y): the drawn pose and its
  // potential energy follow.
  json doc = h.app->doc.scene();
  doc["initial"]["qpos"] = {-0.5, 0, 0, 0};
  h.app->doc.edit("tilt", doc);
  ASSERT_EQ(h.run("wait 2\nscreenshot $TMP/tilted.png viewport\n"), "");
  EXPECT_GT(info.energy[1], potential0 + 1e-3);
  std::string err;
  const Image before = read_png((h.dir / "initial.png").string(), &err);
  const Image after = read_png((h.dir / "tilted.png").string(), &err);
  ASSERT_FALSE(before.empty() || after.empty()) << err;
  ASSERT_EQ(before.width, after.width);
  int changed = 0;
  for (int y = 0; y < before.height; ++y)
    for (int x = 0; x < before.width; ++x)
      changed += std::abs(int(before.pixel(x, y)[0]) - int(after.pixel(x, y)[0])) > 30;
  EXPECT_GT(changed, 100);

  // A finished Simulate shows its take instead.
  ASSERT_EQ(h.run("click_item Simulate\nwait_job 60\nexpect \": done\"\nwait_frames 61 10\nset_frame 30\nwait 3\n"), "");
  EXPECT_FALSE(h.app->take.dir().empty());
  EXPECT_EQ(h.app->take.frame, 30);
  TakeReader take(h.app->take.dir());
  EXPECT_NEAR(info.energy[2], take.read_frame_at(30).find("energy")->data[2], 1e-5);
}
#endif

}  // namespace pliant::editor::test
