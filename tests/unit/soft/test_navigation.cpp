// Navigation: the turn objective measures yaw rate; a gait primitive of a straight
// gait has no yaw; the cached gaits of soft_navigate.json reach the goal around the
// obstacle in re-simulation. Without OMPL a "navigation" scene is an InputError.
// (The RRT* route: test_navigation_rrt.cpp.)
#include <gtest/gtest.h>

#include <cmath>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;
using namespace pliant::soft;

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

// Re-simulates the whole plan (about 23 s of spider walking): label slow. The
// spider ends well inside the goal disc and its COM never enters an obstacle.
TEST(NavigationSlow, CachedGaitsPlanAroundTheObstacle) {
  if (!navigation_available()) GTEST_SKIP() << "built without OMPL";
  SoftModel m = soft_compile(load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/soft_navigate.json"));
  soft_bind(m);
  const NavSettings& nav = m.navigation;
  ASSERT_TRUE(nav.enabled);
  ASSERT_EQ(nav.cached_theta.size(), 3u) << "soft_navigate.json should carry its optimized gaits";
  std::vector<Gait> gaits;
  for (int k = 0; k < 3; ++k) gaits.push_back(measure_gait(m.problem, "g", nav.cached_theta[k], nav.body_axis));
  EXPECT_GT(gaits[0].forward_m, 0.02);  // forward walks forward
  EXPECT_GT(gaits[1].yaw_rad, 0.05);    // left turns left
  EXPECT_LT(gaits[2].yaw_rad, -0.05);   // right (the mirrored left gait) turns right
  Eigen::VectorXd mirrored;
  ASSERT_TRUE(mirror_gait(m.problem, nav.cached_theta[1], &mirrored));
  EXPECT_LT((mirrored - nav.cached_theta[2]).norm(), 1e-4 * mirrored.norm());
  // The period after a switch is not the held gait (the executor's lattice has these
  // transition primitives as edges): right after forward a turning gait turns the
  // same way but less than held (the DMP activations lag the parameters).
  const std::vector<Eigen::Vector3d> tr = transition_primitives(m.problem, gaits, nav.body_axis);
  ASSERT_EQ(tr.size(), 9u);
  for (int k = 1; k < 3; ++k) {
    EXPECT_GT(tr[size_t(k)][2] * gaits[size_t(k)].yaw_rad, 0.0) << "gait " << k;
    EXPECT_LT(std::abs(tr[size_t(k)][2]), 0.8 * std::abs(gaits[size_t(k)].yaw_rad)) << "gait " << k;
  }
  const NavResult r = navigate(m.problem, gaits, nav);
  ASSERT_FALSE(r.planned.empty());
  EXPECT_LE((r.planned.back().head<2>() - nav.goal_m).norm(), nav.goal_tolerance_m);
  EXPECT_GT(r.min_clearance_m, 0.0);  // the COM never entered an obstacle's footprint
  // Closed loop on the re-simulated body: the COM ends well inside the goal
  // tolerance (the executor aims for half of it; 0.100 m measured for 0.2, where
  // stopping at the disc's edge gave 0.198 m), not just at its edge.
  EXPECT_TRUE(r.reached) << "ended " << r.final_distance_m << " m from the goal after " << r.com.size() << " frames";
  EXPECT_LE(r.final_distance_m, 0.75 * nav.goal_tolerance_m);
  for (const Eigen::Vector3d& c : r.com)
    for (const NavObstacle& o : nav.obstacles) ASSERT_GT((Eigen::Vector2d(c[0], c[2]) - o.center_m).norm(), o.radius_m);
  std::printf("navigation: final distance %.3f m, %zu frames, min clearance %.3f m, %d primitive updates\n",
              r.final_distance_m, r.com.size(), r.min_clearance_m, r.primitive_updates);
}
