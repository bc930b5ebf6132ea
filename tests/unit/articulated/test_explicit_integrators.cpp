// Explicit baselines (explicit_integrators.cpp); Euler's period and joint limits are
// checked with the PBAD family in test_sim.cpp and test_joint_limits.cpp.
#include <gtest/gtest.h>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "sim_fixture.h"

namespace pliant::articulated {
namespace {

TEST(Sim, Rk4ConservesEnergyAtSmallStep) {
  EXPECT_LT(test::chain_drift(3, Integrator::Rk4, 0.001, 1.0), 1e-4);
}

// Body-body contact in the explicit integrators: two free spheres meet head-on in zero
// gravity (frictionless): equal and opposite forces keep the momentum, the elastic
// penalty returns the relative velocity reversed (RK4 at a small step).
TEST(Sim, ExplicitBodyContactBouncesAndKeepsMomentum) {
  const Model m = model_from_mjcf(R"(<mujoco><option gravity="0 0 0"/><worldbody>
    <body name="a"><freejoint/><geom size="0.05" mass="1"/></body>
    <body name="b" pos="0.12 0 0"><freejoint/><geom size="0.05" mass="2"/></body></worldbody></mujoco>)", "two.xml");
  for (Integrator integ : {Integrator::Rk4, Integrator::Euler}) {
    SimOptions o;
    o.integrator = integ;
    o.dt = 2e-4;
    o.contact.self_collision = true;
    o.contact.friction = FrictionModel::None;
    State s = state_init(m);
    s.qvel[0] = 1.0;
    SimWorkspace ws;
    for (int i = 0; i < 500; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
    const double p = s.qvel[0] + 2 * s.qvel[6];
    EXPECT_NEAR(p, 1.0, 1e-9);
    // Elastic: relative velocity reversed (-1), within the scheme's energy error.
    EXPECT_NEAR(s.qvel[0] - s.qvel[6], -1.0, integ == Integrator::Rk4 ? 1e-3 : 5e-2);
  }
}

}  // namespace
}  // namespace pliant::articulated
