#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>

#include "pliant/core/error.h"
#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/smoke.h"

namespace pliant::smoke {
namespace {

struct TempTake {
  std::filesystem::path dir;
  TempTake() {
    std::string pattern = (std::filesystem::temp_directory_path() / "pliant-smoke-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    dir = pattern;
  }
  ~TempTake() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

const char* kScene = R"({"pliant":1,"kind":"smoke","grid":{"resolution":[16,12]},
  "time":{"dt_s":0.02,"frames":6},"buoyancy_m_per_s2":2,
  "sources":[{"shape":"sphere","center_m":[0.08,0.03],"radius_m":0.03,"density_per_s":3}],
  "output":{"velocity":true,"every":2}})";

TEST(SmokeJob, FrameRecordShapes) {
  SmokeModel m;
  m.dim = 3;
  m.n = {5, 4, 3};
  SmokeState s = smoke_init(m);
  s.u[m.n[0] * 0 + 1] = 2.0f;  // face (1,0,0) between cells 0 and 1
  const Record r = smoke_frame_record(m, s);
  const Field* d = r.find("density");
  const Field* v = r.find("velocity");
  ASSERT_TRUE(d && v);
  EXPECT_EQ(d->shape, (std::vector<uint32_t>{3, 4, 5}));
  EXPECT_EQ(v->shape, (std::vector<uint32_t>{3, 4, 5, 3}));
  EXPECT_EQ(v->data.size(), 5u * 4 * 3 * 3);
  EXPECT_FLOAT_EQ(v->data[0 * 3 + 0], 1.0f);  // cell 0: average of faces 0 and 1
  EXPECT_FLOAT_EQ(v->data[1 * 3 + 0], 1.0f);  // cell 1: faces 1 and 2
  m.write_velocity = false;
  EXPECT_EQ(smoke_frame_record(m, s).find("velocity"), nullptr);
}

TEST(SmokeJob, RunWritesFramesAndMetrics) {
  TempTake tmp;
  const Scene scene = parse_scene(kScene, "job.json");
  Manifest man;
  man.kind = "smoke";
  TakeWriter take = TakeWriter::create(tmp.dir / "take", man);
  ProgressReport last;
  Progress progress([&](const ProgressReport& r) { last = r; });
  progress.min_interval_s = 0;
  std::FILE* null_out = std::fopen("/dev/null", "w");
  JobEvents events(null_out);
  JobContext ctx{scene, take, progress, events, 1, false};
  const nlohmann::json metrics = smoke_run_job(ctx);
  take.finish("done");
  std::fclose(null_out);
  EXPECT_EQ(metrics["frames"], 6);
  EXPECT_EQ(metrics["cells"], 16 * 12);
  EXPECT_GT(metrics["total_density"].get<double>(), 0.0);
  EXPECT_GT(metrics["cell_steps_per_s"].get<double>(), 0.0);
  EXPECT_GT(metrics["mean_pressure_iterations"].get<double>(), 0.0);
  EXPECT_LT(metrics["max_divergence_per_s"].get<double>(), 1e-2);
  EXPECT_EQ(last.stage, "simulate");
  EXPECT_EQ(last.iter, 6);
  EXPECT_EQ(last.of, 6);
  EXPECT_NEAR(last.objective, metrics["total_density"].get<double>(), 1e-9);
  TakeReader reader(tmp.dir / "take");
  ASSERT_EQ(reader.frame_count(), 4u);  // frames 0, 2, 4, 6
  const Record rec = reader.read_frame_at(3);
  EXPECT_EQ(rec.index, 6);
  EXPECT_NEAR(rec.time_s, 0.12, 1e-12);
  ASSERT_NE(rec.find("velocity"), nullptr);
  double total = 0;
  for (float x : rec.find("density")->data) total += x;
  EXPECT_NEAR(total, metrics["total_density"].get<double>(), 1e-4 * total);
}

TEST(SmokeJob, CancelledJobStops) {
  TempTake tmp;
  const Scene scene = parse_scene(kScene, "job.json");
  TakeWriter take = TakeWriter::create(tmp.dir / "take", Manifest{});
  Progress progress;
  progress.cancel();
  std::FILE* null_out = std::fopen("/dev/null", "w");
  JobEvents events(null_out);
  JobContext ctx{scene, take, progress, events, 0, false};
  EXPECT_THROW(smoke_run_job(ctx), CancelledError);
  std::fclose(null_out);
}

TEST(SmokeJob, BlowUpIsReportedWithFrameAndField) {
  // A uniform force beyond float range overflows the velocity in the first frame;
  // the NaN must be reported (not crash the sampler), in both boundary kinds.
  for (const char* boundary : {"periodic", "closed"})
    for (const char* advection : {"semi_lagrangian", "upwind"}) {
      TempTake tmp;
      const Scene scene = parse_scene(std::string(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,8],"boundary":")") +
                                          boundary + R"("},"advection":")" + advection +
                                          R"(","time":{"frames":5},"forces":[{"type":"uniform","acceleration_m_per_s2":[1e300,0]}]})",
                                      "boom.json");
      TakeWriter take = TakeWriter::create(tmp.dir / "take", Manifest{});
      Progress progress;
      std::FILE* null_out = std::fopen("/dev/null", "w");
      JobEvents events(null_out);
      JobContext ctx{scene, take, progress, events, 0, false};
      try {
        smoke_run_job(ctx);
        ADD_FAILURE() << "expected a NaN error for " << boundary << " " << advection;
      } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("NaN in velocity at frame 1"), std::string::npos) << msg;
        EXPECT_NE(msg.find("dt_s"), std::string::npos) << msg;
      }
      std::fclose(null_out);
    }
}

// A run cancelled after frame 14 and resumed continues from the checkpoint at
// frame 10 and ends bitwise equal to an uninterrupted run.
TEST(SmokeJob, ResumeFromCheckpointIsBitwiseEqual) {
  TempTake tmp;
  const Scene scene = parse_scene(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[16,12]},
    "time":{"dt_s":0.02,"frames":25},"buoyancy_m_per_s2":2,
    "sources":[{"shape":"sphere","center_m":[0.08,0.03],"radius_m":0.03,"density_per_s":3}]})", "resume.json");
  std::FILE* null_out = std::fopen("/dev/null", "w");
  JobEvents events(null_out);
  auto run = [&](const std::filesystem::path& dir, bool resume, int cancel_after) {
    TakeWriter take = resume ? TakeWriter::reopen(dir) : TakeWriter::create(dir, Manifest{});
    Progress* self = nullptr;
    Progress progress([&](const ProgressReport& r) {
      if (r.iter == cancel_after) self->cancel();
    });
    self = &progress;
    progress.min_interval_s = 0;
    JobContext ctx{scene, take, progress, events, 1, resume};
    nlohmann::json metrics;
    try {
      metrics = smoke_run_job(ctx);
      take.finish("done");
    } catch (const CancelledError&) {
      take.finish("cancelled");
    }
    return metrics;
  };
  run(tmp.dir / "reference", false, -1);
  EXPECT_TRUE(run(tmp.dir / "killed", false, 14).is_null());
  const nlohmann::json resumed = run(tmp.dir / "killed", true, -1);
  std::fclose(null_out);
  EXPECT_EQ(resumed["resumed_from_frame"], 10);
  TakeReader ref(tmp.dir / "reference"), got(tmp.dir / "killed");
  ASSERT_EQ(ref.frame_count(), 26u);
  ASSERT_EQ(got.frame_count(), 26u);
  for (size_t n = 0; n < 26; ++n) {
    const Record a = ref.read_frame_at(n), b = got.read_frame_at(n);
    ASSERT_EQ(a.index, b.index);
    EXPECT_EQ(a.find("density")->data, b.find("density")->data) << "frame " << n;
    EXPECT_EQ(a.find("velocity")->data, b.find("velocity")->data) << "frame " << n;
  }
  Record cp;
  ASSERT_TRUE(ref.latest(RecordKind::Checkpoint, &cp));
  EXPECT_EQ(cp.index, 20);
}

}  // namespace
}  // namespace pliant::smoke
