// The control job end to end in-process: frames 0..T with density, velocity and
// force; checkpoints; metrics; --resume continues from the latest checkpoint and
// ends at the same objective as the uninterrupted run.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/control.h"

namespace pliant::smoke {
namespace {

namespace fs = std::filesystem;

Scene tiny_scene(int iterations) {
  const std::string text = R"({"pliant": 1, "kind": "smoke", "grid": {"resolution": [12, 12], "cell_size_m": 0.08333333},
    "time": {"dt_s": 0.05, "frames": 5}, "control": {"method": "lbfgs", "r": 1e-3, "tolerance": 1e-12,
    "max_iterations": )" + std::to_string(iterations) + R"(,
    "initial_density": [{"type": "circle", "center": [0.3, 0.3], "radius": 0.2}],
    "keyframes": [{"frame": 5, "target": {"type": "square", "center": [0.6, 0.6], "half_size": [0.177, 0.177]}}]}})";
  return parse_scene(text, "tiny_control.json");
}

struct JobRun {
  nlohmann::json metrics;
  int frame_events = 0;
};

JobRun run(const Scene& scene, const fs::path& dir, bool resume) {
  Manifest man;
  man.kind = "smoke";
  TakeWriter take = resume ? TakeWriter::reopen(dir) : TakeWriter::create(dir, man);
  Progress progress;
  std::FILE* sink = std::tmpfile();
  JobEvents events(sink);
  JobContext ctx{scene, take, progress, events, 1, resume};
  JobRun out;
  out.metrics = smoke_control_run_job(ctx);
  take.finish("done");
  std::rewind(sink);
  char line[4096];
  while (std::fgets(line, sizeof line, sink)) out.frame_events += std::string(line).find("\"frame\"") != std::string::npos;
  std::fclose(sink);
  return out;
}

TEST(ControlJob, WritesFramesCheckpointsAndMetricsAndResumes) {
  const fs::path dir = fs::temp_directory_path() / ("pliant_control_job_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Scene scene = tiny_scene(60);
  ASSERT_TRUE(scene_has_control(scene));
  const JobRun full = run(scene, dir / "full", false);
  EXPECT_EQ(full.frame_events, 6);
  EXPECT_EQ(smoke_control_job_frames(scene), full.frame_events);  // what the manifest expects
  EXPECT_EQ(full.metrics["method"], "lbfgs");
  EXPECT_EQ(full.metrics["resumed_from_iteration"], -1);
  EXPECT_LT(double(full.metrics["keyframes"][0]["relative_l2"]), 1.0);
  EXPECT_LT(double(full.metrics["max_divergence_per_s"]), 1e-6);
  TakeReader reader(dir / "full");
  ASSERT_EQ(reader.frame_count(), 6u);
  const Record f5 = reader.read_frame_at(5);
  ASSERT_TRUE(f5.find("density") && f5.find("velocity") && f5.find("force"));
  EXPECT_EQ(f5.find("velocity")->shape, (std::vector<uint32_t>{12, 12, 2}));
  size_t checkpoints = 0;
  for (size_t i = 0; i < reader.record_count(); ++i) checkpoints += reader.record_kind(i) == RecordKind::Checkpoint;
  ASSERT_GE(checkpoints, 2u);

  // "Killed" run: a take holding only the first checkpoint of the full run.
  {
    Manifest man;
    man.kind = "smoke";
    TakeWriter killed = TakeWriter::create(dir / "killed", man);
    for (size_t i = 0; i < reader.record_count(); ++i)
      if (reader.record_kind(i) == RecordKind::Checkpoint) {
        killed.append(reader.read(i));
        break;
      }
  }
  const JobRun resumed = run(scene, dir / "killed", true);
  EXPECT_GT(int(resumed.metrics["resumed_from_iteration"]), 0);
  EXPECT_EQ(resumed.metrics["iterations"], full.metrics["iterations"]);
  EXPECT_DOUBLE_EQ(double(resumed.metrics["objective"]), double(full.metrics["objective"]));
  fs::remove_all(dir);
}

TEST(ControlJob, ThreeDimensionalTake) {
  const fs::path dir = fs::temp_directory_path() / ("pliant_control_job3d_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Scene scene = parse_scene(
      R"({"pliant": 1, "kind": "smoke", "grid": {"resolution": [8, 7, 6], "cell_size_m": 0.125},
          "time": {"dt_s": 0.05, "frames": 3}, "control": {"method": "lbfgs", "r": 1e-3, "max_iterations": 5,
          "initial_density": [{"type": "sphere", "center": [0.4, 0.4, 0.5], "radius": 0.25}],
          "keyframes": [{"frame": 3, "target": {"type": "box", "center": [0.6, 0.6, 0.5], "half_size": [0.2, 0.2, 0.2]}}]}})",
      "tiny3d.json");
  const JobRun r = run(scene, dir, false);
  EXPECT_EQ(r.frame_events, 4);
  TakeReader reader(dir);
  const Record f = reader.read_frame_at(3);
  EXPECT_EQ(f.find("density")->shape, (std::vector<uint32_t>{6, 7, 8}));
  EXPECT_EQ(f.find("velocity")->shape, (std::vector<uint32_t>{6, 7, 8, 3}));
  EXPECT_EQ(f.find("force")->shape, (std::vector<uint32_t>{6, 7, 8, 3}));
  EXPECT_LT(double(r.metrics["keyframes"][0]["relative_l2"]), 1.0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pliant::smoke
