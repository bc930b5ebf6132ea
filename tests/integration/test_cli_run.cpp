// `pliant run` to completion: the JSON-lines protocol and the take it leaves.
#include "cli_fixture.h"

namespace pliant::test {
namespace {

using RunJob = CliTest;

TEST_F(RunJob, WritesADoneTakeAndJsonLines) {
  const int frames = 30;
  const fs::path scene = write_scene("plume.json", smoke_scene(32, 32, frames));
  const fs::path take_dir = dir_ / "take";
  const ProcessResult r =
      pliant({"run", scene.string(), "--take", take_dir.string(), "--threads", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;

  const auto events = parse_json_lines(r.out);
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events.front()["event"], "start");
  EXPECT_EQ(events.front()["kind"], "smoke");
  EXPECT_EQ(events.front()["frames"], frames + 1);  // frame records: the initial state + one per frame
  EXPECT_EQ(events.back()["event"], "done");
  EXPECT_TRUE(events.back()["metrics"].is_object());
  std::vector<int> frame_events;
  for (const auto& e : events) {
    EXPECT_NE(e["event"], "error") << e.dump();
    if (e["event"] == "frame") frame_events.push_back(e["index"]);
    if (e["event"] == "progress") {
      EXPECT_TRUE(e.contains("stage") && e.contains("iter")) << e.dump();
    }
  }

  TakeReader take(take_dir);
  EXPECT_EQ(take.manifest().status, "done");
  EXPECT_EQ(take.manifest().kind, "smoke");
  EXPECT_EQ(take.manifest().frames_expected, frames + 1);
  EXPECT_FALSE(take.torn_tail());
  ASSERT_EQ(take.frame_count(), frame_events.size());
  ASSERT_GE(take.frame_count(), size_t(frames));
  double previous_time = -1;
  for (size_t n = 0; n < take.frame_count(); ++n) {
    const Record rec = take.read_frame_at(n);
    EXPECT_EQ(rec.index, frame_events[n]);
    EXPECT_GT(rec.time_s, previous_time);
    previous_time = rec.time_s;
    const Field* density = rec.find("density");
    ASSERT_NE(density, nullptr);
    EXPECT_EQ(density->shape, (std::vector<uint32_t>{32, 32}));  // [ny, nx]
    EXPECT_TRUE(all_finite(rec)) << "frame " << n;
  }
  // The source injected density: the last frame holds some.
  const Record last = take.read_frame_at(take.frame_count() - 1);
  double total = 0;
  for (float v : last.find("density")->data) total += v;
  EXPECT_GT(total, 0.0);
}

TEST_F(RunJob, SameSceneSameThreadsIsBitwiseReproducible) {
  const fs::path scene = write_scene("plume.json", smoke_scene(24, 24, 10));
  for (const char* name : {"a", "b"}) {
    const ProcessResult r =
        pliant({"run", scene.string(), "--take", (dir_ / name).string(), "--threads", "1"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  TakeReader a(dir_ / "a"), b(dir_ / "b");
  ASSERT_EQ(a.frame_count(), b.frame_count());
  for (size_t n = 0; n < a.frame_count(); ++n) {
    const Record ra = a.read_frame_at(n), rb = b.read_frame_at(n);
    ASSERT_EQ(ra.fields.size(), rb.fields.size());
    for (size_t f = 0; f < ra.fields.size(); ++f) {
      EXPECT_TRUE(bitwise_equal(ra.fields[f].data, rb.fields[f].data)) << "frame " << n << " " << ra.fields[f].name;
    }
  }
}

}  // namespace
}  // namespace pliant::test
