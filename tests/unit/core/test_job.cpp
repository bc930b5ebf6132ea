#include "pliant/core/job.h"

#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>

#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/core/log.h"
#include "temp_dir.h"

namespace pliant {
namespace {

using test::TempDir;
using test::write_text;

// A fake "smoke" job: {"frames": N, "mode": ok|input_error|cancel|signal|throw}.
int fake_frames(const Scene& s) {
  JsonReader r(s.doc, s.file);
  r.accept("pliant");
  r.accept("kind");
  r.accept("name");
  r.accept("mode");
  const int n = static_cast<int>(r.integer("frames", 3, 1, 1000));
  r.finish();
  return n;
}

nlohmann::json fake_run(JobContext& ctx) {
  const int n = fake_frames(ctx.scene);
  const std::string mode = ctx.scene.doc.value("mode", "ok");
  if (mode == "input_error") throw InputError(ctx.scene.file, "/mode", "rejected at run time");
  ctx.progress.stage("simulate", n);
  log_info("fake job starting");
  for (int i = ctx.take.manifest().frames_written; i < n; ++i) {
    ctx.progress.check_cancelled();
    Record r;
    r.index = i;
    r.fields.push_back(Field{"density", {2, 2}, {1.f * i, 2, 3, 4}});
    ctx.take.append(r);
    ctx.events.frame(i);
    ctx.progress.report(i + 1, i == 0 ? std::nan("") : 1.0 / (i + 1));
    if (i == 0 && mode == "cancel") ctx.progress.cancel();
    if (i == 0 && mode == "signal") ::raise(SIGINT);
    if (i == 0 && mode == "throw") throw std::runtime_error("solver exploded");
  }
  return {{"frames", n}, {"resumed", ctx.resume}, {"nan_metric", std::nan("")}};
}

const std::vector<JobKind> kKinds = {{"smoke", fake_run, fake_frames}};

struct JobResult {
  int code;
  std::vector<nlohmann::json> events;
};

JobResult run(const std::filesystem::path& scene, const std::filesystem::path& take, bool resume = false) {
  std::FILE* out = std::tmpfile();
  int code = run_job(RunOptions{scene, take, 1, resume}, kKinds, out);
  std::rewind(out);
  JobResult res{code, {}};
  char line[4096];
  while (std::fgets(line, sizeof line, out)) res.events.push_back(nlohmann::json::parse(line));  // must parse
  std::fclose(out);
  return res;
}

std::vector<std::string> names(const JobResult& r) {
  std::vector<std::string> out;
  for (const auto& e : r.events) out.push_back(e.at("event"));
  return out;
}

size_t count(const JobResult& r, const std::string& name) {
  auto n = names(r);
  return static_cast<size_t>(std::count(n.begin(), n.end(), name));
}

std::filesystem::path scene_file(const TempDir& dir, const std::string& extra) {
  auto p = dir / "scene.json";
  write_text(p, R"({"pliant": 1, "kind": "smoke")" + extra + "}");
  return p;
}

TEST(RunJob, DonePath) {
  TempDir dir;
  auto res = run(scene_file(dir, R"(, "frames": 3)"), dir / "take");
  ASSERT_EQ(res.code, kExitDone);
  ASSERT_GE(res.events.size(), 5u);
  EXPECT_EQ(res.events.front(),
            (nlohmann::json{{"event", "start"}, {"kind", "smoke"}, {"take", (dir / "take").string()}, {"frames", 3}}));
  EXPECT_EQ(res.events.back()["event"], "done");
  EXPECT_EQ(res.events.back()["metrics"]["frames"], 3);
  EXPECT_TRUE(res.events.back()["metrics"]["nan_metric"].is_null());
  EXPECT_EQ(count(res, "frame"), 3u);
  EXPECT_EQ(count(res, "log"), 1u);
  EXPECT_GE(count(res, "progress"), 2u);
  for (const auto& e : res.events) {
    if (e["event"] == "log") {
      EXPECT_EQ(e["level"], "info");
      EXPECT_EQ(e["message"], "fake job starting");
    }
    if (e["event"] == "progress" && e["iter"] == 1) {
      EXPECT_FALSE(e.contains("objective"));  // NaN omitted
    }
  }
  TakeReader take(dir / "take");
  EXPECT_EQ(take.manifest().status, "done");
  EXPECT_EQ(take.manifest().frames_written, 3);
  EXPECT_EQ(take.manifest().frames_expected, 3);
  EXPECT_EQ(take.manifest().metrics["frames"], 3);
  EXPECT_EQ(take.manifest().progress["iter"], 3);
  EXPECT_EQ(take.manifest().scene["frames"], 3);
  EXPECT_EQ(take.frame_count(), 3u);
  EXPECT_FLOAT_EQ(take.read_frame_at(2).fields[0].data[0], 2.f);
}

TEST(RunJob, InvalidSceneIsExit2WithoutTake) {
  TempDir dir;
  auto res = run(scene_file(dir, R"(, "frames": -1)"), dir / "take");
  EXPECT_EQ(res.code, kExitInvalid);
  ASSERT_EQ(res.events.size(), 1u);
  EXPECT_EQ(res.events[0]["event"], "error");
  EXPECT_EQ(res.events[0]["message"], (dir / "scene.json").string() + ": /frames: expected a positive integer, got -1");
  EXPECT_FALSE(std::filesystem::exists(dir / "take"));

  res = run(dir / "missing.json", dir / "take");
  EXPECT_EQ(res.code, kExitInvalid);
  EXPECT_EQ(names(res), std::vector<std::string>{"error"});
}

TEST(RunJob, UnimplementedKindNamesKind) {
  TempDir dir;
  auto p = dir / "liquid.json";
  write_text(p, R"({"pliant": 1, "kind": "liquid"})");
  auto res = run(p, dir / "take");
  EXPECT_EQ(res.code, kExitInvalid);
  ASSERT_EQ(res.events.size(), 1u);
  EXPECT_EQ(res.events[0]["message"],
            p.string() + ": /kind: no job for scene kind \"liquid\" in this build (available: \"smoke\")");
}

TEST(RunJob, InputErrorDuringRunFailsTheTake) {
  TempDir dir;
  auto res = run(scene_file(dir, R"(, "mode": "input_error")"), dir / "take");
  EXPECT_EQ(res.code, kExitInvalid);
  EXPECT_EQ(res.events.back()["event"], "error");
  TakeReader take(dir / "take");
  EXPECT_EQ(take.manifest().status, "failed");
  EXPECT_EQ(take.manifest().error, (dir / "scene.json").string() + ": /mode: rejected at run time");
}

TEST(RunJob, InternalErrorIsExit1) {
  TempDir dir;
  auto res = run(scene_file(dir, R"(, "mode": "throw")"), dir / "take");
  EXPECT_EQ(res.code, kExitInternal);
  EXPECT_EQ(res.events.back()["message"], "solver exploded");
  TakeReader take(dir / "take");
  EXPECT_EQ(take.manifest().status, "failed");
  EXPECT_EQ(take.frame_count(), 1u);
}

TEST(RunJob, CancelLeavesAReadableCancelledTake) {
  TempDir dir;
  auto res = run(scene_file(dir, R"(, "mode": "cancel", "frames": 5)"), dir / "take");
  EXPECT_EQ(res.code, kExitCancelled);
  EXPECT_EQ(res.events.back(), (nlohmann::json{{"event", "cancelled"}}));
  TakeReader take(dir / "take");
  EXPECT_EQ(take.manifest().status, "cancelled");
  EXPECT_EQ(take.frame_count(), 1u);
  EXPECT_FALSE(take.torn_tail());
}

TEST(RunJob, SigintCancelsAndHandlersAreRestored) {
  struct sigaction before {};
  sigaction(SIGINT, nullptr, &before);
  TempDir dir;
  auto res = run(scene_file(dir, R"(, "mode": "signal", "frames": 5)"), dir / "take");
  EXPECT_EQ(res.code, kExitCancelled);
  EXPECT_EQ(TakeReader(dir / "take").manifest().status, "cancelled");
  struct sigaction after {};
  sigaction(SIGINT, nullptr, &after);
  EXPECT_EQ(before.sa_handler, after.sa_handler);
}

TEST(RunJob, ResumeContinuesAfterTheLastGoodFrame) {
  TempDir dir;
  auto scene = scene_file(dir, R"(, "frames": 4, "mode": "cancel")");
  ASSERT_EQ(run(scene, dir / "take").code, kExitCancelled);
  std::ofstream(dir / "take/frames.bin", std::ios::binary | std::ios::app) << "torn bytes of a killed run";
  scene = scene_file(dir, R"(, "frames": 4)");
  auto res = run(scene, dir / "take", /*resume=*/true);
  ASSERT_EQ(res.code, kExitDone);
  EXPECT_EQ(count(res, "frame"), 3u);  // frames 1..3; frame 0 was already there
  EXPECT_EQ(res.events.back()["metrics"]["resumed"], true);
  TakeReader take(dir / "take");
  EXPECT_EQ(take.manifest().status, "done");
  EXPECT_EQ(take.frame_count(), 4u);
  EXPECT_FALSE(take.torn_tail());
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(take.read_frame_at(i).index, static_cast<int>(i));
}

TEST(JobEvents, LinesAreValidJsonEvenWithNaN) {
  std::FILE* out = std::tmpfile();
  JobEvents ev(out);
  ProgressReport r;
  r.stage = "x";
  ev.progress(r);
  r.objective = 0.25;
  r.eta_s = 3;
  ev.progress(r);
  ev.error("bad \xff byte");
  std::rewind(out);
  char line[1024];
  std::vector<nlohmann::json> lines;
  while (std::fgets(line, sizeof line, out)) lines.push_back(nlohmann::json::parse(line));
  std::fclose(out);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_FALSE(lines[0].contains("objective"));
  EXPECT_FALSE(lines[0].contains("eta_s"));
  EXPECT_DOUBLE_EQ(lines[1]["objective"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(lines[1]["eta_s"].get<double>(), 3);
  EXPECT_EQ(lines[2]["event"], "error");
}

}  // namespace
}  // namespace pliant
