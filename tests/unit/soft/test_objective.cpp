// Objectives through full rollouts: the T-shape optimized for a jump reaches at
// least 90% of the target height when re-simulated; residuals have a fixed size;
// partial keyframes vanish when the target is the rest pose.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;
using namespace pliant::soft;

namespace {
Scene t_scene(const std::string& objectives, const std::string& optimizer) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "t_shape.obj", "resolution": 4, "modes": 6},
    "material": {"density_kg_per_m3": 1000, "young_pa": 1e5, "poisson": 0.3},
    "environment": {"type": "ground", "friction": 0.8},
    "simulation": {"dt_s": 0.025, "frames": 30},
    "controller": {"modes": 6, "kernels": 3, "period_s": 0.6, "max_activation_rel": 1.0},
    "objectives": )" + objectives + R"(, "optimizer": )" + optimizer + "}";
  return parse_scene(text, "t.json", std::string(PLIANT_ASSETS_DIR) + "/characters");
}
}  // namespace

TEST(Objective, TShapeReachesNinetyPercentOfTargetJump) {
  const double target = 0.03;
  SoftModel m = soft_compile(t_scene(R"({"jump": {"height_m": 0.03, "weight": 100}, "effort": {"weight": 1e-4}})",
                                     R"({"method": "hybrid", "iterations": 8, "horizon_frames": 24})"));
  soft_bind(m);
  // Stop once the smooth max is within 5% of the target (objective 100/2 (0.05 h)^2):
  // keeps the test short under sanitizers.
  m.optimizer.target = 0.5 * 100 * std::pow(0.05 * target, 2);
  OptimizerState st;
  st.theta = initial_theta(m.problem);
  const double before = max_height_gain(m.problem, st.theta, m.frames);
  optimize([&](const Eigen::VectorXd& th) { return residuals(m.problem, th); }, m.optimizer, st);
  for (size_t i = 1; i < st.history.size(); ++i) EXPECT_LE(st.history[i], st.history[i - 1]);
  // Independent re-simulation over the whole take, not the optimizer's numbers.
  const double after = max_height_gain(m.problem, st.theta, m.frames);
  EXPECT_LT(before, 0.2 * target);
  EXPECT_GE(after, 0.9 * target);
}

TEST(Objective, ResidualSizeAndKeyframesAtRest) {
  SoftModel m = soft_compile(t_scene(
      R"({"keyframes": {"weight": 1, "frames": [{"frame": 2, "vertices": [0, 3, 5]}]},
          "velocity": {"target_m_per_s": [0, 0, 0], "weight": 1}, "effort": {"weight": 0}})",
      R"({"method": "none", "horizon_frames": 2})"));
  soft_bind(m);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m.problem.dmp.parameters());
  const Eigen::VectorXd r = residuals(m.problem, zero);
  EXPECT_EQ(r.size(), 3 + 9 + zero.size());
  // No control, standing on the ground: vertices stay near the rest pose (they
  // sink by the penalty depth and the elastic sag only).
  EXPECT_LT(r.segment(3, 9).cwiseAbs().maxCoeff(), 0.01);
}

TEST(Objective, TrajectoryResidualsEqualRolloutResiduals) {
  // Every term on, keyframes listed out of frame order, a short rollout.
  SoftModel m = soft_compile(t_scene(
      R"({"keyframes": {"weight": 2, "frames": [{"frame": 3, "vertices": [1, 2]}, {"frame": 2, "vertices": [0]}]},
          "velocity": {"target_m_per_s": [0.1, 0, 0], "weight": 1},
          "position": {"target_m": [0.2, 0, 0], "weight": 1},
          "heading": {"body_axis": [1, 0, 0], "direction": [1, 0, 0], "weight": 1},
          "jump": {"height_m": 0.03, "weight": 3},
          "distance": {"distance_m": 0.5, "direction": [1, 0, 0], "weight": 1},
          "shuffle": {"weight": 1}, "effort": {"weight": 1e-3}})",
      R"({"method": "none", "horizon_frames": 4})"));
  soft_bind(m);
  m.problem.obj.w_turn = 1;
  m.problem.obj.turn_rate_rad_per_s = 0.3;
  const Eigen::VectorXd theta = 20 * initial_theta(m.problem);
  std::vector<SoftState> frames;
  simulate(m.problem, theta, m.problem.frames, [&](const SoftState& s) { frames.push_back(s); });
  ASSERT_EQ(int(frames.size()), 4);
  const Eigen::VectorXd r = residuals(m.problem, theta);
  const Eigen::VectorXd rt = trajectory_residuals(m.problem, frames, theta);
  ASSERT_EQ(r.size(), rt.size());
  EXPECT_EQ(r.size(), 3 + 3 + 3 + 1 + 1 + 2 + 4 + 9 + theta.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) EXPECT_DOUBLE_EQ(r[i], rt[i]) << "residual " << i;
  // A different trajectory gives different residuals (the frames are really read).
  frames[1].c += Eigen::Vector3d(0, 0.01, 0);
  EXPECT_GT((trajectory_residuals(m.problem, frames, theta) - r).norm(), 1e-4);
  frames.pop_back();
  EXPECT_THROW(trajectory_residuals(m.problem, frames, theta), std::invalid_argument);
}
