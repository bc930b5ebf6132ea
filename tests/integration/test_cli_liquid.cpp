// `pliant` on liquid scenes, feedback planner pipeline end to end: a dataset
// sweep shard writes samples into its take, liquid_train turns the takes into
// a network, and a feedback run uses it; a missing network exits 2 naming
// /planner/network.
#include "cli_fixture.h"

namespace pliant::test {
namespace {


class LiquidCli : public CliTest {};

nlohmann::json problem_scene(int id, const nlohmann::json& planner) {
  return {{"pliant", 1}, {"kind", "liquid"}, {"dim", 2}, {"problem", {{"seed", 2026}, {"id", id}}}, {"planner", planner}};
}

TEST_F(LiquidCli, FeedbackWithoutNetworkExitsTwoNamingTheField) {
  const fs::path scene =
      write_scene("feedback.json", problem_scene(1, {{"mode", "feedback"}, {"network", "missing_net.json"}}));
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "/planner/network")) << r.err;
  EXPECT_TRUE(contains(r.err, scene.string())) << r.err;
  // A held-out problem is refused as training data.
  const fs::path held = write_scene("held.json", problem_scene(5, {{"mode", "simplified"}}));
  const ProcessResult h = pliant({"validate", held.string()});
  EXPECT_EQ(h.exit_code, 2) << h.err;
  EXPECT_TRUE(contains(h.err, "/problem/id")) << h.err;
}

TEST_F(LiquidCli, DatasetSweepTrainAndFeedbackRun) {
  const fs::path trainer = fs::path(kPliant).parent_path() / "liquid_train";
  if (!fs::exists(trainer)) GTEST_SKIP() << "liquid_train not built";
  write_scene("dataset_scene.json", problem_scene(1, {{"mode", "simplified"},
                                                       {"generations", 4},
                                                       {"fit_discharge", false},
                                                       {"refine_iterations", 0},
                                                       {"record_samples", true}}));
  const nlohmann::json sweep = {{"pliant_sweep", 1},
                                {"scene", "dataset_scene.json"},
                                {"out", "dataset"},
                                {"threads", 1},
                                {"parameters", {{{"pointer", "/problem/id"}, {"values", {1, 2}}}}}};
  const fs::path sweep_file = write_text("dataset.json", sweep.dump());
  // Shard 1/2 runs problem 2 only.
  const ProcessResult s = pliant({"sweep", sweep_file.string(), "--shard", "1/2"});
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const TakeReader take(dir_ / "dataset/run_0001");
  EXPECT_EQ(take.manifest().status, "done");
  ASSERT_TRUE(take.manifest().metrics.contains("samples"));
  EXPECT_EQ(take.manifest().metrics["samples_count"].get<int>(), 26);  // 2.6 s in 0.1 s intervals
  EXPECT_FALSE(fs::exists(dir_ / "dataset/run_0000"));

  const fs::path net = dir_ / "net.json";
  const ProcessResult t = run_process({trainer.string(), (dir_ / "dataset").string(), net.string(), "--epochs", "5"});
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(contains(t.out, "\"takes\":1")) << t.out;

  const fs::path scene = write_scene("feedback.json", problem_scene(2, {{"mode", "feedback"}, {"network", "net.json"}}));
  const ProcessResult r = pliant({"run", scene.string(), "--take", (dir_ / "fb").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const TakeReader fb(dir_ / "fb");
  const auto& m = fb.manifest().metrics;
  EXPECT_EQ(m["mpc_steps"].get<int>(), 26);
  EXPECT_GT(m["mpc_step_ms"].get<double>(), 0.0);
  EXPECT_EQ(m["planner"]["mode"], "feedback");
  EXPECT_EQ(fb.frame_count(), 131u);
}

}  // namespace
}  // namespace pliant::test
