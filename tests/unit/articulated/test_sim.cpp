#include <gtest/gtest.h>

#include <cmath>

#include "pliant/articulated/sim.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

// Period from upward zero crossings of the hinge angle.
double measure_period(const Model& m, Integrator integ, double dt, double theta0, double duration) {
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  State s = state_init(m);
  s.qpos[0] = theta0;
  SimWorkspace ws;
  std::vector<double> crossings;
  double prev = s.qpos[0], prev_t = 0;
  while (s.time < duration) {
    EXPECT_TRUE(sim_step(m, o, s, ws));
    const double cur = s.qpos[0];
    if (prev < 0 && cur >= 0) crossings.push_back(prev_t + dt * (-prev) / (cur - prev));
    prev = cur;
    prev_t = s.time;
  }
  EXPECT_GE(crossings.size(), 3u);
  return (crossings.back() - crossings.front()) / (crossings.size() - 1);
}

TEST(Sim, PendulumSmallAnglePeriodWithinOnePercent) {
  const double length = 1.0, g = 9.81;
  const Model m = test::pendulum(length);
  const double inertia = 1.0 * length * length + 1e-6;
  const double analytic = 2 * M_PI * std::sqrt(inertia / (1.0 * g * length));
  for (Integrator integ : {Integrator::Pbad2, Integrator::Pbad3, Integrator::Euler, Integrator::Rk4}) {
    const double t = measure_period(m, integ, 0.01, 0.05, 12);
    EXPECT_NEAR(t / analytic, 1.0, 0.01) << integrator_name(integ);
  }
}

// Chain hanging 30 degrees from vertical, swinging in 3D. (Released from horizontal
// the chain whips; PBAD's numerical damping then loses much more: bench_articulated.)
double chain_drift(int links, Integrator integ, double dt, double duration) {
  const Model m = model_from_mjcf(chain_mjcf(links), "chain.xml");
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  State s = state_init(m);
  s.qpos[0] = 1.3;  // about y: from along +x towards -z
  s.qvel[1] = 0.3;  // root swings sideways too: a 3D motion
  SimWorkspace ws;
  const double e0 = state_energy(m, o, s, ws).total;
  // Normalised by the potential energy range: straight horizontal to hanging.
  double mass = 0;
  for (const Body& b : m.bodies) mass += b.mass;
  const double range = mass / links * 9.81 * 0.1 * links * links / 2.0;
  double drift = 0;
  while (s.time < duration - 1e-9) {
    if (!sim_step(m, o, s, ws)) return 1e9;
    drift = std::max(drift, std::abs(state_energy(m, o, s, ws).total - e0));
  }
  return drift / range;
}

TEST(Sim, Pbad3TenLinkChainDriftBelowOnePercent) {
  const double drift = chain_drift(10, Integrator::Pbad3, 0.01, 10.0);
  EXPECT_LT(drift, 0.01);
}

TEST(Sim, Rk4ConservesEnergyAtSmallStep) {
  EXPECT_LT(chain_drift(3, Integrator::Rk4, 0.001, 1.0), 1e-4);
}

TEST(Sim, PbadStableAtLargeStep) {
  // Fully implicit: dissipates rather than blowing up at dt = 0.1.
  const Model m = model_from_mjcf(chain_mjcf(10), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad2;
  o.dt = 0.1;
  State s = state_init(m);
  SimWorkspace ws;
  const double e0 = state_energy(m, o, s, ws).total;
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  EXPECT_LE(state_energy(m, o, s, ws).total, e0 + 1e-6);
}

TEST(Sim, LevenbergMarquardtReachesStationarity) {
  const Model m = model_from_mjcf(chain_mjcf(5), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.02;
  State s = state_init(m);
  SimWorkspace ws;
  StepInfo info;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(sim_step(m, o, s, ws, &info));
  EXPECT_TRUE(info.converged);
  EXPECT_LT(info.energy_residual, 1e-6);
}

VecX run_chain(const Model& m, Integrator integ, double dt, double duration) {
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  o.lm_tolerance = 1e-12;
  State s = state_init(m);
  SimWorkspace ws;
  const int n = static_cast<int>(std::llround(duration / dt));
  for (int i = 0; i < n; ++i) EXPECT_TRUE(sim_step(m, o, s, ws));
  return s.qpos;
}

TEST(Sim, Pbad3IsSecondOrderPbad2FirstOrder) {
  // Global error against an RK4 reference: halving dt divides it by ~4 (pbad3), ~2 (pbad2).
  const Model m = model_from_mjcf(chain_mjcf(3), "chain.xml");
  const VecX ref = run_chain(m, Integrator::Rk4, 1e-4, 0.2);
  const double e3a = (run_chain(m, Integrator::Pbad3, 0.004, 0.2) - ref).norm();
  const double e3b = (run_chain(m, Integrator::Pbad3, 0.002, 0.2) - ref).norm();
  const double e2a = (run_chain(m, Integrator::Pbad2, 0.004, 0.2) - ref).norm();
  const double e2b = (run_chain(m, Integrator::Pbad2, 0.002, 0.2) - ref).norm();
  EXPECT_GT(e3a / e3b, 3.3);
  EXPECT_LT(e3a / e3b, 4.8);
  EXPECT_GT(e2a / e2b, 1.6);
  EXPECT_LT(e2a / e2b, 2.5);
}

TEST(Sim, LbfgsSolverReachesTheLevenbergMarquardtSolution) {
  const Model m = model_from_mjcf(chain_mjcf(8), "chain.xml");
  SimOptions lm, lb;
  lm.integrator = lb.integrator = Integrator::Pbad3;
  lm.dt = lb.dt = 0.02;
  lm.lm_tolerance = lb.lm_tolerance = 1e-10;
  lb.solver = Solver::Lbfgs;
  State a = state_init(m), b = a;
  a.qpos[0] = b.qpos[0] = 1.0;
  SimWorkspace wa, wb;
  StepInfo ib;
  for (int i = 0; i < 5; ++i) {  // few steps: the swinging chain is chaotic
    ASSERT_TRUE(sim_step(m, lm, a, wa));
    ASSERT_TRUE(sim_step(m, lb, b, wb, &ib));
  }
  EXPECT_LT((a.qpos - b.qpos).norm(), 1e-5);
  EXPECT_LT(ib.energy_residual, 1e-7);
}

}  // namespace
}  // namespace pliant::articulated
