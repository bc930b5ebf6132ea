// `pliant sweep`: Cartesian product of values, sharding, skipping done takes.
#include "cli_fixture.h"

namespace pliant::test {
namespace {

using Sweep = CliTest;

nlohmann::json sweep_doc() {
  return {{"pliant_sweep", 1},
          {"scene", "scene.json"},
          {"out", "takes"},
          {"threads", 1},
          {"parameters",
           {{{"pointer", "/buoyancy_m_per_s2"}, {"values", {1.0, 3.0}}},
            {{"pointer", "/sources/0/radius_m"}, {"values", {0.1, 0.2, 0.3}}}}}};
}

TEST_F(Sweep, ShardsCoverEveryCombinationOnceAndSkipDoneTakes) {
  write_scene("scene.json", smoke_scene(12, 12, 3));
  const fs::path sweep = write_scene("sweep.json", sweep_doc());
  std::vector<int> runs_seen;
  for (const char* shard : {"0/2", "1/2"}) {
    const ProcessResult r = pliant({"sweep", sweep.string(), "--shard", shard});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto events = parse_json_lines(r.out);
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.back()["event"], "sweep");
    EXPECT_EQ(events.back()["done"], 3);
    for (const auto& e : events) {
      if (e["event"] == "run") {
        runs_seen.push_back(e["index"]);
        EXPECT_EQ(e["index"].get<int>() % 2, shard[0] - '0') << e.dump();
      }
    }
  }
  std::sort(runs_seen.begin(), runs_seen.end());
  EXPECT_EQ(runs_seen, (std::vector<int>{0, 1, 2, 3, 4, 5}));

  // Run k = (buoyancy index) * 3 + (radius index): the last parameter is fastest.
  const double buoyancy[] = {1.0, 3.0}, radius[] = {0.1, 0.2, 0.3};
  for (int k = 0; k < 6; ++k) {
    char name[16];
    std::snprintf(name, sizeof name, "run_%04d", k);
    TakeReader take(dir_ / "takes" / name);
    EXPECT_EQ(take.manifest().status, "done") << name;
    EXPECT_EQ(take.frame_count(), 4u) << name;
    EXPECT_EQ(take.manifest().scene["buoyancy_m_per_s2"], buoyancy[k / 3]) << name;
    EXPECT_EQ(take.manifest().scene["sources"][0]["radius_m"], radius[k % 3]) << name;
  }

  // Re-running a shard skips its finished takes.
  const ProcessResult again = pliant({"sweep", sweep.string(), "--shard", "0/2"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const auto events = parse_json_lines(again.out);
  EXPECT_EQ(events.back()["skipped"], 3);
  EXPECT_EQ(events.back()["done"], 0);
}

TEST_F(Sweep, BadPointerAndShardAreInvalidInput) {
  write_scene("scene.json", smoke_scene(12, 12, 3));
  auto doc = sweep_doc();
  doc["parameters"][1]["pointer"] = "/sources/0/radius";
  const fs::path sweep = write_scene("sweep.json", doc);
  ProcessResult r = pliant({"sweep", sweep.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, sweep.string())) << r.err;
  EXPECT_TRUE(contains(r.err, "/parameters/1/pointer")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "takes"));

  r = pliant({"sweep", sweep.string(), "--shard", "2/2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--shard")) << r.err;
}

}  // namespace
}  // namespace pliant::test
