// Explicit baselines (explicit_integrators.cpp); Euler's period and joint limits are
// checked with the PBAD family in test_sim.cpp and test_joint_limits.cpp.
#include <gtest/gtest.h>

#include "pliant/articulated/sim.h"
#include "sim_fixture.h"

namespace pliant::articulated {
namespace {

TEST(Sim, Rk4ConservesEnergyAtSmallStep) {
  EXPECT_LT(test::chain_drift(3, Integrator::Rk4, 0.001, 1.0), 1e-4);
}

}  // namespace
}  // namespace pliant::articulated
