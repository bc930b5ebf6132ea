// Document edits through the UI (mock platform: ImGui runs, no pixels):
// undo/redo of an inspector drag, save + reopen, crash recovery, bad drops.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "doc/autosave.h"
#include "editor_harness.h"
#include "pliant/core/scene.h"

namespace pliant::editor::test {

using nlohmann::json;

TEST(EditorUi, InspectorDragIsOneUndoStepAndCtrlZRestoresExactJson) {
  EditorHarness h("undo");
  fs::path scene = h.copy_scene("small_plume.json");
  h.start(scene, /*gl=*/false);
  const json original = h.app->doc.scene();
  ASSERT_EQ(h.run("wait 2\ndrag_item /buoyancy_m_per_s2 60 0 12\nwait 2\n"), "");
  const json edited = h.app->doc.scene();
  ASSERT_NE(edited, original);
  EXPECT_GT(edited["buoyancy_m_per_s2"].get<double>(), 2.0);  // dragged right: larger
  EXPECT_EQ(h.app->doc.history().size(), 1u) << "a drag must merge into one undo step";
  EXPECT_TRUE(h.app->doc.dirty());
  // Everything but the dragged value is untouched.
  json a = edited, b = original;
  a.erase("buoyancy_m_per_s2");
  b.erase("buoyancy_m_per_s2");
  EXPECT_EQ(a, b);

  ASSERT_EQ(h.run("key CTRL+Z\nwait 1\n"), "");
  EXPECT_EQ(h.app->doc.scene(), original);
  EXPECT_FALSE(h.app->doc.dirty());
  ASSERT_EQ(h.run("key CTRL+SHIFT+Z\nwait 1\n"), "");
  EXPECT_EQ(h.app->doc.scene(), edited);
  ASSERT_EQ(h.run("key CTRL+Z\nwait 1\nkey CTRL+Y\nwait 1\n"), "");
  EXPECT_EQ(h.app->doc.scene(), edited);
  // The Edit menu's Undo does the same.
  ASSERT_EQ(h.run("click_item Edit\nwait 2\nclick_item Undo\nwait 1\n"), "");
  EXPECT_EQ(h.app->doc.scene(), original);
}

TEST(EditorUi, SaveAsAndReopenGiveIdenticalJson) {
  EditorHarness h("save");
  fs::path scene = h.copy_scene("small_plume.json");
  h.start(scene, false);
  fs::path saved = h.dir / "saved.json";
  ASSERT_EQ(h.run("wait 2\n"
                  "drag_item /time/dt_s 30 0 6\n"
                  "drag_item /grid/cell_size_m 25 0 6\n"
                  "click_item \"Add source\"\n"
                  "wait 2\n"),
            "");
  const json edited = h.app->doc.scene();
  ASSERT_EQ(edited["sources"].size(), 2u);
  ASSERT_EQ(h.run("key CTRL+SHIFT+S\nwait 3\nkey CTRL+A\ntype $TMP/saved.json\nkey ENTER\nwait 2\n"
                  "expect Saved\n"),
            "");
  ASSERT_TRUE(fs::exists(saved));
  EXPECT_FALSE(h.app->doc.dirty());
  EXPECT_EQ(h.app->doc.path(), saved);
  // Reopen: first something else, then the saved file through Ctrl+O.
  h.app->cmd_open(scene);
  ASSERT_NE(h.app->doc.scene(), edited);
  ASSERT_EQ(h.run("key CTRL+O\nwait 3\ntype $TMP/saved.json\nkey ENTER\nwait 2\nexpect Opened\n"), "");
  EXPECT_EQ(h.app->doc.path(), saved);
  EXPECT_EQ(h.app->doc.scene(), edited);
  EXPECT_EQ(load_scene(saved).doc, edited);
  // The saved file went into the recent list.
  ASSERT_FALSE(h.app->recent.items().empty());
  EXPECT_EQ(h.app->recent.items().front(), saved.string());
}

int reaped_child_pid() {
  pid_t p = ::fork();
  if (p == 0) ::_exit(0);
  int st;
  ::waitpid(p, &st, 0);
  return p;
}

// A crashed session leaves its lock (dead pid) and an autosave newer than the file.
void fake_crashed_session(const fs::path& cfg, const fs::path& scene, const json& unsaved) {
  int pid = reaped_child_pid();
  fs::create_directories(cfg / "sessions");
  fs::create_directories(cfg / "autosave");
  fs::last_write_time(scene, fs::file_time_type::clock::now() - std::chrono::hours(1));
  std::ofstream(cfg / "sessions" / (std::to_string(pid) + ".lock")) << pid << "\n";
  save_json_atomic(cfg / "autosave" / (std::to_string(pid) + ".json"),
                   json{{"file", scene.string()}, {"scene", unsaved}, {"saved_unix_s", 0}});
}

TEST(EditorUi, RecoveryPromptRecoverRestoresTheUnsavedEdit) {
  EditorHarness h("recover");
  fs::path scene = h.copy_scene("small_plume.json");
  json unsaved = load_scene(scene).doc;
  unsaved["buoyancy_m_per_s2"] = 3.25;
  unsaved["name"] = "edited before the crash";
  fake_crashed_session(h.dir / "config", scene, unsaved);
  h.start(scene, false);
  ASSERT_TRUE(h.app->recovery.has_value());
  EXPECT_EQ(h.app->doc.scene()["buoyancy_m_per_s2"], 2.0);
  ASSERT_EQ(h.run("wait 2\nclick_item recovery_prompt\nclick_item Recover\nwait 2\n"
                  "expect_json /buoyancy_m_per_s2 3.25\nexpect Recovered\n"),
            "");
  EXPECT_EQ(h.app->doc.scene(), unsaved);
  EXPECT_EQ(h.app->doc.path(), scene);
  EXPECT_TRUE(h.app->doc.dirty());  // recovered work is not on disk yet
  EXPECT_FALSE(h.app->recovery.has_value());
  // The dead session's files are gone: no second prompt next time.
  Autosave probe(h.dir / "config", 30);
  EXPECT_FALSE(probe.find_recovery().has_value());
}

TEST(EditorUi, RecoveryPromptDiscardKeepsTheFile) {
  EditorHarness h("discard");
  fs::path scene = h.copy_scene("small_plume.json");
  json unsaved = load_scene(scene).doc;
  unsaved["buoyancy_m_per_s2"] = 7.0;
  fake_crashed_session(h.dir / "config", scene, unsaved);
  h.start(scene, false);
  ASSERT_TRUE(h.app->recovery.has_value());
  ASSERT_EQ(h.run("wait 2\nclick_item Discard\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.scene(), load_scene(scene).doc);
  EXPECT_FALSE(h.app->doc.dirty());
  Autosave probe(h.dir / "config", 30);
  EXPECT_FALSE(probe.find_recovery().has_value());
}

TEST(EditorUi, AutosaveWritesTheDirtyDocumentAndCleanExitRemovesIt) {
  EditorHarness h("autosave_app");
  fs::path scene = h.copy_scene("small_plume.json");
  h.start(scene, false, 1280, 720, /*autosave_s=*/0.05);
  fs::path as = h.dir / "config" / "autosave" / (std::to_string(::getpid()) + ".json");
  fs::path lock = h.dir / "config" / "sessions" / (std::to_string(::getpid()) + ".lock");
  EXPECT_TRUE(fs::exists(lock));
  ASSERT_EQ(h.run("wait 2\ndrag_item /buoyancy_m_per_s2 40 0 6\nwait 2\n"), "");
  // Frames are fast: give the 0.05 s interval real time to pass.
  for (int i = 0; i < 50 && !fs::exists(as); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    h.app->frame();
  }
  ASSERT_TRUE(fs::exists(as));
  std::ifstream in(as);
  json j = json::parse(in);
  EXPECT_EQ(j["scene"], h.app->doc.scene());
  h.app->shutdown(true);
  EXPECT_FALSE(fs::exists(as));
  EXPECT_FALSE(fs::exists(lock));
}

TEST(EditorUi, DroppedInvalidSceneShowsTheErrorAndKeepsTheDocument) {
  EditorHarness h("drop");
  fs::path scene = h.copy_scene("small_plume.json");
  h.start(scene, false);
  ASSERT_EQ(h.run("wait 2\ndrag_item /buoyancy_m_per_s2 30 0 6\nwait 1\n"), "");
  const json before = h.app->doc.scene();
  std::ofstream(h.dir / "broken.json") << "{\n  \"pliant\": 1,\n  \"kind\": \"smoke\",\n  oops\n}\n";
  std::ofstream(h.dir / "wrong_kind.json") << R"({"pliant": 1, "kind": "teapot", "name": "x"})";
  ASSERT_EQ(h.run("drop $TMP/broken.json\nwait 2\nexpect broken.json\nexpect \"cannot open scene\"\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  EXPECT_EQ(h.app->doc.path(), scene);
  EXPECT_TRUE(h.app->doc.dirty());
  EXPECT_NE(h.app->status().find("broken.json"), std::string::npos) << h.app->status();
  EXPECT_TRUE(h.app->status_is_error());
  ASSERT_EQ(h.run("drop $TMP/wrong_kind.json\nwait 2\nexpect wrong_kind.json\n"), "");
  EXPECT_EQ(h.app->doc.scene(), before);
  // A valid scene dropped afterwards does open.
  fs::path other = h.dir / "other.json";
  json o = before;
  o["name"] = "other";
  save_json_atomic(other, o);
  ASSERT_EQ(h.run("drop $TMP/other.json\nwait 2\n"), "");
  EXPECT_EQ(h.app->doc.path(), other);
  EXPECT_EQ(h.app->doc.scene()["name"], "other");
}

TEST(EditorUi, ViewportMouseMovesTheCameraAndResetViewRestoresIt) {
  EditorHarness h("camera");
  h.start(h.copy_scene("small_plume.json"), false);
  ASSERT_EQ(h.run("wait 2\n"), "");
  ASSERT_NE(h.app->marks.find("viewport"), nullptr);
  const UiRect vr = *h.app->marks.find("viewport");  // a copy: marks change every frame
  const UiRect* v = &vr;
  const OrbitCamera home = h.app->viewport.camera;
  std::string cx = std::to_string(static_cast<int>(v->cx())), cy = std::to_string(static_cast<int>(v->cy()));
  ASSERT_EQ(h.run("move " + cx + " " + cy + "\nwait 1\nscroll 2\nwait 1\n"), "");
  EXPECT_NE(h.app->viewport.camera.zoom2d, home.zoom2d);
  EXPECT_NE(h.app->viewport.camera.distance, home.distance);
  // Right-drag pans, left-drag orbits.
  std::string x1 = std::to_string(static_cast<int>(v->cx()) + 80);
  OrbitCamera before_pan = h.app->viewport.camera;
  ASSERT_EQ(h.run("drag " + cx + " " + cy + " " + x1 + " " + cy + " 8 right\nwait 1\n"), "");
  EXPECT_NE(h.app->viewport.camera.pan2d, before_pan.pan2d);
  EXPECT_EQ(h.app->viewport.camera.yaw_deg, home.yaw_deg);
  ASSERT_EQ(h.run("drag " + cx + " " + cy + " " + x1 + " " + cy + " 8\nwait 1\n"), "");
  EXPECT_NE(h.app->viewport.camera.yaw_deg, home.yaw_deg);
  ASSERT_EQ(h.run("click_item \"Reset view\"\nwait 1\n"), "");
  EXPECT_EQ(h.app->viewport.camera.zoom2d, home.zoom2d);
  EXPECT_EQ(h.app->viewport.camera.pan2d, home.pan2d);
  EXPECT_EQ(h.app->viewport.camera.yaw_deg, home.yaw_deg);
  // Camera moves are view state, not document edits.
  EXPECT_FALSE(h.app->doc.history().can_undo());
}

TEST(EditorUi, FailedJobShowsItsMessageInTheStatusAndLog) {
  EditorHarness h("failjob");
  // A stand-in for `pliant run` that fails the way the protocol says.
  h.pliant = h.dir / "fake-pliant";
  std::ofstream(h.pliant) << "#!/bin/sh\n"
                             "echo '{\"event\":\"start\",\"kind\":\"smoke\",\"take\":\"t\",\"frames\":3}'\n"
                             "echo '{\"event\":\"log\",\"level\":\"warning\",\"message\":\"args: '\"$*\"'\"}'\n"
                             "echo '{\"event\":\"error\",\"message\":\"s.json: /grid: boom\"}'\n"
                             "exit 2\n";
  fs::permissions(h.pliant, fs::perms::owner_all);
  h.start(h.copy_scene("small_plume.json"), false);
  ASSERT_EQ(h.run("wait 2\nclick_item Run\nwait_job 20\nexpect \"Job 1: failed: s.json: /grid: boom\"\n"), "");
  JobStatus st = h.app->newest_job()->snapshot();
  EXPECT_EQ(st.state, JobState::Failed);
  EXPECT_EQ(st.exit_code, 2);
  EXPECT_TRUE(h.app->status_is_error());
  // The job got `run SCENE --take DIR --threads 1`.
  bool saw_args = false;
  for (const auto& l : h.app->log.lines())
    if (l.level == LogLevel::Warning && l.message.find("args: run ") == 0 &&
        l.message.find(" --take ") != std::string::npos &&
        l.message.find(" --threads 1") != std::string::npos)
      saw_args = true;
  EXPECT_TRUE(saw_args);
}

TEST(EditorUi, ScriptErrorsNameTheLineAndItem) {
  EditorHarness h("script_err");
  fs::path scene = h.copy_scene("small_plume.json");
  h.start(scene, false);
  std::string err = h.run("wait 1\nclick_item NoSuchButton\n", "missing.txt");
  EXPECT_NE(err.find("missing.txt:2: click_item: no item 'NoSuchButton'"), std::string::npos) << err;
  err = h.run("wait 1\n\nexpect_json /buoyancy_m_per_s2 99\n", "json.txt");
  EXPECT_NE(err.find("json.txt:3: expect_json: /buoyancy_m_per_s2 is 2.0, expected 99"), std::string::npos)
      << err;
  err = h.run("key CTRL+NOPE\n", "key.txt");
  EXPECT_NE(err.find("key.txt:1: key: unknown key"), std::string::npos) << err;
}

// Every shipped scene opens in the editor (EGL, its kind's inspector, viewport and
// timeline drawn for a few frames) with no scene error and no error in the status
// line, and opening it changes nothing on disk.
TEST(EditorUi, EveryShippedSceneOpensWithoutAnError) {
  EditorHarness h("all_scenes");
  const fs::path scenes = fs::absolute(test_data("../../assets/scenes")).lexically_normal();
  h.start(scenes / "plume_2d.json", /*gl=*/true);
  int opened = 0;
  for (const auto& e : fs::directory_iterator(scenes)) {
    if (e.path().extension() != ".json") continue;
    const auto before = fs::last_write_time(e.path());
    ASSERT_TRUE(h.app->cmd_open(e.path())) << e.path();
    ASSERT_EQ(h.run("wait 3\n"), "") << e.path();
    EXPECT_EQ(h.app->scene_error(), "") << e.path();
    EXPECT_FALSE(h.app->status_is_error()) << e.path() << ": " << h.app->status();
    EXPECT_FALSE(h.app->doc.dirty()) << e.path();
    EXPECT_EQ(fs::last_write_time(e.path()), before) << e.path();
    ++opened;
  }
  EXPECT_GE(opened, 30);
}

// The File menu offers the imports and exports of the open scene's kind only: a
// smoke scene its keyframe image and OpenVDB, a liquid its particles, a soft body its
// OBJ sequence, and the CSV table (small per-frame fields) every kind but smoke.
TEST(EditorUi, FileMenuOffersTheImportsAndExportsOfTheScenesKind) {
  EditorHarness h("file_menu");
  const fs::path scenes = fs::absolute(test_data("../../assets/scenes")).lexically_normal();
  h.start(scenes / "plume_2d.json", /*gl=*/true);
  const std::vector<std::string> items = {"Import Image", "Export VDB", "Export Particles", "Export OBJ",
                                          "Export CSV"};
  const std::vector<std::pair<std::string, std::vector<bool>>> cases = {
      {"plume_2d.json", {true, true, false, false, false}},
      {"liquid_pour_2d.json", {false, false, true, false, true}},
      {"soft_ball_roll.json", {false, false, false, true, true}},
      {"chain_swing.json", {false, false, false, false, true}}};
  for (const auto& [scene, shown] : cases) {
    ASSERT_TRUE(h.app->cmd_open(scenes / scene)) << scene;
    ASSERT_EQ(h.run("wait 2\nclick_item File\nwait 3\n"), "") << scene;
    ASSERT_NE(h.app->marks.find("Export PNG"), nullptr) << scene << ": the File menu is not open";
    for (size_t i = 0; i < items.size(); ++i)
      EXPECT_EQ(h.app->marks.find(items[i]) != nullptr, shown[i]) << scene << ": " << items[i];
    ASSERT_EQ(h.run("click_item File\nwait 2\n"), "") << scene;  // closes it
  }
}

// A keyframe scene opens on its keyframes (no result to show yet), a plain one on
// the result; running the scene switches to the result to watch the run.
TEST(EditorUi, KeyframeSceneOpensOnItsKeyframesAndARunShowsTheResult) {
  EditorHarness h("open_keyframes");
  h.start(h.copy_scene("small_plume.json"), /*gl=*/true);
  EXPECT_FALSE(h.app->viewport.show_canvas);
  // The canvas test scene with one keyframe (a square at frame 20), 2 ADMM iterations.
  json scene = json::parse(std::ifstream(h.copy_scene("keyframe_32.json")));
  scene["control"]["max_iterations"] = 2;
  scene["control"]["keyframes"] = json::array(
      {{{"frame", 20}, {"target", {{"type", "square"}, {"center", {0.6, 0.6}}, {"half_size", {0.13, 0.13}}}}}});
  const fs::path path = h.dir / "one_key.json";
  std::ofstream(path) << scene.dump(2);
  ASSERT_TRUE(h.app->cmd_open(path));
  ASSERT_EQ(h.run("wait 2\n"), "");
  EXPECT_TRUE(h.app->viewport.show_canvas);
  ASSERT_NE(h.app->marks.find("keyframe_canvas"), nullptr);
  ASSERT_EQ(h.run("key F5\nwait 2\n"), "");
  EXPECT_FALSE(h.app->viewport.show_canvas) << h.app->status();
  ASSERT_EQ(h.run("wait_job 60\nclick_item view_keyframes\nwait 2\n"), "");  // and back, by hand
  EXPECT_TRUE(h.app->viewport.show_canvas);
  ASSERT_TRUE(h.app->cmd_open(h.copy_scene("small_plume.json")));
  EXPECT_FALSE(h.app->viewport.show_canvas);
}

}  // namespace pliant::editor::test
