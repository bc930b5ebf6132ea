#include <gtest/gtest.h>

#include "pliant/articulated/io.h"
#include "pliant/articulated/mpc.h"

namespace pliant::articulated {
namespace {

TEST(Batch, InterleavedIterationsGiveTheSequentialResult) {
  const Model m = model_from_mjcf(chain_mjcf(6), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.02;
  o.lm_relative_tolerance = 0;  // converge fully: several LM iterations per step
  std::vector<State> batch(5);
  for (int t = 0; t < 5; ++t) {
    batch[t] = state_init(m);
    batch[t].qpos[0] = 0.2 * t;  // different trajectories need different iteration counts
  }
  std::vector<State> seq = batch;
  const int passes = batch_rollout(m, o, batch, 8, 2);
  EXPECT_GT(passes, 8);  // more than one LM iteration per step (passes of the busiest worker)
  for (State& s : seq) {
    SimWorkspace ws;
    for (int i = 0; i < 8; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  }
  for (int t = 0; t < 5; ++t) {
    EXPECT_EQ(batch[t].step, 8);
    EXPECT_LT((batch[t].qpos - seq[t].qpos).norm(), 1e-12) << t;
  }
}

TEST(Batch, ExplicitIntegratorsStepOncePerPass) {
  const Model m = model_from_mjcf(chain_mjcf(3), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Rk4;
  o.dt = 0.001;
  std::vector<State> batch(3, state_init(m));
  EXPECT_EQ(batch_rollout(m, o, batch, 4, 1), 4);
  EXPECT_NEAR(batch[2].time, 0.004, 1e-12);
}

}  // namespace
}  // namespace pliant::articulated
