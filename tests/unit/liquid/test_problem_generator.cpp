#include "pliant/liquid/problem_generator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pliant::liquid {
namespace {

TEST(ProblemGenerator, FixedSeedIsReproducibleAndSplitIsHeldOut) {
  const TransferProblem a = generate_problem(7, 42), b = generate_problem(7, 42), c = generate_problem(7, 43);
  EXPECT_EQ(a.model.fill_fraction, b.model.fill_fraction);
  EXPECT_EQ(a.model.target.pose.position_m[0], b.model.target.pose.position_m[0]);
  EXPECT_NE(a.model.fill_fraction, c.model.fill_fraction);
  EXPECT_FALSE(a.held_out);
  const auto held = held_out_problems(10, 42);
  ASSERT_EQ(held.size(), 10u);
  for (const auto& p : held) EXPECT_TRUE(p.held_out);
}

TEST(ProblemGenerator, ProblemsAreValidScenes) {
  for (int id = 0; id < 20; ++id) {
    const LiquidModel m = generate_problem(id, 1).model;
    EXPECT_GE(m.source.shape.wall_m, m.cell_size_m);
    EXPECT_GT(m.target.pose.position_m[0] - m.target.shape.radius_m - m.target.shape.wall_m,
              m.source.pose.position_m[0] + m.source.shape.radius_m);  // target to the +x side, apart
    const LiquidState s = liquid_init(m);
    EXPECT_GT(s.count(), 100u) << id;
    EXPECT_DOUBLE_EQ(liquid_fractions(m, s)[2], 1.0) << id;  // all liquid starts in the source
  }
}

// TRANSFER+FOLLOW: the same draws as TRANSFER+ZERO plus a constant horizontal
// target velocity that keeps the whole target inside the domain for the run;
// the held-out split is the same ids in both families.
TEST(ProblemGenerator, FollowFamilyMovesTheTargetInsideTheDomain) {
  for (int id = 0; id < 40; ++id) {
    const TransferProblem z = generate_problem(id, 2026), f = generate_problem(id, 2026, 2, Family::Follow);
    EXPECT_EQ(z.family, "transfer_zero");
    EXPECT_EQ(f.family, "transfer_follow");
    EXPECT_EQ(z.held_out, f.held_out);
    EXPECT_FALSE(target_moves(z.model));
    EXPECT_EQ(z.model.fill_fraction, f.model.fill_fraction);
    EXPECT_EQ(z.model.target.pose.position_m[0], f.model.target.pose.position_m[0]);
    const double v = f.model.target_velocity_mps[0];
    EXPECT_GE(std::abs(v), 0.015) << id;
    EXPECT_LE(std::abs(v), 0.04) << id;
    EXPECT_EQ(f.model.target_velocity_mps[1], 0.0);
    const double end = f.model.frames * f.model.dt_s;
    const double reach = f.model.target.shape.radius_m + f.model.target.shape.wall_m;
    for (double t : {0.0, end}) {
      const double x = target_pose_at(f.model, t).position_m[0];
      EXPECT_GT(x - reach, f.model.source.pose.position_m[0] + f.model.source.shape.radius_m) << id;
      EXPECT_LT(x + reach, f.model.domain_max_m[0]) << id;
    }
  }
  for (const auto& p : held_out_problems(5, 2026, 2, Family::Follow)) {
    EXPECT_TRUE(p.held_out);
    EXPECT_TRUE(target_moves(p.model));
  }
}

}  // namespace
}  // namespace pliant::liquid
