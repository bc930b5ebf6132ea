#include "pliant/liquid/problem_generator.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pliant::liquid
