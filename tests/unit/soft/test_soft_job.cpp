// Job kind "soft": frames carry vertices / triangles (frame 0) / com; a checkpoint
// per optimizer iteration; --resume continues the objective history.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;

namespace {
const char* kScene = R"({"pliant": 1, "kind": "soft",
  "character": {"mesh": "worm.obj", "resolution": 6, "modes": 4},
  "environment": {"type": "ground", "friction": 0.6},
  "simulation": {"dt_s": 0.04, "frames": 5},
  "controller": {"modes": 2, "kernels": 2, "period_s": 0.4},
  "objectives": {"velocity": {"target_m_per_s": [0.1, 0, 0], "weight": 10}},
  "optimizer": {"method": "lm", "iterations": ITER, "horizon_frames": 6}})";

Scene scene_with(int iterations, const std::string& method = "lm") {
  std::string t = kScene;
  t.replace(t.find("ITER"), 4, std::to_string(iterations));
  t.replace(t.find("\"lm\""), 4, "\"" + method + "\"");
  return parse_scene(t, "job.json", std::string(PLIANT_ASSETS_DIR) + "/characters");
}

struct TempDir {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("pliant_soft_job_" + std::to_string(::getpid()) + "_" + std::to_string(rand()));
  ~TempDir() { std::filesystem::remove_all(dir); }
};

nlohmann::json run(const Scene& scene, TakeWriter& take, bool resume) {
  Progress progress;
  std::FILE* null_out = std::fopen("/dev/null", "w");
  JobEvents events(null_out);
  JobContext ctx{scene, take, progress, events, 1, resume};
  nlohmann::json m = soft::soft_run_job(ctx);
  take.finish("done");
  std::fclose(null_out);
  return m;
}
}  // namespace

TEST(SoftJob, FramesCheckpointsAndResume) {
  TempDir tmp;
  {
    const Scene scene = scene_with(2);
    EXPECT_EQ(soft::soft_job_frames(scene), 5);
    const nlohmann::json summary = soft::soft_summary(scene);
    EXPECT_EQ(summary["frames"], 5);
    TakeWriter take = TakeWriter::create(tmp.dir / "take", Manifest{});
    const nlohmann::json m = run(scene, take, false);
    EXPECT_EQ(m["iterations"], 2);
    const auto hist = m["objective_history"].get<std::vector<double>>();
    ASSERT_EQ(hist.size(), 3u);
    for (size_t i = 1; i < hist.size(); ++i) EXPECT_LE(hist[i], hist[i - 1]);
    TakeReader reader(tmp.dir / "take");
    ASSERT_EQ(reader.frame_count(), 5u);
    const Record f0 = reader.read_frame_at(0), f4 = reader.read_frame_at(4);
    ASSERT_TRUE(f0.find("vertices") && f0.find("triangles") && f0.find("com"));
    EXPECT_EQ(f0.find("vertices")->shape[1], 3u);
    EXPECT_EQ(f0.find("triangles")->shape[1], 3u);
    EXPECT_EQ(f4.find("triangles"), nullptr);
    EXPECT_EQ(f4.find("vertices")->shape, f0.find("vertices")->shape);
    EXPECT_EQ(f4.find("com")->shape, (std::vector<uint32_t>{3}));
    Record ck;
    ASSERT_TRUE(reader.latest(RecordKind::Checkpoint, &ck));
    EXPECT_EQ(ck.index, 2);
  }
  {
    // Resume with a larger budget: continues at iteration 2, keeps the history.
    const Scene scene = scene_with(3);
    TakeWriter take = TakeWriter::reopen(tmp.dir / "take");
    const nlohmann::json m = run(scene, take, true);
    EXPECT_EQ(m["iterations"], 3);
    EXPECT_EQ(m["objective_history"].size(), 4u);
  }
}

TEST(SoftJob, BadSceneFieldsAreInputErrors) {
  auto pointer_of = [](const std::string& text) {
    try {
      soft::soft_compile(parse_scene(text, "bad.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
    } catch (const InputError& e) {
      return e.pointer();
    }
    return std::string("no error");
  };
  EXPECT_EQ(pointer_of(R"({"pliant":1,"kind":"soft"})"), "/character");
  EXPECT_EQ(pointer_of(R"({"pliant":1,"kind":"soft","character":{"mesh":"worm.obj","resolutoin":4}})"),
            "/character/resolutoin");
  EXPECT_EQ(pointer_of(R"({"pliant":1,"kind":"soft","character":{"mesh":"worm.obj","resolution":1}})"),
            "/character/resolution");
  EXPECT_EQ(pointer_of(R"({"pliant":1,"kind":"soft","character":{"mesh":"worm.obj"},"environment":{"type":"lava"}})"),
            "/environment/type");
}

// "method": "spacetime" runs spacetime_optimize: one checkpoint per iteration, its
// per-iteration blocks in the metrics, physics violation of accepted points ~ 0
// (feasibility projection), and the history is the re-simulated objective.
TEST(SoftJob, SpacetimeMethodReportsItsTerms) {
  TempDir tmp;
  const Scene scene = scene_with(2, "spacetime");
  TakeWriter take = TakeWriter::create(tmp.dir / "take", Manifest{});
  const nlohmann::json m = run(scene, take, false);
  EXPECT_EQ(m["optimizer"], "spacetime");
  EXPECT_EQ(m["iterations"], 2);
  const auto hist = m["objective_history"].get<std::vector<double>>();
  ASSERT_EQ(hist.size(), 3u);
  for (size_t i = 1; i < hist.size(); ++i) EXPECT_LE(hist[i], hist[i - 1]);
  const auto& st = m["spacetime"];
  ASSERT_EQ(st["physics_violation_m"].size(), 3u);
  for (double v : st["physics_violation_m"]) EXPECT_LT(v, 1e-9);
  EXPECT_EQ(st["dmp_weight"].size(), 3u);
  const auto resim = st["resimulated_objective"].get<std::vector<double>>();
  EXPECT_DOUBLE_EQ(*std::min_element(resim.begin(), resim.end()), hist.back());
  TakeReader reader(tmp.dir / "take");
  Record ck;
  ASSERT_TRUE(reader.latest(RecordKind::Checkpoint, &ck));
  EXPECT_EQ(ck.index, 2);
}

// A spacetime run resumes from its checkpoint's theta (in full precision: the
// history so far is kept bit for bit) and finishes the iteration budget.
TEST(SoftJob, SpacetimeResumesFromItsCheckpoint) {
  TempDir tmp;
  nlohmann::json first;
  {
    TakeWriter take = TakeWriter::create(tmp.dir / "take", Manifest{});
    first = run(scene_with(1, "spacetime"), take, false);
  }
  TakeWriter take = TakeWriter::reopen(tmp.dir / "take");
  const nlohmann::json m = run(scene_with(2, "spacetime"), take, true);
  EXPECT_EQ(m["iterations"], 2);
  const auto h0 = first["objective_history"].get<std::vector<double>>();
  const auto h = m["objective_history"].get<std::vector<double>>();
  ASSERT_EQ(h.size(), 3u);
  EXPECT_EQ(h[0], h0[0]);
  EXPECT_EQ(h[1], h0[1]);
  EXPECT_LE(h[2], h[1]);
}

// "basis": "rotation_strain" switches the character's map (a rotation of the first
// mode's coordinate keeps the volume, unlike linear modes); "course" sets its term.
TEST(SoftJob, SceneSelectsRotationStrainBasisAndCourseTerm) {
  std::string t = kScene;
  t.replace(t.find("ITER"), 4, "0");
  t.replace(t.find("\"modes\": 4}"), 11, "\"modes\": 4, \"basis\": \"rotation_strain\"}");
  t.replace(t.find("\"weight\": 10}}"), 14,
            "\"weight\": 10}, \"course\": {\"direction\": [0, 0, 2], \"weight\": 3}}");
  const soft::SoftModel m =
      soft::soft_compile(parse_scene(t, "rs.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
  EXPECT_NE(m.character.rotation_strain, nullptr);
  EXPECT_DOUBLE_EQ(m.problem.obj.w_course, 3.0);
  EXPECT_NEAR(m.problem.obj.course_direction.z(), 1.0, 1e-12);
  const soft::SoftModel lin = soft::soft_compile(scene_with(0));
  EXPECT_EQ(lin.character.rotation_strain, nullptr);
  EXPECT_DOUBLE_EQ(lin.problem.obj.w_course, 0.0);
  // Range checks: a negative weight, a vertical direction (no lateral offset on the
  // ground) and an unknown key are InputErrors at their pointers.
  auto term_error = [](const std::string& term, const std::string& body) {
    std::string bad = kScene;
    bad.replace(bad.find("ITER"), 4, "0");
    bad.replace(bad.find("\"weight\": 10}}"), 14, "\"weight\": 10}, \"" + term + "\": " + body + "}");
    try {
      soft::soft_compile(parse_scene(bad, "course.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
    } catch (const InputError& e) {
      return e.pointer();
    }
    return std::string("no error");
  };
  auto course_error = [&](const std::string& course) { return term_error("course", course); };
  EXPECT_EQ(course_error(R"({"weight": -1})"), "/objectives/course/weight");
  EXPECT_EQ(course_error(R"({"direction": [0, 2, 0]})"), "/objectives/course/direction");
  EXPECT_EQ(course_error(R"({"direction": [0, 0, 0]})"), "/objectives/course/direction");
  EXPECT_EQ(course_error(R"({"wieght": 1})"), "/objectives/course/wieght");
  EXPECT_EQ(course_error(R"({"direction": [1, 0.5, 0], "weight": 2})"), "no error");
  // upright: a body axis (any non-zero direction) and a weight.
  EXPECT_EQ(term_error("upright", R"({"weight": -1})"), "/objectives/upright/weight");
  EXPECT_EQ(term_error("upright", R"({"body_axis": [0, 0, 0]})"), "/objectives/upright/body_axis");
  EXPECT_EQ(term_error("upright", R"({"wieght": 1})"), "/objectives/upright/wieght");
  EXPECT_EQ(term_error("upright", R"({"body_axis": [0, 2, 0], "weight": 5})"), "no error");
}

// The optimizer keys of the fifth session reach OptimizerSettings; out of range is
// an InputError at its pointer.
TEST(SoftJob, SceneSetsLmDampingBroydenReuseAndLbfgsFirstStep) {
  std::string t = kScene;
  t.replace(t.find("ITER"), 4, "0, \"lm_lambda_initial\": 0.5, \"broyden_reuse\": 0, \"lbfgs_initial_step\": 0.01");
  const soft::SoftModel m =
      soft::soft_compile(parse_scene(t, "opt.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
  EXPECT_DOUBLE_EQ(m.optimizer.lambda_initial, 0.5);
  EXPECT_EQ(m.optimizer.broyden_reuse, 0);
  EXPECT_DOUBLE_EQ(m.optimizer.lbfgs_initial_step, 0.01);
  const soft::SoftModel d = soft::soft_compile(scene_with(0));
  EXPECT_DOUBLE_EQ(d.optimizer.lambda_initial, 1e-3);
  EXPECT_EQ(d.optimizer.broyden_reuse, 4);
  EXPECT_DOUBLE_EQ(d.optimizer.lbfgs_initial_step, 1.0);
  EXPECT_EQ(d.problem.sim.newton_decrement_stop, 0.0);  // opt-in, off by default
  std::string st = kScene;
  st.replace(st.find("\"frames\": 5"), 11, "\"frames\": 5, \"newton_decrement_stop\": 1e-13");
  st.replace(st.find("ITER"), 4, "0");
  EXPECT_DOUBLE_EQ(soft::soft_compile(parse_scene(st, "stop.json", std::string(PLIANT_ASSETS_DIR) + "/characters"))
                       .problem.sim.newton_decrement_stop,
                   1e-13);
  std::string bad = kScene;
  bad.replace(bad.find("ITER"), 4, "0, \"broyden_reuse\": -1");
  try {
    soft::soft_compile(parse_scene(bad, "opt.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/optimizer/broyden_reuse");
  }
}
