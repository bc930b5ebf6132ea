// Navigation route: RRT* (OMPL) ends in the goal disc without touching the inflated
// obstacles. Without OMPL the test skips.
#include <gtest/gtest.h>

#include <cmath>

#include "pliant/soft/navigation.h"

using namespace pliant;
using namespace pliant::soft;

TEST(Navigation, RrtStarPathAvoidsObstaclesAndEndsAtGoal) {
  if (!navigation_available()) GTEST_SKIP() << "built without OMPL";
  NavSettings nav;
  nav.goal_m = {3, 0};
  nav.goal_tolerance_m = 0.2;
  nav.obstacles = {{{1.5, 0.0}, 0.5}};
  nav.planning_time_s = 0.5;
  const double rho = 0.4, inflate = 0.2;
  const auto path = plan_dubins_path({0, 0, 0}, nav, rho, inflate);
  ASSERT_GT(path.size(), 10u);
  EXPECT_LE((path.back().head<2>() - nav.goal_m).norm(), nav.goal_tolerance_m);
  double len = 0;
  for (size_t i = 0; i < path.size(); ++i) {
    EXPECT_GT((path[i].head<2>() - nav.obstacles[0].center_m).norm(), nav.obstacles[0].radius_m + inflate - 1e-6);
    if (i > 0) len += (path[i].head<2>() - path[i - 1].head<2>()).norm();
  }
  EXPECT_GT(len, 3.0);  // it had to go around
}
