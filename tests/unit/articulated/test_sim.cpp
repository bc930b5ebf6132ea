// The integrator family through sim_step (sim.cpp): pendulum period, chain energy
// drift, the stencils' damping against linear theory, stability and order.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "pliant/articulated/sim.h"
#include "sim_fixture.h"
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
  for (Integrator integ : {Integrator::Pbad2, Integrator::Pbad3, Integrator::Pbad4, Integrator::Euler, Integrator::Rk4}) {
    const double t = measure_period(m, integ, 0.01, 0.05, 12);
    EXPECT_NEAR(t / analytic, 1.0, 0.01) << integrator_name(integ);
  }
}

TEST(Sim, Pbad3TenLinkChainDriftBelowOnePercent) {
  const double drift = test::chain_drift(10, Integrator::Pbad3, 0.01, 10.0);
  EXPECT_LT(drift, 0.01);
}

// Issue 6's bar: drift < 1% over 10 s at dt 0.05 on the 10-link chain. pbad4 measures
// 0.11% over 10 s (bench_articulated), pbad3 1.05%; over the first 2 s (the chain
// speeds up, the damping is fastest) pbad4 0.028%, pbad3 0.31%. The bound is the 1%
// target scaled to 2 s, and pbad4 must damp several times less than pbad3.
TEST(Sim, Pbad4TenLinkChainDriftAtLargeStep) {
  const double d4 = test::chain_drift(10, Integrator::Pbad4, 0.05, 2.0);
  const double d3 = test::chain_drift(10, Integrator::Pbad3, 0.05, 2.0);
  EXPECT_LT(d4, 0.01 * 2.0 / 10.0);
  EXPECT_LT(d4, d3 / 4) << d3;
}

// Energy of a small-angle pendulum lost in 10 s: the stencils' numerical damping per
// step on y'' = -w^2 y is O((w dt)^4) for pbad3 and O((w dt)^6) for pbad4 (the 4th
// difference cancels the former), so per unit time it falls as dt^3 and dt^5. The
// amplitude comes from the samples alone: q_k^2 - q_{k+1} q_{k-1} = A^2 sin^2(w dt) for
// any sampled sinusoid (no velocity estimate, no peak-sampling error).
double pendulum_energy_loss(Integrator integ, double dt) {
  const Model m = test::pendulum(1.0);
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  State s = state_init(m);
  s.qpos[0] = 0.02;
  SimWorkspace ws;
  const int n = static_cast<int>(std::llround(10.0 / dt));
  std::vector<double> q(n);
  for (int i = 0; i < n; ++i) {
    EXPECT_TRUE(sim_step(m, o, s, ws));
    q[i] = s.qpos[0];
  }
  auto invariant = [&](int k) { return q[k] * q[k] - q[k + 1] * q[k - 1]; };
  const int k0 = static_cast<int>(std::llround(0.5 / dt));  // start-up transients gone
  return 1 - invariant(n - 2) / invariant(k0);
}

// Linear theory of a stencil c_0 q_{i+1} + c_1 q_i + ... = -h^2 q_{i+1} (h = w dt): the
// energy kept per step is |z|^2 for the principal root z of (c_0 + h^2) z^k + c_1 z^{k-1}
// + ... + c_k (Newton's method from e^{ih}, the exact solution's factor).
double principal_root_modulus(const std::vector<double>& c, double h) {
  std::complex<double> z = std::polar(1.0, h);
  for (int it = 0; it < 50; ++it) {
    std::complex<double> p = 0, dp = 0;
    for (size_t j = 0; j < c.size(); ++j) {
      dp = dp * z + p;
      p = p * z + (c[j] + (j == 0 ? h * h : 0.0));
    }
    z -= p / dp;
  }
  return std::abs(z);
}

TEST(Sim, PendulumDampingMatchesTheStencilsLinearTheory) {
  const double omega = std::sqrt(9.81 / (1.0 + 1e-6));  // test::pendulum(1): m L^2 + 1e-6 armature
  const std::vector<double> c3 = {2, -5, 4, -1}, c4 = {2.5, -7, 7, -3, 0.5};
  double loss[2][2];
  for (int d = 0; d < 2; ++d) {
    const double dt = d == 0 ? 0.1 : 0.05;
    const int steps = static_cast<int>(std::llround(10.0 / dt)) - 2 - static_cast<int>(std::llround(0.5 / dt));
    for (int i = 0; i < 2; ++i) {
      const Integrator integ = i == 0 ? Integrator::Pbad3 : Integrator::Pbad4;
      const double predicted = 1 - std::pow(principal_root_modulus(i == 0 ? c3 : c4, omega * dt), 2 * steps);
      loss[i][d] = pendulum_energy_loss(integ, dt);
      EXPECT_NEAR(loss[i][d] / predicted, 1.0, 0.03) << integrator_name(integ) << " dt " << dt;
    }
  }
  // Halving dt: pbad3's loss rate falls ~2^3 (here 6.3 at w dt = 0.31), pbad4's ~2^5 (26).
  const double r3 = std::log(1 - loss[0][0]) / std::log(1 - loss[0][1]);
  const double r4 = std::log(1 - loss[1][0]) / std::log(1 - loss[1][1]);
  EXPECT_GT(r3, 5);
  EXPECT_LT(r3, 9);
  EXPECT_GT(r4, 20);
  EXPECT_LT(r4, 33);
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
  const double e4a = (run_chain(m, Integrator::Pbad4, 0.004, 0.2) - ref).norm();
  const double e4b = (run_chain(m, Integrator::Pbad4, 0.002, 0.2) - ref).norm();
  EXPECT_GT(e4a / e4b, 3.3) << "pbad4";
  EXPECT_LT(e4a / e4b, 4.8) << "pbad4";
}

}  // namespace
}  // namespace pliant::articulated
