// Crash safety of `pliant run`: SIGTERM cancels at a safe point and leaves a
// readable take with status "cancelled"; kill -9 leaves every complete frame
// readable (bitwise equal to a re-run) and the take can be resumed; a soft job
// killed mid-optimization resumes to the uninterrupted run's result.
#include <signal.h>

#include <fstream>

#include "cli_fixture.h"

namespace pliant::test {
namespace {

using Crash = CliTest;

// Long enough (64x64, 2000 frames: ~5 s to finish in a Release build) that
// the job is surely mid-run when the test has seen a few frame events, even
// on a loaded machine; the test kills it right then, so it stays fast.
constexpr int kLongFrames = 2000;
constexpr int kFramesBeforeKill = 3;
// For kill -9: past the first checkpoint (the smoke job writes one every 10
// frames), so --resume has one to start from.
constexpr int kFramesBeforeKill9 = 12;

// Starts `pliant run` and returns once `count` frame events have arrived.
int wait_for_frames(LiveProcess& p, int count) {
  int seen = 0;
  while (seen < count) {
    const auto line = p.read_line(60);
    if (!line) break;
    const auto j = nlohmann::json::parse(*line);
    if (j["event"] == "frame") ++seen;
  }
  return seen;
}

TEST_F(Crash, SigtermCancelsAndLeavesReadableTake) {
  const fs::path scene = write_scene("long.json", smoke_scene(64, 64, kLongFrames));
  const fs::path take_dir = dir_ / "take";
  LiveProcess p({kPliant, "run", scene.string(), "--take", take_dir.string(), "--threads", "1"},
                dir_ / "stderr.txt");
  int seen = wait_for_frames(p, kFramesBeforeKill);
  ASSERT_EQ(seen, kFramesBeforeKill);
  p.send_signal(SIGTERM);
  std::vector<std::string> rest;
  const ProcessResult r = p.finish(&rest);
  EXPECT_EQ(r.term_signal, 0);
  EXPECT_EQ(r.exit_code, 3);
  ASSERT_FALSE(rest.empty());
  for (const auto& line : rest) {
    const auto j = nlohmann::json::parse(line);  // every line is still JSON
    if (j["event"] == "frame") ++seen;
  }
  EXPECT_EQ(nlohmann::json::parse(rest.back())["event"], "cancelled") << rest.back();

  TakeReader take(take_dir);
  EXPECT_EQ(take.manifest().status, "cancelled");
  EXPECT_FALSE(take.torn_tail());
  EXPECT_EQ(take.frame_count(), size_t(seen));
  EXPECT_LT(take.frame_count(), size_t(kLongFrames));  // it was stopped mid-run
  for (size_t n = 0; n < take.frame_count(); ++n) {
    EXPECT_TRUE(all_finite(take.read_frame_at(n))) << "frame " << n;
  }
}

TEST_F(Crash, Kill9KeepsEveryCompleteFrameAndResumes) {
  const fs::path scene = write_scene("long.json", smoke_scene(64, 64, kLongFrames));
  const fs::path take_dir = dir_ / "take";
  {
    LiveProcess p({kPliant, "run", scene.string(), "--take", take_dir.string(), "--threads", "1"},
                  dir_ / "stderr.txt");
    const int seen = wait_for_frames(p, kFramesBeforeKill9);
    ASSERT_EQ(seen, kFramesBeforeKill9);
    p.send_signal(SIGKILL);
    const ProcessResult r = p.finish(nullptr);
    EXPECT_EQ(r.term_signal, SIGKILL);
  }

  TakeReader take(take_dir);
  EXPECT_EQ(take.manifest().status, "running");  // nobody finished it
  const size_t kept = take.frame_count();
  ASSERT_GE(kept, size_t(kFramesBeforeKill9));
  Record checkpoint;
  const bool has_checkpoint = take.latest(RecordKind::Checkpoint, &checkpoint);
  ASSERT_LT(kept, size_t(kLongFrames));  // it was killed mid-run

  // A re-run of the same scene for exactly the frames that survived must
  // reproduce them bit for bit (deterministic with one thread).
  auto short_doc = smoke_scene(64, 64, kLongFrames);
  const Record last_kept = take.read_frame_at(kept - 1);
  short_doc["time"]["frames"] = last_kept.index;  // frames 0..index
  const fs::path short_scene = write_scene("short.json", short_doc);
  const ProcessResult rerun = pliant(
      {"run", short_scene.string(), "--take", (dir_ / "rerun").string(), "--threads", "1"});
  ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
  TakeReader reference(dir_ / "rerun");
  ASSERT_EQ(reference.frame_count(), kept);
  for (size_t n = 0; n < kept; ++n) {
    const Record got = take.read_frame_at(n), want = reference.read_frame_at(n);
    EXPECT_TRUE(all_finite(got)) << "frame " << n;
    ASSERT_EQ(got.index, want.index);
    ASSERT_EQ(got.fields.size(), want.fields.size());
    for (size_t f = 0; f < got.fields.size(); ++f) {
      EXPECT_EQ(got.fields[f].name, want.fields[f].name);
      EXPECT_EQ(got.fields[f].shape, want.fields[f].shape);
      EXPECT_TRUE(bitwise_equal(got.fields[f].data, want.fields[f].data))
          << "frame " << n << " field " << got.fields[f].name;
    }
  }

  // --resume is accepted on the killed take and completes it, from the last
  // checkpoint when there is one (else from frame 0). A horizon two frames past
  // the last kept one keeps the test fast (also under ASan).
  const int resume_frames = last_kept.index + 2;
  auto resume_doc = smoke_scene(64, 64, resume_frames);
  const fs::path resume_scene = write_scene("resume.json", resume_doc);
  const ProcessResult resumed = pliant(
      {"run", resume_scene.string(), "--take", take_dir.string(), "--threads", "1", "--resume"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto events = parse_json_lines(resumed.out);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back()["event"], "done");
  int resumed_frames = 0;
  for (const auto& e : events) resumed_frames += e["event"] == "frame";
  if (has_checkpoint) {  // it continued after the checkpoint instead of starting over
    EXPECT_EQ(resumed_frames, resume_frames - checkpoint.index);
  } else {
    EXPECT_EQ(resumed_frames, resume_frames + 1);
  }
  TakeReader done(take_dir);
  EXPECT_EQ(done.manifest().status, "done");
  EXPECT_EQ(done.manifest().frames_expected, resume_frames + 1);
  EXPECT_FALSE(done.torn_tail());  // reopen dropped any torn tail
  ASSERT_EQ(done.frame_count(), size_t(resume_frames + 1));
  for (size_t n = 0; n < done.frame_count(); ++n) {
    const Record r = done.read_frame_at(n);
    EXPECT_EQ(r.index, int(n));
    EXPECT_TRUE(all_finite(r));
    if (n < kept) {  // the resumed frames agree with the ones that survived
      EXPECT_TRUE(bitwise_equal(r.find("density")->data,
                                reference.read_frame_at(n).find("density")->data))
          << "frame " << n;
    }
  }
}

// The soft job: kill -9 mid-optimization, then --resume. The checkpoint holds the
// optimizer's whole state in doubles, so the resumed run ends exactly where an
// uninterrupted one does (objective history, rollouts, every frame). The worm crawl
// at resolution 6 with 25 iterations: ~1 s per run in Release.
constexpr int kSoftIterations = 25;

nlohmann::json soft_worm_scene() {
  std::ifstream in(kRepo / "assets/scenes/soft_worm_crawl.json");
  nlohmann::json s = nlohmann::json::parse(in);
  s["character"]["mesh"] = (kRepo / "assets/characters/worm.obj").string();
  s["character"]["resolution"] = 6;
  s["simulation"]["frames"] = 20;
  s["optimizer"]["iterations"] = kSoftIterations;
  return s;
}

TEST_F(Crash, SoftKill9MidOptimizationResumesToTheUninterruptedResult) {
  const fs::path scene = write_scene("worm.json", soft_worm_scene());
  const ProcessResult whole =
      pliant({"run", scene.string(), "--take", (dir_ / "whole").string(), "--threads", "1"});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const fs::path take_dir = dir_ / "take";
  {
    LiveProcess p({kPliant, "run", scene.string(), "--take", take_dir.string(), "--threads", "1"},
                  dir_ / "stderr.txt");
    // Killed once the second iteration's checkpoint is in the take (the progress
    // event follows the checkpoint's write).
    for (;;) {
      const auto line = p.read_line(60);
      ASSERT_TRUE(line) << "no optimizer progress";
      const auto j = nlohmann::json::parse(*line);
      if (j["event"] == "progress" && j.value("stage", "") == "optimize" && j.value("iter", 0) >= 2) break;
    }
    p.send_signal(SIGKILL);
    EXPECT_EQ(p.finish(nullptr).term_signal, SIGKILL);
  }
  {
    TakeReader killed(take_dir);
    EXPECT_EQ(killed.manifest().status, "running");
    Record ck;
    ASSERT_TRUE(killed.latest(RecordKind::Checkpoint, &ck));
    EXPECT_GE(ck.index, 2);
    EXPECT_LT(ck.index, kSoftIterations) << "the optimization ended before the kill";
    EXPECT_EQ(killed.frame_count(), 0u);  // frames come after the optimization
  }
  const ProcessResult resumed =
      pliant({"run", scene.string(), "--take", take_dir.string(), "--threads", "1", "--resume"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  TakeReader a(dir_ / "whole"), b(take_dir);
  const nlohmann::json &ma = a.manifest().metrics, &mb = b.manifest().metrics;
  EXPECT_EQ(mb["iterations"], kSoftIterations);
  // Exact: the JSON numbers round-trip doubles.
  EXPECT_EQ(mb["objective_final"].get<double>(), ma["objective_final"].get<double>());
  EXPECT_EQ(mb["objective_history"], ma["objective_history"]);
  EXPECT_EQ(mb["rollouts"], ma["rollouts"]);
  EXPECT_EQ(mb["step_kinds"], ma["step_kinds"]);
  ASSERT_EQ(a.frame_count(), b.frame_count());
  for (size_t n = 0; n < a.frame_count(); ++n)
    EXPECT_TRUE(bitwise_equal(a.read_frame_at(n).find("vertices")->data, b.read_frame_at(n).find("vertices")->data))
        << "frame " << n;
}

}  // namespace
}  // namespace pliant::test
