// `pliant` on soft-character scenes: a broken mesh exits 2 naming the field; a
// short worm optimisation runs end to end and its take holds the documented
// per-frame fields (engine/soft/README.md); SIGTERM leaves a cancelled take.
#include <signal.h>

#include "cli_fixture.h"

namespace pliant::test {
namespace {

nlohmann::json worm_scene(int iterations, int frames) {
  std::ifstream in(kRepo / "assets/scenes/soft_worm_crawl.json");
  nlohmann::json s = nlohmann::json::parse(in);
  s["character"]["mesh"] = (kRepo / "assets/characters/worm.obj").string();
  s["optimizer"]["iterations"] = iterations;
  s["simulation"]["frames"] = frames;
  return s;
}

class SoftCli : public CliTest {};

TEST_F(SoftCli, BrokenMeshExitsTwoNamingTheMeshField) {
  for (const char* mesh : {"garbage.obj", "empty.obj", "zero_area.obj", "absurd_scale.obj", "missing.obj"}) {
    nlohmann::json s = worm_scene(1, 10);
    s["character"]["mesh"] = (kRepo / "tests/meshes" / mesh).string();
    const fs::path scene = write_scene(std::string("broken_") + mesh + ".json", s);
    const ProcessResult r = pliant({"validate", scene.string()});
    EXPECT_EQ(r.exit_code, 2) << mesh << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "/character/mesh")) << mesh << ": " << r.err;
    EXPECT_TRUE(contains(r.err, scene.string())) << r.err;
  }
}

TEST_F(SoftCli, ShortWormOptimisationWritesVerticesTrianglesAndCom) {
  const fs::path scene = write_scene("worm.json", worm_scene(1, 10));
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", scene.string(), "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto events = parse_json_lines(r.out);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back()["event"], "done");
  TakeReader reader(take);
  EXPECT_EQ(reader.manifest().status, "done");
  ASSERT_GE(reader.frame_count(), 10u);
  const Record first = reader.read_frame_at(0);
  const Field* v = first.find("vertices");
  const Field* t = first.find("triangles");
  ASSERT_TRUE(v && t && first.find("com"));
  ASSERT_EQ(v->shape.size(), 2u);
  EXPECT_EQ(v->shape[1], 3u);
  EXPECT_GE(v->shape[0], 8u);
  // Triangle indices address the frame's vertices.
  for (float idx : t->data) ASSERT_TRUE(idx >= 0 && idx < float(v->shape[0]));
  const Record last = reader.read_frame_at(reader.frame_count() - 1);
  EXPECT_TRUE(all_finite(last));
  EXPECT_FALSE(bitwise_equal(last.find("vertices")->data, v->data)) << "the worm never moved";
}

TEST_F(SoftCli, SigtermDuringOptimisationLeavesACancelledTake) {
  const fs::path scene = write_scene("worm_long.json", worm_scene(200, 100));
  const fs::path take = dir_ / "take";
  LiveProcess p({kPliant, "run", scene.string(), "--take", take.string()}, dir_ / "stderr.txt");
  // Wait for the optimiser's first progress event, then cancel mid-run.
  bool optimising = false;
  while (auto line = p.read_line(60)) {
    if (contains(*line, "\"progress\"")) {
      optimising = true;
      break;
    }
  }
  ASSERT_TRUE(optimising);
  p.send_signal(SIGTERM);
  std::vector<std::string> rest;
  const ProcessResult r = p.finish(&rest, 60);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(TakeReader(take).manifest().status, "cancelled");
}

}  // namespace
}  // namespace pliant::test

namespace pliant::test {
namespace {

nlohmann::json navigate_scene(int max_frames) {
  std::ifstream in(kRepo / "assets/scenes/soft_navigate.json");
  nlohmann::json s = nlohmann::json::parse(in);
  s["character"]["mesh"] = (kRepo / "assets/characters/spider.obj").string();
  s["navigation"]["max_frames"] = max_frames;
  s["navigation"]["planning_time_s"] = 0.5;
  return s;
}

class SoftNavigateCli : public CliTest {};

TEST_F(SoftNavigateCli, WrongGaitSizeExitsTwoNamingTheField) {
  nlohmann::json s = navigate_scene(10);
  s["navigation"]["gaits"]["left"] = {1.0, 2.0};
  const fs::path scene = write_scene("nav_bad.json", s);
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // Without OMPL the whole section is refused, naming the package.
  EXPECT_TRUE(contains(r.err, "/navigation/gaits/left") || contains(r.err, "libompl-dev")) << r.err;
}

TEST_F(SoftNavigateCli, ShortNavigationWritesGaitPerFrame) {
  const fs::path scene = write_scene("nav.json", navigate_scene(30));
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", scene.string(), "--take", take.string()});
  if (r.exit_code == 2 && contains(r.err, "libompl-dev")) GTEST_SKIP() << "built without OMPL";
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  TakeReader reader(take);
  ASSERT_GE(reader.frame_count(), 10u);
  const Record last = reader.read_frame_at(reader.frame_count() - 1);
  const Field* g = last.find("gait");
  ASSERT_TRUE(g && last.find("com") && last.find("vertices"));
  ASSERT_EQ(g->data.size(), 1u);
  EXPECT_TRUE(g->data[0] == 0 || g->data[0] == 1 || g->data[0] == 2);
  const auto events = parse_json_lines(r.out);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back()["event"], "done");
  EXPECT_GT(events.back()["metrics"]["min_clearance_m"].get<double>(), 0.0);
}

}  // namespace
}  // namespace pliant::test
