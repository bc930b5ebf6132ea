// control_solve_lbfgs's chunks (control/control_lbfgs.cpp, ControlModel::lbfgs_chunk): the
// scene key is parsed and range-checked, the chunk length sets how many iterations run
// between checkpoints, and a run resumed from any chunk's checkpoint ends where the
// uninterrupted run ends; the best-so-far objective trace (control_trace.h) is monotone,
// starts at the first evaluation and survives a checkpoint. (Gradients: tests/unit/smoke_control.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "control/control_trace.h"
#include "pliant/smoke/control.h"

namespace pliant::smoke {
namespace {

// 16^2 x 6, a circle moved sideways: tiny, but L-BFGS does not converge in 12 iterations.
Scene scene_with(const std::string& control_extra) {
  const std::string text = R"({"pliant": 1, "kind": "smoke",
    "grid": {"resolution": [16, 16], "cell_size_m": 0.0625}, "time": {"dt_s": 0.05, "frames": 6},
    "advection": "upwind",
    "control": {"method": "lbfgs", "r": 1e-5, "max_iterations": 12, "progressive_preview": false)" +
                           control_extra + R"(,
      "initial_density": [{"type": "circle", "center": [0.4, 0.5], "radius": 0.2}],
      "keyframes": [{"frame": 6, "target": {"type": "circle", "center": [0.6, 0.5], "radius": 0.2}}]}})";
  return parse_scene(text, "chunk.json");
}

TEST(ControlLbfgsChunk, SceneKeyIsParsedAndRangeChecked) {
  EXPECT_EQ(control_compile(scene_with("")).lbfgs_chunk, 20);  // the default
  EXPECT_EQ(control_compile(scene_with(R"(, "lbfgs_chunk": 100)")).lbfgs_chunk, 100);
  EXPECT_THROW(control_compile(scene_with(R"(, "lbfgs_chunk": 0)")), InputError);
  EXPECT_THROW(control_compile(scene_with(R"(, "lbfgs_chunk": 2.5)")), InputError);
}

// The ADMM schedule key of the same group (control_coarse_to_fine.cpp; its effect on the
// iteration counts: smoke_admm.Admm.CoarseOnlyScheduleRunsAdmmOnTheCoarseLevelsOnly).
TEST(ControlLbfgsChunk, CoarseAdmmLevelsKeyIsParsedAndRangeChecked) {
  EXPECT_EQ(control_compile(scene_with("")).coarse_admm_levels, -1);  // every coarse level
  EXPECT_EQ(control_compile(scene_with(R"(, "coarse_admm_levels": 1)")).coarse_admm_levels, 1);
  EXPECT_THROW(control_compile(scene_with(R"(, "coarse_admm_levels": -2)")), InputError);
  EXPECT_THROW(control_compile(scene_with(R"(, "coarse_admm_levels": true)")), InputError);
}

// Checkpoints (on_iteration) come once per chunk: never more than `chunk` iterations apart
// (a chunk ends early, counted as 1 iteration, when its first line search fails: the start
// from rest here), and 12 iterations in chunks of 4 checkpoint more often than in one chunk.
TEST(ControlLbfgsChunk, ChunkLengthSetsTheCheckpoints) {
  auto checkpoints = [](int chunk) {
    ControlModel m = control_compile(scene_with(""));
    m.lbfgs_chunk = chunk;
    ControlState s = control_init(m);
    Progress progress;
    std::vector<int> at;
    ControlCallbacks cb;
    cb.on_iteration = [&](const ControlState& st) { at.push_back(st.iteration); };
    control_solve_lbfgs(m, s, progress, cb);
    return at;
  };
  const std::vector<int> c4 = checkpoints(4), c12 = checkpoints(12);
  ASSERT_FALSE(c4.empty());
  ASSERT_FALSE(c12.empty());
  for (size_t i = 0; i < c4.size(); ++i) EXPECT_LE(c4[i] - (i ? c4[i - 1] : 0), 4) << "checkpoint " << i;
  for (size_t i = 0; i < c12.size(); ++i) EXPECT_LE(c12[i] - (i ? c12[i - 1] : 0), 12) << "checkpoint " << i;
  EXPECT_EQ(c4.back(), 12);
  EXPECT_EQ(c12.back(), 12);
  EXPECT_GE(c4.size(), 3u);
  EXPECT_LT(c12.size(), c4.size());
}

// A run resumed from the checkpoint before its last chunk ends bit-identically where the
// uninterrupted run ends (the chunk restarts its memory, the state holds everything else).
TEST(ControlLbfgsChunk, ResumeFromAChunkCheckpointMatches) {
  ControlModel m = control_compile(scene_with(R"(, "lbfgs_chunk": 6)"));
  Progress progress;
  std::vector<std::vector<uint8_t>> saved;
  ControlCallbacks cb;
  cb.on_iteration = [&](const ControlState& st) { saved.push_back(control_state_serialize(st)); };
  ControlState full = control_init(m);
  control_solve_lbfgs(m, full, progress, cb);
  ASSERT_GE(saved.size(), 2u);
  ControlState resumed = control_state_deserialize(saved[saved.size() - 2]);
  EXPECT_LT(resumed.iteration, 12);
  control_solve_lbfgs(m, resumed, progress, {});
  ASSERT_EQ(resumed.force.size(), full.force.size());
  for (size_t t = 0; t < full.force.size(); ++t) EXPECT_EQ(resumed.force[t], full.force[t]) << "frame " << t;
  EXPECT_EQ(resumed.objective_history, full.objective_history);
}

// A clock that ticks once per reading: deterministic trace times.
std::function<double()> trace_test_ticks() {
  auto n = std::make_shared<double>(0.0);
  return [n] { return *n += 1.0; };
}

void expect_trace_monotone(const std::vector<std::array<double, 2>>& t) {
  for (size_t i = 1; i < t.size(); ++i) {
    EXPECT_GE(t[i][0], t[i - 1][0]) << "point " << i;
    EXPECT_LT(t[i][1], t[i - 1][1]) << "point " << i;
  }
}

// L-BFGS: the trace starts at the first evaluation (the forces at rest), only falls, ends at
// the run's best objective, and a run resumed from a chunk's checkpoint keeps the
// checkpoint's trace and clock and ends at the same point as the uninterrupted run.
TEST(ControlLbfgsTrace, MonotoneFromTheFirstEvaluationAndResumable) {
  ControlModel m = control_compile(scene_with(R"(, "lbfgs_chunk": 6)"));
  const double E0 = control_objective(m, control_init(m).force, nullptr);
  Progress progress;
  std::vector<std::vector<uint8_t>> saved;
  ControlCallbacks cb;
  cb.clock = trace_test_ticks();
  cb.on_iteration = [&](const ControlState& st) { saved.push_back(control_state_serialize(st)); };
  ControlState full = control_init(m);
  control_solve_lbfgs(m, full, progress, cb);
  const auto& t = full.objective_trace;
  ASSERT_GE(t.size(), 3u);
  EXPECT_NEAR(t.front()[1], E0, 1e-12 * E0);
  EXPECT_EQ(t.front()[0], 1.0);  // one tick after the clock started
  expect_trace_monotone(t);
  EXPECT_EQ(t.back()[1], *std::min_element(full.objective_history.begin(), full.objective_history.end()));
  EXPECT_GE(full.trace_s, t.back()[0]);
  // Checkpoint round trip, then resume.
  ASSERT_GE(saved.size(), 2u);
  ControlState ck = control_state_deserialize(saved[saved.size() - 2]);
  ASSERT_FALSE(ck.objective_trace.empty());
  const std::vector<std::array<double, 2>> prefix(t.begin(), t.begin() + ck.objective_trace.size());
  EXPECT_EQ(ck.objective_trace, prefix);
  EXPECT_GT(ck.trace_s, 0.0);
  EXPECT_EQ(control_state_deserialize(control_state_serialize(full)).objective_trace, t);
  ControlState resumed = ck;
  ControlCallbacks rcb;
  rcb.clock = trace_test_ticks();
  control_solve_lbfgs(m, resumed, progress, rcb);
  expect_trace_monotone(resumed.objective_trace);
  ASSERT_GT(resumed.objective_trace.size(), ck.objective_trace.size());
  EXPECT_GT(resumed.objective_trace[ck.objective_trace.size()][0], ck.trace_s);
  EXPECT_EQ(resumed.objective_trace.back()[1], t.back()[1]);
  // A version 3 checkpoint (before the trace) still loads, with an empty trace.
  std::vector<uint8_t> v3 = saved.front();
  const ControlState first = control_state_deserialize(v3);
  v3.resize(v3.size() - 8 - 16 - 16 * first.objective_trace.size());  // version 5's admm_beta, the trace
  v3[4] = 3;
  const ControlState old = control_state_deserialize(v3);
  EXPECT_TRUE(old.objective_trace.empty());
  EXPECT_EQ(old.trace_s, 0.0);
  EXPECT_EQ(old.force, first.force);
  // A trace that rises is damage.
  ControlState bad = full;
  bad.objective_trace.push_back({bad.trace_s + 1, bad.objective_trace.back()[1] + 1});
  EXPECT_THROW(control_state_deserialize(control_state_serialize(bad)), std::runtime_error);
}

// ADMM: its starting forces and outer iterations are trace points, then the polish's
// evaluations; the trace ends at the best of all of them. Decimation keeps the ends.
TEST(ControlLbfgsTrace, AdmmIterationsAndPolishShareTheTrace) {
  ControlModel m = control_compile(scene_with(""));
  m.method = ControlMethod::Admm;
  m.max_iterations = 3;
  m.polish_iterations = 4;
  const double E0 = control_objective(m, control_init(m).force, nullptr);
  Progress progress;
  ControlCallbacks cb;
  cb.clock = trace_test_ticks();
  ControlState s = control_init(m);
  control_solve_admm(m, s, progress, cb);
  const auto& t = s.objective_trace;
  ASSERT_GE(t.size(), 2u);
  EXPECT_NEAR(t.front()[1], E0, 1e-12 * E0);
  expect_trace_monotone(t);
  double best = t.front()[1];
  for (double e : s.objective_history) best = std::min(best, e);
  EXPECT_EQ(t.back()[1], best);
  const auto d = control_detail::decimate_trace(t, 2);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d.front(), t.front());
  EXPECT_EQ(d.back(), t.back());
  EXPECT_EQ(control_detail::decimate_trace(t, 1000), t);
}

}  // namespace
}  // namespace pliant::smoke
