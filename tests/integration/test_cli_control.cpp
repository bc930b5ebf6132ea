// `pliant run` on a smoke scene with a "control" section: the take holds frames
// 0..T with density, velocity and force, and metrics; a run killed with SIGKILL
// after its first checkpoint resumes (--resume) to the same objective as an
// uninterrupted run; invalid keyframes exit 2 naming the field.
#include <signal.h>

#include "cli_fixture.h"

namespace pliant::test {
namespace {

nlohmann::json control_scene(int n, int frames, int iterations, double r = 1e-3) {
  return {{"pliant", 1},
          {"kind", "smoke"},
          {"name", "integration test control"},
          {"grid", {{"resolution", {n, n}}, {"cell_size_m", 1.0 / n}, {"boundary", "closed"}}},
          {"time", {{"dt_s", 0.05}, {"frames", frames}}},
          {"control",
           {{"method", "lbfgs"},
            {"r", r},
            {"max_iterations", iterations},
            {"tolerance", 1e-12},
            {"initial_density", {{{"type", "circle"}, {"center", {0.3, 0.3}}, {"radius", 0.15}}}},
            {"keyframes",
             {{{"frame", frames},
               {"target", {{"type", "square"}, {"center", {0.62, 0.62}}, {"half_size", {0.133, 0.133}}}}}}}}}};
}

const nlohmann::json* find_done(const std::vector<nlohmann::json>& events) {
  for (const auto& e : events)
    if (e["event"] == "done") return &e;
  return nullptr;
}

class Control : public CliTest {
 protected:
  // expect_level >= 0: the resumed run reports that coarse-to-fine level (resumed_from_level).
  void expect_killed_run_resumes_to_same_objective(const nlohmann::json& doc, const std::string& stage, int kill_at,
                                                   int expect_level = -1);
};

TEST_F(Control, RunWritesFramesAndMetrics) {
  // The disjoint default target: the first L-BFGS steps change the objective by ~1e-12
  // relative (unit first step); the stop needs 3 such iterations in a row, so the run
  // goes on and moves the smoke (ControlLbfgs.FirstTinyStepsDoNotStopTheRun).
  nlohmann::json doc = control_scene(16, 6, 20);
  const fs::path scene = write_scene("c.json", doc);
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", scene.string(), "--take", take.string(), "--threads", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto events = parse_json_lines(r.out);
  const nlohmann::json* done = find_done(events);
  ASSERT_TRUE(done);
  const auto& m = (*done)["metrics"];
  EXPECT_EQ(m["method"], "lbfgs");
  ASSERT_EQ(m["keyframes"].size(), 1u);
  EXPECT_LT(double(m["keyframes"][0]["relative_l2"]), std::sqrt(2.0));  // sqrt(2): disjoint, no control
  EXPECT_LT(double(m["objective_history"].back()), 0.9 * double(m["objective_history"].front()));
  EXPECT_LT(double(m["max_divergence_per_s"]), 1e-6);
  EXPECT_GT(m["objective_history"].size(), 1u);
  TakeReader reader(take);
  ASSERT_EQ(reader.frame_count(), 7u);
  const Record last = reader.read_frame_at(6);
  ASSERT_TRUE(last.find("density") && last.find("velocity") && last.find("force"));
  EXPECT_EQ(last.find("velocity")->shape, (std::vector<uint32_t>{16, 16, 2}));
  Record cp;
  EXPECT_TRUE(reader.latest(RecordKind::Checkpoint, &cp));
}

// Runs `doc` uninterrupted, then again killed with SIGKILL once the progress of
// `stage` reports iteration `kill_at` (its checkpoint precedes the report), resumes
// it with --resume and expects the uninterrupted run's objective.
void Control::expect_killed_run_resumes_to_same_objective(const nlohmann::json& doc, const std::string& stage,
                                                          int kill_at, int expect_level) {
  const fs::path scene = write_scene(stage + ".json", doc);
  const ProcessResult full =
      pliant({"run", scene.string(), "--take", (dir_ / "full").string(), "--threads", "1"});
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const auto full_events = parse_json_lines(full.out);
  ASSERT_TRUE(find_done(full_events));
  const double objective = double((*find_done(full_events))["metrics"]["objective"]);
  const fs::path take = dir_ / "killed";
  {
    LiveProcess p({kPliant, "run", scene.string(), "--take", take.string(), "--threads", "1"}, dir_ / "err.txt");
    bool seen = false;
    while (auto line = p.read_line(60)) {
      const auto e = nlohmann::json::parse(*line);
      if (e["event"] == "progress" && e["stage"] == stage && int(e["iter"]) >= kill_at) {
        seen = true;
        break;
      }
    }
    ASSERT_TRUE(seen);
    p.send_signal(SIGKILL);
  }
  Record cp;
  ASSERT_TRUE(TakeReader(take).latest(RecordKind::Checkpoint, &cp));
  const ProcessResult resumed =
      pliant({"run", scene.string(), "--take", take.string(), "--threads", "1", "--resume"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto resumed_events = parse_json_lines(resumed.out);
  const nlohmann::json* done = find_done(resumed_events);
  ASSERT_TRUE(done);
  const auto& m = (*done)["metrics"];
  EXPECT_GE(int(m["resumed_from_iteration"]), kill_at);
  if (expect_level >= 0) {
    EXPECT_EQ(int(m["resumed_from_level"]), expect_level);
  }
  EXPECT_NEAR(double(m["objective"]), objective, 1e-9 * objective);
}

TEST_F(Control, KilledRunResumesToTheSameObjective) {
  // Long enough (several L-BFGS chunks of 20 iterations, each > 0.1 s) that the
  // progress events of the "lbfgs" stage are not throttled away.
  expect_killed_run_resumes_to_same_objective(control_scene(32, 12, 100, 1e-4), "lbfgs", 1);
}

// The ADMM method (outer loop, then the L-BFGS polish): killed after its second outer
// iteration; the checkpoint holds all the state the solver carries.
TEST_F(Control, KilledAdmmRunResumesToTheSameObjective) {
  nlohmann::json doc = control_scene(32, 12, 10, 1e-4);
  doc["control"]["method"] = "admm";
  doc["control"]["admm"] = {{"nso_vcycles", 2}, {"polish_iterations", 20}};
  expect_killed_run_resumes_to_same_objective(doc, "admm", 2);
}

// Killed during the 32^2 level of a 64^2 problem's progressive preview: the coarse
// level's checkpoint resumes there, then the 64^2 level runs as uninterrupted.
TEST_F(Control, KilledDuringACoarseLevelResumesThere) {
  nlohmann::json doc = control_scene(64, 8, 2, 1e-4);
  doc["control"]["method"] = "admm";
  doc["control"]["coarse_iterations"] = 4;
  doc["control"]["admm"] = {{"nso_vcycles", 2}, {"polish_iterations", 5}};
  expect_killed_run_resumes_to_same_objective(doc, "admm 32x32", 2, 1);
}

TEST_F(Control, InvalidKeyframesExitTwo) {
  nlohmann::json doc = control_scene(16, 6, 5);
  doc["control"]["keyframes"][0]["frame"] = 7;
  const fs::path scene = write_scene("bad.json", doc);
  const ProcessResult r = pliant({"run", scene.string(), "--take", (dir_ / "t").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("/control/keyframes/0/frame: expected a frame in 1..6, got 7"), std::string::npos) << r.out;
  nlohmann::json mesh = control_scene(16, 6, 5);
  mesh["grid"]["resolution"] = {8, 8, 8};
  mesh["control"]["initial_density"][0]["center"] = {0.3, 0.3, 0.3};
  mesh["control"]["keyframes"][0]["target"] = {{"type", "mesh"}, {"file", "missing_bunny.obj"}};
  const ProcessResult rm = pliant({"validate", write_scene("mesh.json", mesh).string()});
  EXPECT_EQ(rm.exit_code, 2);
  EXPECT_NE((rm.out + rm.err).find("missing_bunny.obj: cannot load mesh"), std::string::npos) << rm.out << rm.err;
}

}  // namespace
}  // namespace pliant::test
