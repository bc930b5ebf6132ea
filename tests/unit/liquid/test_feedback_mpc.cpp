// Feedback MPC: decisions are deterministic, the closed loop is reproducible
// from its recorded key poses.
#include <gtest/gtest.h>

#include "planners.h"
#include "pliant/liquid/feedback.h"
#include "pliant/liquid/problem_generator.h"

namespace pliant::liquid {
namespace {

// A fixed (untrained, seeded) predictor: the MPC's arithmetic, not its skill.
FeedbackPredictor fixed_net() {
  FeedbackPredictor p;
  p.flow = optim::Mlp({kFeedbackFeatures, 8, 8, 8, 1}, 3);
  p.exit = optim::Mlp({kFeedbackFeatures, 8, 8, 8, kFeedbackExitOutputs}, 4);
  p.x_mean = Eigen::VectorXd::Zero(kFeedbackFeatures);
  p.x_scale = Eigen::VectorXd::Ones(kFeedbackFeatures);
  p.flow_scale = 0.5;
  return p;
}

TEST(FeedbackMpc, DecisionIsDeterministic) {
  const LiquidModel m = generate_problem(2, 2026, 2).model;
  FeedbackContext c(m);
  const FeedbackPredictor net = fixed_net();
  const MpcSettings ms;
  Pose pose = m.source.pose;
  pose.tilt_rad = 0.7;
  const MpcAction committed{0.45, 0.02, 0};
  const MpcAction a = mpc_decide(c, net, ms, 0.6, pose, 0.8, committed);
  const MpcAction b = mpc_decide(c, net, ms, 0.6, pose, 0.8, committed);
  EXPECT_EQ(a.tilt_rate, b.tilt_rate);
  EXPECT_EQ(a.vx, b.vx);
  EXPECT_EQ(a.vy, b.vy);
  // The choice is one of the candidates.
  EXPECT_NE(std::find(ms.tilt_rates.begin(), ms.tilt_rates.end(), a.tilt_rate), ms.tilt_rates.end());
  EXPECT_NE(std::find(ms.speeds.begin(), ms.speeds.end(), a.vx), ms.speeds.end());
}

TEST(FeedbackMpc, StreamSpillAveragesOverTheStreamWidth) {
  MpcSettings ms;
  ms.spill_inner = 0.25, ms.spill_outer = 0.65, ms.stream_near = 0, ms.stream_far = 0;
  // Mean stream only: the ramp at the mean landing point.
  EXPECT_EQ(stream_spill(ms, 1.0, 0.5, 1.0, 0.1), 0.0);
  EXPECT_NEAR(stream_spill(ms, 1.045, 0.5, 1.0, 0.1), 0.5, 1e-12);
  EXPECT_EQ(stream_spill(ms, 0.9, 0.5, 1.0, 0.1), 1.0);
  // Width: mean on the centre, near edge 0.1 m short (1 inner radius): the
  // point at -0.1 m spills fully, the one at -0.05 m (0.5 radii) 0.625, the
  // mean none.
  ms.stream_near = 1.0;
  EXPECT_NEAR(stream_spill(ms, 1.0, 0.9, 1.0, 0.1), 1.625 / 5, 1e-12);
  ms.stream_near = 0.5;  // -0.025 m (none) and -0.05 m (0.625)
  EXPECT_NEAR(stream_spill(ms, 1.0, 0.9, 1.0, 0.1), 0.625 / 5, 1e-12);
  ms.stream_far = 1.0;   // +0.05 m (0.625) and +0.1 m (full) beyond the mean
  EXPECT_NEAR(stream_spill(ms, 1.0, 0.9, 1.0, 0.1), 2.25 / 5, 1e-12);
  // A near edge on the mean: no width, the mean's ramp.
  EXPECT_NEAR(stream_spill(ms, 1.045, 1.045, 1.0, 0.1), 0.5, 1e-12);
}

TEST(FeedbackMpc, SettingsByName) {
  MpcSettings ms;
  EXPECT_TRUE(set_mpc_setting(ms, "stream_near", 0.5));
  EXPECT_EQ(ms.stream_near, 0.5);
  EXPECT_TRUE(set_mpc_setting(ms, "horizon", 6));
  EXPECT_EQ(ms.horizon, 6);
  EXPECT_TRUE(set_mpc_setting(ms, "bottle_stream_width", 1));
  EXPECT_TRUE(ms.bottle_stream_width);
  EXPECT_FALSE(set_mpc_setting(ms, "stream_nearr", 1));
}

TEST(FeedbackMpc, StopRuleTurnsUprightAfterThePourTime) {
  const LiquidModel m = generate_problem(2, 2026, 2).model;  // ZERO: static target
  FeedbackContext c(m);
  const FeedbackPredictor net = fixed_net();
  MpcSettings ms;
  Pose pose = m.source.pose;
  pose.tilt_rad = 1.9;
  const MpcAction committed{0.45, 0.06, 0};
  const double t = ms.stop_at * m.planner.pour_time_s;
  // Before the stop time: one of the (non-negative) candidate tilt rates.
  EXPECT_GE(mpc_decide(c, net, ms, t - 0.2, pose, 0.3, committed).tilt_rate, 0.0);
  // From the stop time on: back upright, position held.
  const MpcAction a = mpc_decide(c, net, ms, t, pose, 0.3, committed);
  EXPECT_EQ(a.tilt_rate, -ms.stop_tilt_rate);
  EXPECT_EQ(a.vx, 0.0);
  EXPECT_EQ(a.vy, 0.0);
  // Off: the MPC keeps choosing among its candidates.
  ms.stop_at = 0;
  EXPECT_GE(mpc_decide(c, net, ms, t, pose, 0.3, committed).tilt_rate, 0.0);
  EXPECT_TRUE(set_mpc_setting(ms, "stop_at", 0.9));
  EXPECT_EQ(ms.stop_at, 0.9);
}

TEST(FeedbackMpc, ClosedLoopIsReproducedByItsKeyPoses) {
  LiquidModel m = generate_problem(3, 2026, 2).model;
  m.frames = 30;
  int frames = 0;
  const FeedbackRun run = run_feedback(m, fixed_net(), MpcSettings{}, liquid_init(m), {},
                                       [&](const LiquidModel&, const LiquidState&) { ++frames; });
  EXPECT_EQ(frames, 30);
  EXPECT_EQ(run.mpc_steps, 6);
  EXPECT_GE(run.mpc_step_ms_max, run.mpc_step_ms_mean);
  // Replaying the recorded path gives the same final particles (up to the
  // rounding of frame times that land on a key time).
  m.source_path = run.path;
  LiquidState s = liquid_init(m);
  for (int f = 0; f < m.frames; ++f) liquid_step(m, s);
  ASSERT_EQ(s.x.size(), run.final_state.x.size());
  for (size_t i = 0; i < s.x.size(); ++i) ASSERT_NEAR(s.x[i], run.final_state.x[i], 1e-4) << i;
}

}  // namespace
}  // namespace pliant::liquid
