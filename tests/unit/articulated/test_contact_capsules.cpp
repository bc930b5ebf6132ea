// Contact: capsule against capsule (parallel axes, continuity through parallel).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"
#include "pair_fixture.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

using namespace pair_test;

// A free capsule dropped slightly tilted (3 degrees) on a fixed one, axes parallel in
// plan, offset along them: the overlap's two end spheres (x = -0.06 and 0.1) carry its
// weight as a beam on two supports (3/8 and 5/8 of m g, centre at x = 0.04), so it
// rests at the penalty's static tilt (F2 - F1) / (k span). The one contact at the
// middle of the overlap held it on the kink of an energy V-shaped in the tilt (exactly
// level, 1.98 LM iterations per step here against 1.34).
TEST(Contact, CapsuleOnAParallelCapsuleRestsOnTwoContacts) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody>
    <body name="low"><geom type="capsule" size="0.02 0.1" euler="0 90 0"/></body>
    <body name="up" pos="0.04 0 0.0458" euler="0 87 0"><freejoint/><geom type="capsule" size="0.02 0.1" mass="0.5"/></body>
    </worldbody></mujoco>)", "capsules.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  double iterations = 0;
  for (int i = 0; i < 100; ++i) {
    StepInfo info;
    ASSERT_TRUE(sim_step(m, o, s, ws, &info));
    iterations += info.iterations;
  }
  Kinematics k;
  kinematics(m, s.qpos, &k);
  const double tilt = std::asin(std::abs(k.xmat[2].col(2).z()));  // axis against the horizontal
  const double expect = (0.625 - 0.375) * 0.5 * 9.81 / (o.contact.stiffness * 0.16);
  const std::vector<PairContact> c = pair_contacts_at(m, s.qpos);
  std::printf("capsule on a parallel capsule: %zu contacts, tilt %.4g rad (beam on two supports %.4g), %.2f LM iterations per step\n",
              c.size(), tilt, expect, iterations / 100);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(tilt / expect, 1.0, 0.05);
  EXPECT_NEAR((c[0].depth + c[1].depth) * o.contact.stiffness / (0.5 * 9.81), 1.0, 0.01);
  EXPECT_LT(s.qvel.lpNorm<Eigen::Infinity>(), 1e-2);
}

// Energy of two capsules continuous as the upper one turns through parallel and its
// crossing point slides off the lower one's end (the contact rule switches there), and
// the gradient still matches finite differences for a crossing with an end sphere in
// reach (closest-point contact plus end spheres but the deepest).
TEST(Contact, CapsuleCapsuleEnergyIsContinuousThroughParallel) {
  const auto energy_at = [](double yaw, double shift) {
    const Model m = model_from_mjcf("<mujoco><worldbody><body name=\"low\"><geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 0\"/></body>"
                                    "<body name=\"up\" pos=\"" + std::to_string(shift) + " 0 0.039\" euler=\"0 0 " +
                                        std::to_string(yaw) + "\"><freejoint/><geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 0\"/></body>"
                                    "</worldbody></mujoco>", "capsules.xml");
    double e = 0;
    for (const PairContact& c : pair_contacts_at(m, state_init(m).qpos)) e += c.depth * c.depth;
    return e;
  };
  double worst = 0;
  for (double shift : {0.04, 0.19}) {
    double prev = energy_at(-2, shift);
    for (int i = 1; i <= 400; ++i) {  // yaw -2 .. 2 degrees, 0.01 degree steps
      const double e = energy_at(-2 + 0.01 * i, shift);
      worst = std::max(worst, std::abs(e - prev) / std::max(e, prev));
      prev = e;
    }
  }
  std::printf("capsule pair energy: largest relative change per 0.01 degree %.3g\n", worst);
  EXPECT_LT(worst, 0.02);
  EXPECT_GE(expect_pair_derivatives(two_bodies("0 0 0", "<geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 0\"/>",
                                               "0.07 0.01 0.038", "<geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 40\"/>")),
            2u);
}

}  // namespace
}  // namespace pliant::articulated
