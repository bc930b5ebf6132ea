#include <gtest/gtest.h>

#include <cstdio>
#include <unistd.h>

#include <filesystem>

#include "pliant/core/error.h"
#include "pliant/core/job.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {
namespace {

namespace fs = std::filesystem;

const char* kScene = R"({
  "pliant": 1, "kind": "liquid", "dim": 2,
  "domain": {"min_m": [-0.1, 0], "max_m": [0.3, 0.3], "cell_size_m": 0.01},
  "time": {"dt_s": 0.02, "frames": 30},
  "source": {"container": {"shape": "cylinder", "radius_m": 0.04, "height_m": 0.1, "wall_m": 0.015},
             "position_m": [0, 0.12],
             "trajectory": [{"time_s": 0, "position_m": [0, 0.12]},
                            {"time_s": 0.5, "position_m": [0.03, 0.12], "tilt_deg": 110}]},
  "target": {"container": {"shape": "cylinder", "radius_m": 0.06, "height_m": 0.06, "wall_m": 0.015},
             "position_m": [0.17, 0]}
})";

struct JobRun {
  nlohmann::json metrics;
  bool cancelled = false;
};

JobRun run(const Scene& scene, const fs::path& dir, bool resume, int cancel_at = -1) {
  Manifest man;
  man.kind = "liquid";
  TakeWriter take = resume ? TakeWriter::reopen(dir) : TakeWriter::create(dir, man);
  Progress* self = nullptr;
  Progress progress([&](const ProgressReport& r) {
    if (cancel_at >= 0 && r.stage == "simulate" && r.iter >= cancel_at) self->cancel();
  });
  progress.min_interval_s = 0;
  self = &progress;
  std::FILE* sink = std::fopen("/dev/null", "w");
  JobEvents events(sink);
  JobContext ctx{scene, take, progress, events};
  ctx.resume = resume;
  JobRun out;
  try {
    out.metrics = liquid_run_job(ctx);
    take.finish("done");
  } catch (const CancelledError&) {
    out.cancelled = true;
    take.finish("cancelled");
  }
  std::fclose(sink);
  return out;
}

TEST(LiquidJob, TakeHasTheDocumentedFieldsAndResumeEndsTheSame) {
  const Scene scene = parse_scene(kScene, "job.json");
  const fs::path base = fs::temp_directory_path() / ("pliant_liquid_job_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const JobRun full = run(scene, base / "full", false);
  ASSERT_FALSE(full.cancelled);
  TakeReader reader(base / "full");
  ASSERT_EQ(reader.frame_count(), 31u);
  const Record last = reader.read_frame_at(30);
  const Field* p = last.find("particles");
  ASSERT_TRUE(p);
  ASSERT_EQ(p->shape.size(), 2u);
  EXPECT_EQ(p->shape[1], 2u);
  ASSERT_TRUE(last.find("speed"));
  EXPECT_EQ(last.find("speed")->shape[0], p->shape[0]);
  EXPECT_EQ(last.find("source_pose")->shape[0], 7u);
  EXPECT_EQ(last.find("target_pose")->shape[0], 7u);
  const Field* fr = last.find("fractions");
  ASSERT_TRUE(fr);
  EXPECT_NEAR(fr->data[0] + fr->data[1] + fr->data[2], 1.0, 1e-6);
  EXPECT_NEAR(fr->data[0], full.metrics["fraction_in_target"].get<double>(), 1e-6);
  EXPECT_GT(full.metrics["fraction_in_target"].get<double>(), 0.5);  // the hand pour reaches the target

  const JobRun first = run(scene, base / "resumed", false, 15);
  EXPECT_TRUE(first.cancelled);
  const JobRun second = run(scene, base / "resumed", true);
  ASSERT_FALSE(second.cancelled);
  EXPECT_EQ(second.metrics["resumed_from_frame"].get<int>(), 10);
  EXPECT_EQ(second.metrics["fraction_in_target"], full.metrics["fraction_in_target"]);
  EXPECT_EQ(second.metrics["fraction_spilled"], full.metrics["fraction_spilled"]);
  fs::remove_all(base);
}

// The feedback closed loop cancelled mid-way and resumed from its checkpoint
// (state + the key poses decided so far) ends exactly like an uninterrupted run.
TEST(LiquidJob, FeedbackResumeEndsTheSame) {
  auto doc = nlohmann::json::parse(kScene);
  doc["source"].erase("trajectory");
  doc["planner"] = {{"mode", "feedback"},
                    {"network", (fs::path(PLIANT_ASSETS_DIR) / "sweeps/liquid_dataset_net.json").string()}};
  const Scene scene = parse_scene(doc.dump(), "job.json");
  const fs::path base = fs::temp_directory_path() / ("pliant_liquid_fb_resume_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const JobRun full = run(scene, base / "full", false);
  ASSERT_FALSE(full.cancelled);
  EXPECT_EQ(full.metrics["mpc_steps"].get<int>(), 6);
  const JobRun first = run(scene, base / "resumed", false, 15);
  EXPECT_TRUE(first.cancelled);
  const JobRun second = run(scene, base / "resumed", true);
  ASSERT_FALSE(second.cancelled);
  EXPECT_EQ(second.metrics["resumed_from_frame"].get<int>(), 10);
  EXPECT_EQ(second.metrics["fraction_in_target"], full.metrics["fraction_in_target"]);
  EXPECT_EQ(second.metrics["fraction_in_source"], full.metrics["fraction_in_source"]);
  // Same decisions (the checkpoint keeps doubles as float pairs: ~1e-15 apart).
  const auto& a = second.metrics["trajectory"];
  const auto& b = full.metrics["trajectory"];
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_NEAR(a[k]["tilt_deg"].get<double>(), b[k]["tilt_deg"].get<double>(), 1e-9) << k;
    EXPECT_NEAR(a[k]["position_m"][0].get<double>(), b[k]["position_m"][0].get<double>(), 1e-12) << k;
  }
  fs::remove_all(base);
}

TEST(LiquidJob, FeedbackPlannerWithoutNetworkIsInvalidInput) {
  auto doc = nlohmann::json::parse(kScene);
  doc["planner"] = {{"mode", "feedback"}, {"network", "no_such_network.json"}};
  const Scene scene = parse_scene(doc.dump(), "job.json");
  const fs::path dir = fs::temp_directory_path() / ("pliant_liquid_fb_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  Manifest man;
  TakeWriter take = TakeWriter::create(dir, man);
  Progress progress;
  std::FILE* sink = std::fopen("/dev/null", "w");
  JobEvents events(sink);
  JobContext ctx{scene, take, progress, events};
  EXPECT_THROW(liquid_run_job(ctx), InputError);
  std::fclose(sink);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pliant::liquid
