// --resume of the soft job continues exactly as the uninterrupted run: a take cut
// after iteration k's checkpoint (what kill -9 leaves) resumed to N ends with the
// same objective history, rollout count, step kinds and frames (bit for bit) as the
// run of N, for the hybrid (Broyden reuse), the hybrid with fused trials and a trust
// region, pure L-BFGS (its curvature pairs) and a hybrid that is in its L-BFGS phase
// when it stops (SoftJobResumeSlow). The editor's theta of a take is the one the job
// played back. A damaged checkpoint is an InputError naming the take; an old
// checkpoint (f32 theta and history, no "optimizer" blob) still resumes as before.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "pliant/core/blob_field.h"
#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#include "soft_test_scenes.h"

using namespace pliant;

namespace {

struct ResumeTempDir {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("pliant_soft_resume_" + std::to_string(::getpid()) + "_" + std::to_string(rand()));
  ~ResumeTempDir() { std::filesystem::remove_all(dir); }
};

nlohmann::json run_soft_job(const Scene& scene, const std::filesystem::path& dir, bool resume,
                            Progress::Sink sink = {}) {
  TakeWriter take = resume ? TakeWriter::reopen(dir) : TakeWriter::create(dir, Manifest{});
  Progress progress(std::move(sink));
  std::FILE* null_out = std::fopen("/dev/null", "w");
  JobEvents events(null_out);
  JobContext ctx{scene, take, progress, events, 1, resume};
  nlohmann::json m;
  try {
    m = soft::soft_run_job(ctx);
  } catch (...) {
    std::fclose(null_out);
    throw;
  }
  take.finish("done");
  std::fclose(null_out);
  return m;
}

bool job_bits_equal(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<uint64_t>(a[i]) != std::bit_cast<uint64_t>(b[i])) return false;
  return true;
}

// ck becomes the take's latest checkpoint (appended, the take closed).
void append_checkpoint(const std::filesystem::path& dir, const Record& ck) {
  TakeWriter w = TakeWriter::reopen(dir);
  w.append(ck);
  w.finish("done");
}

// ck's blob field `name` cut to half its length, or one bit of it flipped. False if
// ck has no such field.
bool damage_blob(Record& ck, const std::string& name, bool truncate) {
  for (Field& f : ck.fields) {
    if (f.name != name) continue;
    if (truncate) {
      f.data.resize(f.data.size() / 2);
      f.shape = {uint32_t(f.data.size())};
    } else {
      const uint32_t w = std::bit_cast<uint32_t>(f.data[f.data.size() / 2]);
      f.data[f.data.size() / 2] = std::bit_cast<float>(w ^ 0x100u);
    }
    return true;
  }
  return false;
}

bool job_bits_equal(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<uint32_t>(a[i]) != std::bit_cast<uint32_t>(b[i])) return false;
  return true;
}

// Every frame's vertices and COM agree bit for bit (the played theta is the same).
void expect_same_frames(const std::filesystem::path& a, const std::filesystem::path& b) {
  TakeReader ra(a), rb(b);
  ASSERT_EQ(ra.frame_count(), rb.frame_count());
  for (size_t n = 0; n < ra.frame_count(); ++n) {
    const Record fa = ra.read_frame_at(n), fb = rb.read_frame_at(n);
    EXPECT_TRUE(job_bits_equal(fa.find("vertices")->data, fb.find("vertices")->data)) << "frame " << n;
    EXPECT_TRUE(job_bits_equal(fa.find("com")->data, fb.find("com")->data)) << "frame " << n;
  }
}

// The worm crawl (resolution 6, 20 frames) with `optimizer` (JSON members).
Scene resume_worm(const std::string& optimizer, int iterations) {
  return soft::test::worm_crawl_scene("{" + optimizer + ", \"iterations\": " + std::to_string(iterations) + "}");
}

// The checkpoints of a take, in order.
std::vector<Record> checkpoints(const std::filesystem::path& dir) {
  TakeReader reader(dir);
  std::vector<Record> out;
  for (size_t i = 0; i < reader.record_count(); ++i)
    if (reader.record_kind(i) == RecordKind::Checkpoint) out.push_back(reader.read(i));
  return out;
}

// Runs `scene` uninterrupted; then makes the take a kill right after the checkpoint
// of iteration k would leave (that run's checkpoints 1..k; k from `pick`, given them
// all), resumes it and checks that it ends exactly as the uninterrupted run. Returns
// the uninterrupted run's metrics.
nlohmann::json expect_exact_resume(const Scene& scene, const std::function<int(const std::vector<Record>&)>& pick) {
  ResumeTempDir tmp;
  const nlohmann::json whole = run_soft_job(scene, tmp.dir / "whole", false);
  const std::vector<Record> cks = checkpoints(tmp.dir / "whole");
  const int k = pick(cks);
  EXPECT_TRUE(k >= 1 && k < whole["iterations"].get<int>()) << k;
  {
    TakeWriter killed = TakeWriter::create(tmp.dir / "parts", Manifest{});
    for (const Record& ck : cks)
      if (ck.index <= k) killed.append(ck);
  }  // status "running", as a killed job leaves it
  const nlohmann::json resumed = run_soft_job(scene, tmp.dir / "parts", true);
  EXPECT_EQ(resumed["iterations"], whole["iterations"]);
  const auto hw = whole["objective_history"].get<std::vector<double>>();
  const auto hr = resumed["objective_history"].get<std::vector<double>>();
  EXPECT_TRUE(job_bits_equal(hw, hr)) << "uninterrupted " << whole["objective_history"].dump() << "\nresumed       "
                                      << resumed["objective_history"].dump();
  EXPECT_EQ(resumed["rollouts"], whole["rollouts"]);
  EXPECT_EQ(resumed["step_kinds"], whole["step_kinds"]);
  // Spacetime's per-iteration blocks (merit, violation, DMP weight, ...) and steps.
  EXPECT_EQ(resumed.value("spacetime", nlohmann::json()), whole.value("spacetime", nlohmann::json()));
  expect_same_frames(tmp.dir / "whole", tmp.dir / "parts");
  // The last checkpoints' blobs (theta and all the carried state) agree bit for bit.
  Record lw, lr;
  EXPECT_TRUE(TakeReader(tmp.dir / "whole").latest(RecordKind::Checkpoint, &lw));
  EXPECT_TRUE(TakeReader(tmp.dir / "parts").latest(RecordKind::Checkpoint, &lr));
  for (const char* blob : {"optimizer", "spacetime"}) {
    EXPECT_EQ(lw.find(blob) != nullptr, lr.find(blob) != nullptr) << blob;
    if (lw.find(blob) && lr.find(blob)) {
      EXPECT_TRUE(job_bits_equal(lw.find(blob)->data, lr.find(blob)->data)) << blob;
    }
  }
  return whole;
}

std::function<int(const std::vector<Record>&)> at(int k) {
  return [k](const std::vector<Record>&) { return k; };
}

}  // namespace

TEST(SoftJobResume, HybridBroydenResumesExactly) {
  const nlohmann::json m = expect_exact_resume(resume_worm(R"("method": "hybrid")", 7), at(3));
  const auto kinds = m["step_kinds"].get<std::vector<std::string>>();
  // The resume point's carried state matters: a Broyden step right after it.
  EXPECT_NE(std::find(kinds.begin() + 3, kinds.end(), "lm-broyden"), kinds.end()) << m["step_kinds"].dump();
}

TEST(SoftJobResume, FusedTrustRegionResumesExactly) {
  expect_exact_resume(
      resume_worm(R"("method": "hybrid", "fused_trials": true, "lm_damping": "trust_region")", 7), at(3));
}

TEST(SoftJobResume, LbfgsResumesExactly) {
  const nlohmann::json m = expect_exact_resume(resume_worm(R"("method": "lbfgs")", 8), at(4));
  const auto kinds = m["step_kinds"].get<std::vector<std::string>>();
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "lbfgs"), 8) << m["step_kinds"].dump();
}

// The worm crawl's hybrid switches to L-BFGS after ~16 iterations: stopped after the
// second iteration of an L-BFGS phase (its previous point and gradient, and a
// curvature pair, are in the memory), the resumed run goes on with L-BFGS exactly.
// 28 iterations (1 s in Release): Release only (label unit_slow_no_asan, CMakeLists);
// test_optimizer_state.cpp checks the same case on Rosenbrock under ASan too.
TEST(SoftJobResumeSlow, HybridInsideItsLbfgsPhaseResumesExactly) {
  int k = -1;
  const nlohmann::json m = expect_exact_resume(resume_worm(R"("method": "hybrid")", 25), [&k](const auto& cks) {
    // optimizer_state [iteration, lambda, in_lbfgs, rollouts] after each iteration.
    for (size_t i = 1; i < cks.size() && k < 0; ++i)
      if (cks[i - 1].find("optimizer_state")->data[2] != 0 && cks[i].find("optimizer_state")->data[2] != 0)
        k = cks[i].index;
    return k;
  });
  ASSERT_GT(k, 0) << "no two L-BFGS iterations in a row: " << m["step_kinds"].dump();
  const auto kinds = m["step_kinds"].get<std::vector<std::string>>();
  ASSERT_LT(size_t(k), kinds.size());
  EXPECT_EQ(kinds[size_t(k) - 1], "lbfgs");
  EXPECT_EQ(kinds[size_t(k)], "lbfgs");  // the first resumed iteration uses the pairs
}

// A checkpoint whose "optimizer" blob is damaged or cut short: --resume is an
// InputError (exit code 2 from `pliant run`) naming the take and the problem.
TEST(SoftJobResume, DamagedOrTruncatedCheckpointIsAnInputErrorNamingTheTake) {
  for (const bool truncate : {false, true}) {
    SCOPED_TRACE(truncate ? "truncated" : "damaged");
    ResumeTempDir tmp;
    const std::filesystem::path dir = tmp.dir / "take";
    run_soft_job(resume_worm(R"("method": "hybrid")", 2), dir, false);
    Record ck;
    ASSERT_TRUE(TakeReader(dir).latest(RecordKind::Checkpoint, &ck));
    ASSERT_TRUE(damage_blob(ck, "optimizer", truncate));
    append_checkpoint(dir, ck);
    try {
      run_soft_job(resume_worm(R"("method": "hybrid")", 4), dir, true);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(dir.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(truncate ? "truncated" : "CRC mismatch"), std::string::npos) << msg;
      EXPECT_EQ(e.pointer(), "/optimizer");
    }
  }
}

// A checkpoint of the format before the "optimizer" blob (theta, objective_history
// in f32, optimizer_state [iteration, lambda, in_lbfgs, rollouts]) resumes as it
// always did: from the rounded theta with fresh optimizer memory, the same run as
// optimize() from that state.
TEST(SoftJobResume, OldFormatCheckpointStillResumes) {
  ResumeTempDir tmp;
  const std::filesystem::path dir = tmp.dir / "take";
  run_soft_job(resume_worm(R"("method": "hybrid")", 3), dir, false);
  Record ck;
  ASSERT_TRUE(TakeReader(dir).latest(RecordKind::Checkpoint, &ck));
  std::erase_if(ck.fields, [](const Field& f) { return f.name == "optimizer"; });
  append_checkpoint(dir, ck);
  const Scene scene = resume_worm(R"("method": "hybrid")", 6);
  const nlohmann::json m = run_soft_job(scene, dir, true);
  // What the job did before the blob existed, by hand.
  soft::SoftModel model = soft::soft_compile(scene);
  soft::soft_bind(model);
  soft::OptimizerState st;
  const Field* th = ck.find("theta");
  st.theta.resize(Eigen::Index(th->data.size()));
  for (size_t i = 0; i < th->data.size(); ++i) st.theta[Eigen::Index(i)] = th->data[i];
  for (float v : ck.find("objective_history")->data) st.history.push_back(v);
  const Field* os = ck.find("optimizer_state");
  st.iteration = int(os->data[0]);
  st.lambda = os->data[1];
  st.in_lbfgs = os->data[2] != 0;
  st.evaluations = int(os->data[3]);
  EXPECT_EQ(st.iteration, 3);
  soft::soft_optimize(model, st);
  EXPECT_EQ(m["iterations"], 6);
  EXPECT_TRUE(job_bits_equal(m["objective_history"].get<std::vector<double>>(), st.history));
  EXPECT_EQ(m["rollouts"], st.evaluations);
  Eigen::VectorXd theta;
  ASSERT_TRUE(soft::soft_take_theta(dir.string(), model, &theta));
  EXPECT_EQ(theta, st.theta);
}

// The editor's theta of a finished take (soft_take_theta) is the one the job played:
// its playback reproduces the take's last frame bit for bit.
TEST(SoftJobResume, TakeThetaIsThePlayedBackTheta) {
  ResumeTempDir tmp;
  const Scene scene = resume_worm(R"("method": "hybrid")", 3);
  run_soft_job(scene, tmp.dir / "take", false);
  soft::SoftModel m = soft::soft_compile(scene);
  soft::soft_bind(m);
  Eigen::VectorXd theta;
  ASSERT_TRUE(soft::soft_take_theta((tmp.dir / "take").string(), m, &theta));
  soft::SoftPlayback pb = soft::soft_playback_start(m, theta);
  for (int f = 1; f < m.frames; ++f) soft::soft_playback_step(m, pb);
  TakeReader reader(tmp.dir / "take");
  const Record last = reader.read_frame_at(reader.frame_count() - 1);
  EXPECT_TRUE(job_bits_equal(soft::soft_frame_record(m, pb.state, last.index, false).find("vertices")->data,
                        last.find("vertices")->data));
}

// A scene changed beyond optimizer.iterations (here one more objective term, so a
// residual more): the checkpoint's theta and history are kept, its optimizer memory
// (residuals, J of the old objective) is dropped, and the run goes on from there.
TEST(SoftJobResume, ChangedSceneKeepsThetaAndDropsTheMemory) {
  ResumeTempDir tmp;
  const std::filesystem::path dir = tmp.dir / "take";
  const nlohmann::json first = run_soft_job(resume_worm(R"("method": "hybrid")", 3), dir, false);
  Scene changed = resume_worm(R"("method": "hybrid")", 5);
  changed.doc["objectives"]["heading"] = {{"body_axis", {1, 0, 0}}, {"direction", {1, 0, 0}}, {"weight", 1}};
  const nlohmann::json m = run_soft_job(changed, dir, true);
  EXPECT_EQ(m["iterations"], 5);
  const auto h0 = first["objective_history"].get<std::vector<double>>();
  const auto h = m["objective_history"].get<std::vector<double>>();
  ASSERT_EQ(h.size(), 6u);
  EXPECT_TRUE(job_bits_equal(std::vector<double>(h.begin(), h.begin() + 4), h0));
}

// Spacetime: killed after iteration 2, the resumed run continues from the
// checkpoint's "spacetime" blob (every frame's state, the activations, the DMP weight,
// lambda, the report so far), so its history, rollouts, per-iteration report and
// frames are the uninterrupted run's (before the blob it restarted the trajectory
// from theta's rollout at the initial DMP weight).
TEST(SoftJobResume, SpacetimeResumesExactly) {
  const nlohmann::json m = expect_exact_resume(resume_worm(R"("method": "spacetime")", 4), at(2));
  EXPECT_EQ(m["spacetime"]["merit"].size(), 5u);
}

// A damaged or cut-short "spacetime" blob is an InputError naming the take and the byte.
TEST(SoftJobResume, DamagedSpacetimeBlobIsAnInputErrorNamingTheTake) {
  ResumeTempDir tmp;
  const std::filesystem::path dir = tmp.dir / "take";
  run_soft_job(resume_worm(R"("method": "spacetime")", 1), dir, false);
  Record ck;
  ASSERT_TRUE(TakeReader(dir).latest(RecordKind::Checkpoint, &ck));
  for (const bool truncate : {false, true}) {
    SCOPED_TRACE(truncate ? "truncated" : "damaged");
    Record bad = ck;
    ASSERT_TRUE(damage_blob(bad, "spacetime", truncate));
    append_checkpoint(dir, bad);
    try {
      run_soft_job(resume_worm(R"("method": "spacetime")", 2), dir, true);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(dir.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(truncate ? "truncated" : "CRC mismatch"), std::string::npos) << msg;
      EXPECT_NE(msg.find("at byte"), std::string::npos) << msg;
    }
  }
}

// A spacetime checkpoint without the blob (older takes) resumes as before: from the
// "optimizer" state's theta, the trajectory rebuilt from its rollout.
TEST(SoftJobResume, SpacetimeCheckpointWithoutItsBlobResumesAsBefore) {
  ResumeTempDir tmp;
  const std::filesystem::path dir = tmp.dir / "take";
  run_soft_job(resume_worm(R"("method": "spacetime")", 1), dir, false);
  Record ck;
  ASSERT_TRUE(TakeReader(dir).latest(RecordKind::Checkpoint, &ck));
  std::erase_if(ck.fields, [](const Field& f) { return f.name == "spacetime"; });
  append_checkpoint(dir, ck);
  const Scene scene = resume_worm(R"("method": "spacetime")", 2);
  const nlohmann::json m = run_soft_job(scene, dir, true);
  soft::SoftModel model = soft::soft_compile(scene);
  soft::soft_bind(model);
  soft::OptimizerState st = soft::optimizer_state_deserialize(field_bytes(*ck.find("optimizer")));
  soft::spacetime_optimize(model.problem, model.spacetime, st);
  EXPECT_EQ(m["iterations"], 2);
  EXPECT_TRUE(job_bits_equal(m["objective_history"].get<std::vector<double>>(), st.history));
}

namespace {

// The worm with a short navigation task: forward and left gaits optimized (hybrid,
// `iterations` each; right is the left one mirrored), one controller period played.
Scene resume_navigation(int iterations) {
  Scene s = resume_worm(R"("method": "hybrid")", iterations);
  s.doc["navigation"] = {{"goal_m", {0.4, 0.0}},     {"goal_tolerance_m", 0.1}, {"planning_time_s", 0.05},
                         {"max_frames", 20},         {"speed_m_per_s", 0.05},  {"turn_rate_rad_per_s", 0.3}};
  return s;
}

// Iteration of a checkpoint's gait optimizer blob (-1: none, or the gait is done).
int gait_iteration(const Record& ck, const std::string& gait) {
  const Field* f = ck.find("gait_optimizer_" + gait);
  if (!f || ck.find("gait_theta_" + gait)) return -1;
  return soft::optimizer_state_deserialize(field_bytes(*f)).iteration;
}

}  // namespace

// Thrown by the progress sink once a navigation job's three gaits are done: the job
// stops there as if killed (its take then ends with the gaits' last checkpoint), so
// the tests skip the seconds the cost-to-go lattice of the plan takes.
namespace {
struct GaitsDone {};
void stop_after_gaits(const ProgressReport& r) {
  if (r.stage == "gaits" && r.iter == 3) throw GaitsDone{};
}
}  // namespace

// A navigation job killed inside the left gait's optimization (after its second of
// three iterations) continues that gait from its checkpoint ("gait_optimizer_left"),
// not from the start: the resumed run's first checkpoint of that gait is its third
// iteration, and the gaits' checkpoint at the end (thetas in f32 and f64, each
// gait's optimizer record: history, rollouts, step kinds) is the uninterrupted job's
// bit for bit. (The plan and frames follow from the gaits; RRT*'s time-limited
// planned_path may differ run to run.)
TEST(SoftJobResume, NavigationContinuesTheGaitItWasOptimizing) {
  if (!soft::navigation_available()) GTEST_SKIP() << "built without OMPL";
  const Scene scene = resume_navigation(3);
  ResumeTempDir tmp;
  EXPECT_THROW(run_soft_job(scene, tmp.dir / "whole", false, stop_after_gaits), GaitsDone);
  const std::vector<Record> cks = checkpoints(tmp.dir / "whole");
  size_t cut = cks.size();
  for (size_t i = 0; i < cks.size() && cut == cks.size(); ++i)
    if (gait_iteration(cks[i], "left") == 2) cut = i;
  ASSERT_LT(cut, cks.size()) << "no checkpoint inside the left gait's optimization";
  {
    TakeWriter killed = TakeWriter::create(tmp.dir / "parts", Manifest{});
    for (size_t i = 0; i <= cut; ++i) killed.append(cks[i]);
  }
  EXPECT_THROW(run_soft_job(scene, tmp.dir / "parts", true, stop_after_gaits), GaitsDone);
  const std::vector<Record> after = checkpoints(tmp.dir / "parts");
  int next = -1;  // the left gait's first iteration in the resumed run
  for (size_t i = cut + 1; i < after.size() && next < 0; ++i) next = gait_iteration(after[i], "left");
  EXPECT_EQ(next, 3);
  const Record& lw = cks.back();
  const Record& lr = after.back();
  ASSERT_EQ(lw.fields.size(), lr.fields.size());
  for (size_t i = 0; i < lw.fields.size(); ++i) {
    EXPECT_EQ(lw.fields[i].name, lr.fields[i].name);
    EXPECT_TRUE(job_bits_equal(lw.fields[i].data, lr.fields[i].data)) << lw.fields[i].name;
  }
  const Field* left = lw.find("gait_optimizer_left");
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(soft::optimizer_state_deserialize(field_bytes(*left)).iteration, 3);
}

// A navigation checkpoint whose gait optimizer blob is damaged: --resume is an
// InputError naming the take and the gait, before any work.
TEST(SoftJobResume, DamagedGaitBlobIsAnInputErrorNamingTheTake) {
  if (!soft::navigation_available()) GTEST_SKIP() << "built without OMPL";
  const Scene scene = resume_navigation(3);
  soft::SoftModel model = soft::soft_compile(scene);
  soft::OptimizerState st;
  st.theta = Eigen::VectorXd::Ones(model.problem.dmp.parameters());
  st.history = {1.0};
  Record ck;
  ck.kind = RecordKind::Checkpoint;
  ck.fields.push_back(bytes_field("gait_optimizer_forward", soft::optimizer_state_serialize(st)));
  ASSERT_TRUE(damage_blob(ck, "gait_optimizer_forward", false));
  ResumeTempDir tmp;
  {
    TakeWriter killed = TakeWriter::create(tmp.dir / "bad", Manifest{});
    killed.append(ck);
  }
  try {
    run_soft_job(scene, tmp.dir / "bad", true);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find((tmp.dir / "bad").string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("forward"), std::string::npos) << msg;
    EXPECT_NE(msg.find("CRC mismatch"), std::string::npos) << msg;
    EXPECT_NE(msg.find("at byte"), std::string::npos) << msg;
  }
}
