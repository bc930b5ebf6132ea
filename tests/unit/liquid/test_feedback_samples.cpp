// Feedback samples: features and the samples cut from a full simulation.
#include <gtest/gtest.h>

#include "pliant/liquid/feedback.h"
#include "pliant/liquid/problem_generator.h"

namespace pliant::liquid {
namespace {

// A training problem tipped by a steady ramp for 0.8 s (liquid leaves).
LiquidModel ramp_problem() {
  LiquidModel m = generate_problem(1, 2026, 2).model;
  m.frames = 40;
  KeyPose end{0.8, m.source.pose};
  end.pose.tilt_rad = 1.9;
  end.pose.position_m[0] += 0.04;
  m.source_path.keys = {{0.0, m.source.pose}, end};
  return m;
}

TEST(FeedbackSamples, OutflowAccountsForTheLiquidThatLeft) {
  const LiquidModel m = ramp_problem();
  FeedbackContext c(m);
  LiquidState s = liquid_init(m);
  EXPECT_NEAR(source_volume_fraction(c, s), 1.0, 1e-12);
  SampleRecorder rec(c, s, 0.1);
  for (int f = 0; f < m.frames; ++f) {
    liquid_step(m, s);
    rec.record(s);
  }
  ASSERT_EQ(rec.samples().size(), 8u);  // 0.8 s in 0.1 s intervals
  double left = 0;
  int leaving = 0;
  for (const FeedbackSample& x : rec.samples()) left += x.outflow_rate * 0.1, leaving += x.leaving;
  ASSERT_GT(leaving, 20);
  // What left (summed over intervals) is what is no longer in the source, up to
  // particles sloshing back in and reseeding.
  EXPECT_NEAR(left, 1 - source_volume_fraction(c, s), 0.05);
  // The first interval starts at rest, upright, full: no outflow, tilt rate of the ramp.
  const FeedbackSample& first = rec.samples().front();
  EXPECT_EQ(first.leaving, 0);
  EXPECT_NEAR(first.x[0], 0.0, 1e-12);
  EXPECT_GT(first.x[1], 0.0);
  EXPECT_NEAR(first.x[4], 1.0, 1e-12);
  EXPECT_LT(first.x[5], 0.0);  // free surface below the lip
  EXPECT_EQ(first.x[12 + int(m.source.shape.type)], 1.0);
  // Exit velocity: liquid leaving a tipping container falls (relative vy < 0 on average).
  double vy = 0;
  for (const FeedbackSample& x : rec.samples()) vy += x.leaving * x.exit[3];
  EXPECT_LT(vy, 0.0);
}

TEST(FeedbackSamples, JsonRoundTripAndBadRows) {
  FeedbackSample a;
  for (int i = 0; i < kFeedbackFeatures; ++i) a.x[i] = 0.5 * i;
  a.outflow_rate = 0.25, a.leaving = 7, a.exit = {1, -2, 0.5, -0.25};
  const auto back = SampleRecorder::from_json(SampleRecorder::to_json({a, a}));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].x, a.x);
  EXPECT_EQ(back[1].leaving, 7);
  EXPECT_EQ(back[1].exit, a.exit);
  EXPECT_THROW(SampleRecorder::from_json({{"rows", {{1, 2, 3}}}}), std::runtime_error);
  EXPECT_THROW(SampleRecorder::from_json(nlohmann::json::array()), std::runtime_error);
}

}  // namespace
}  // namespace pliant::liquid
