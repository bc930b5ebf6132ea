// control_solve_lbfgs's chunks (control/control_lbfgs.cpp, ControlModel::lbfgs_chunk): the
// scene key is parsed and range-checked, the chunk length sets how many iterations run
// between checkpoints, and a run resumed from any chunk's checkpoint ends where the
// uninterrupted run ends. (Gradients: tests/unit/smoke_control.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
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

}  // namespace
}  // namespace pliant::smoke
