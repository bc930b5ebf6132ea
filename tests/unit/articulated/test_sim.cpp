#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

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
  for (Integrator integ : {Integrator::Pbad2, Integrator::Pbad3, Integrator::Pbad4, Integrator::Euler, Integrator::Rk4}) {
    const double t = measure_period(m, integ, 0.01, 0.05, 12);
    EXPECT_NEAR(t / analytic, 1.0, 0.01) << integrator_name(integ);
  }
}

// Potential energy range of a chain of 0.1 m links: straight horizontal to hanging
// (drifts are normalised by it).
double chain_energy_range(const Model& m, int links) {
  double mass = 0;
  for (const Body& b : m.bodies) mass += b.mass;
  return mass / links * 9.81 * 0.1 * links * links / 2.0;
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
  const double range = chain_energy_range(m, links);
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

// Issue 6's bar: drift < 1% over 10 s at dt 0.05 on the 10-link chain. pbad4 measures
// 0.11% over 10 s (bench_articulated), pbad3 1.05%; over the first 2 s (the chain
// speeds up, the damping is fastest) pbad4 0.028%, pbad3 0.31%. The bound is the 1%
// target scaled to 2 s, and pbad4 must damp several times less than pbad3.
TEST(Sim, Pbad4TenLinkChainDriftAtLargeStep) {
  const double d4 = chain_drift(10, Integrator::Pbad4, 0.05, 2.0);
  const double d3 = chain_drift(10, Integrator::Pbad3, 0.05, 2.0);
  EXPECT_LT(d4, 0.01 * 2.0 / 10.0);
  EXPECT_LT(d4, d3 / 4) << d3;
}

// Kinetic energy of the body points' second-order backward differences over the
// frames q_{i+1}, q_i, q_{i-1}: independent of how joint angles parametrise the pose.
double body_point_kinetic_energy(const Model& m, const VecX& q0, const VecX& q1, const VecX& q2, double dt) {
  Kinematics k[3];
  kinematics(m, q0, &k[0]);
  kinematics(m, q1, &k[1]);
  kinematics(m, q2, &k[2]);
  double e = 0;
  for (size_t b = 1; b < m.bodies.size(); ++b) {
    const Body& body = m.bodies[b];
    const Mat3 second_moment = 0.5 * body.inertia.trace() * Mat3::Identity() - body.inertia;
    const Vec3 v = (3 * k[0].xcom[b] - 4 * k[1].xcom[b] + k[2].xcom[b]) / (2 * dt);
    const Mat3 rdot = (3 * k[0].xmat[b] - 4 * k[1].xmat[b] + k[2].xmat[b]) / (2 * dt);
    e += 0.5 * body.mass * v.squaredNorm() + 0.5 * (rdot * second_moment * rdot.transpose()).trace();
  }
  return e;
}

// A chain released horizontally (it whips when it swings down) until `until` s: the
// largest energy drift, the largest gap between the state's kinetic energy and the
// body points' own (from `mismatch_from` s on), and LM iterations per step.
struct WhipRun {
  double drift = 0, mismatch = 0, iterations_per_step = 0;
  bool ok = true;
  double failed_at = -1;
};

WhipRun run_whip(int links, Integrator integ, double dt, double until, double mismatch_from) {
  const Model m = model_from_mjcf(chain_mjcf(links), "chain.xml");
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  State s = state_init(m);
  s.qvel[1] = 0.5;
  SimWorkspace ws;
  const double range = chain_energy_range(m, links);
  const double e0 = state_energy(m, o, s, ws).total;
  std::vector<VecX> frames;  // q_{i+1}, q_i, q_{i-1}
  WhipRun r;
  int iterations = 0, steps = 0;
  while (s.time < until - 1e-9) {
    StepInfo info;
    if (!sim_step(m, o, s, ws, &info)) {
      r.ok = false;
      r.failed_at = s.time;
      return r;
    }
    iterations += info.iterations;
    ++steps;
    const Energy e = state_energy(m, o, s, ws);
    r.drift = std::max(r.drift, std::abs(e.total - e0) / range);
    frames.insert(frames.begin(), s.qpos);
    if (frames.size() > 3) frames.pop_back();
    if (frames.size() == 3 && s.time >= mismatch_from)
      r.mismatch = std::max(r.mismatch, std::abs(e.kinetic - body_point_kinetic_energy(m, frames[0], frames[1],
                                                                                       frames[2], o.dt)) / range);
  }
  r.iterations_per_step = static_cast<double>(iterations) / std::max(steps, 1);
  return r;
}


// The 100-link chain released horizontally cracks at t ~ 7.1 s: tip links turn by up
// to ~1 rad per 10 ms step and a link's two hinges pass near gimbal lock. At dt 0.01
// pbad3 used to fail there twice over: (1) the joint angles' difference quotient gave
// a velocity whose kinetic energy was up to 10x the body points' (1639 vs 152 J; the
// positions were fine): the state's velocity is now the mass-weighted fit to the body
// points' motion; (2) the quadratic predictor overshot to a step energy far above
// staying at q_i (404 vs -146 J), LM wandered for 30-50 iterations into other
// minimisers and the positions' energy blew up too (7x the range at t = 7.85 s): the
// step now starts from q_i when that is lower. Either fix alone fails this test.
TEST(Sim, HundredLinkWhipThroughItsCrackAtSmallStep) {
  const WhipRun r = run_whip(100, Integrator::Pbad3, 0.01, 7.9, 6.5);
  ASSERT_TRUE(r.ok) << r.failed_at;
  EXPECT_LT(r.drift, 0.3);
  EXPECT_LT(r.mismatch, 0.01);
}

// The velocity failure, cheaper (ASan pass): pbad4 in the 40-link whip at dt 0.05 was
// "unstable" last session (energy up by the range within 3-4 steps at the crack); the
// joint-space velocity was the cause, and the chain is bounded with the body-point one.
TEST(Sim, Pbad4FortyLinkWhipStaysBounded) {
  const WhipRun r = run_whip(40, Integrator::Pbad4, 0.05, 10.0, 0.0);
  ASSERT_TRUE(r.ok) << r.failed_at;
  EXPECT_LT(r.drift, 0.6);
  EXPECT_LT(r.mismatch, 0.01);
}

// The predictor check in isolation: a link on two hinges (y, z) whose past frames
// alternate between a pose R and its pi-flip about the link's axis ((a, b) ->
// (a + pi, pi - b), the whip's tip failure). The joint-space quadratic predictor
// extrapolates the flip once more, while the stencil's target rotation is nearest to R;
// the flipped pose is a stationary point that LM does not leave, so the step must start
// from q_i (lower step energy) to end near R.
TEST(Sim, StepStartsFromTheLastFrameWhenThePredictorIsWorse) {
  const Model m = model_from_mjcf(chain_mjcf(1), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  State s = state_init(m);
  const VecX q = s.qpos;  // (0, 0): pose R
  VecX flipped = q;
  flipped[0] += M_PI;
  flipped[1] = M_PI - flipped[1];
  s.qpos = q + VecX::Constant(2, 2 * M_PI);  // R again, after two flips in joint space
  s.past = {flipped, q};
  SimWorkspace ws;
  Kinematics k0, k1;
  kinematics(m, q, &k0);
  kinematics(m, flipped, &k1);
  ASSERT_NEAR(k1.xmat[1].col(0).dot(k0.xmat[1].col(0)), 1.0, 1e-9);   // same link axis (x)
  ASSERT_NEAR(k1.xmat[1].col(2).dot(k0.xmat[1].col(2)), -1.0, 1e-9);  // turned by pi about it
  ASSERT_TRUE(sim_step(m, o, s, ws));
  Kinematics k;
  kinematics(m, s.qpos, &k);
  EXPECT_GT(k.xmat[1].col(2).dot(k0.xmat[1].col(2)), 0.9);
}

// In the whip the Newton model at the predictor is often indefinite (compressed links).
// LM used to raise lambda until it was definite (1e-6 -> 1e-2) and then needed several
// accepted steps to get back below the final correction's 1e-4; it now takes the
// Gauss-Newton step there: 100-link whip at dt 0.05, 3.6 -> 2.5 iterations per step
// (cost 1.84x -> 1.33x of linear from 10 links), same drift.
TEST(Sim, IndefiniteNewtonModelTakesTheGaussNewtonStep) {
  const WhipRun r = run_whip(100, Integrator::Pbad3, 0.05, 8.0, 1e9);
  ASSERT_TRUE(r.ok) << r.failed_at;
  EXPECT_LT(r.iterations_per_step, 2.9);
  EXPECT_LT(r.drift, 0.3);
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
  o.lm_relative_tolerance = 0;  // only the absolute criteria
  State s = state_init(m);
  SimWorkspace ws;
  StepInfo info;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(sim_step(m, o, s, ws, &info));
  EXPECT_TRUE(info.converged);
  EXPECT_LT(info.energy_residual, 1e-6);
}

// Exact PBAD Hessian (Gauss-Newton + geometric blocks through tree_solve) against
// central differences of the gradient, on a chain (hinges) and on a hinge + slide model
// touching a plane; the tree solve with those blocks must invert the FD Hessian.
void expect_exact_hessian(const Model& m, State s, const SimOptions& o) {
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  VecX q = p.q;
  for (int i = 0; i < m.nv; ++i) q[i] += 0.05 * std::sin(1.7 * i + 0.3);  // off the minimiser
  const int n = m.nv;
  Eigen::MatrixXd hfd(n, n);
  const double eps = 1e-6;
  for (int i = 0; i < n; ++i) {
    VecX qp = q, qm = q;
    qp[i] += eps;
    qm[i] -= eps;
    pbad_evaluate(m, o, s, p, qp, ws);
    const VecX gp = ws.grad;
    pbad_evaluate(m, o, s, p, qm, ws);
    hfd.col(i) = (gp - ws.grad) / (2 * eps);
  }
  EXPECT_LT((hfd - hfd.transpose()).norm(), 1e-5 * hfd.norm());
  pbad_evaluate(m, o, s, p, q, ws);
  const VecX zero = VecX::Zero(n);
  Eigen::MatrixXd prod(n, n), prod_gn(n, n);
  for (int i = 0; i < n; ++i) {
    VecX x;
    tree_solve(m, ws.kin, ws.h_exact, zero, hfd.col(i), &x, &ws.tree);
    prod.col(i) = x;
    tree_solve(m, ws.kin, ws.h, zero, hfd.col(i), &x, &ws.tree);
    prod_gn.col(i) = x;
  }
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(n, n);
  EXPECT_LT((prod - id).norm(), 1e-5);
  EXPECT_GT((prod_gn - id).norm(), 1e-2);  // the geometric term is not negligible here
}

TEST(Sim, ExactHessianInvertsFiniteDifferenceHessian) {
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.05;
  const Model chain = model_from_mjcf(chain_mjcf(4), "chain.xml");
  State s = state_init(chain);
  s.qpos[0] = 1.3;
  s.qvel.setConstant(0.4);
  expect_exact_hessian(chain, s, o);
  const std::string xml = R"(<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
    <body pos="0 0 0.5"><joint type="slide" axis="0 0 1"/><joint type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 -0.3" size="0.05"/>
      <body pos="0.3 0 -0.3"><joint type="hinge" axis="1 0 0.2"/><geom type="sphere" size="0.05" pos="0 0.1 -0.1"/></body>
    </body></worldbody></mujoco>)";
  const Model legged = model_from_mjcf(xml, "legged.xml");
  State t = state_init(legged);
  t.qpos << -0.2, 0.3, 0.5;
  t.qvel << -1, 0.5, 2;
  o.contact.friction = FrictionModel::None;
  expect_exact_hessian(legged, t, o);
}

struct ChainRun {
  VecX qpos;
  double iterations = 0;
};

ChainRun run_tilted_chain(int links, double dt, int steps, bool exact, double relative_tolerance) {
  const Model m = model_from_mjcf(chain_mjcf(links), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = dt;
  o.exact_hessian = exact;
  o.lm_relative_tolerance = relative_tolerance;
  o.lm_tolerance = 1e-10;
  State s = state_init(m);
  s.qpos[0] = 1.3;
  s.qvel[1] = 0.3;
  SimWorkspace ws;
  ChainRun r;
  for (int i = 0; i < steps; ++i) {
    StepInfo info;
    EXPECT_TRUE(sim_step(m, o, s, ws, &info));
    r.iterations += info.iterations;
  }
  r.iterations /= steps;
  r.qpos = s.qpos;
  return r;
}

TEST(Sim, NewtonConvergesInFewIterationsWhereGaussNewtonCrawls) {
  // 40 links at dt 0.1: the chain's tension (geometric term) is several times M/dt^2.
  const ChainRun newton = run_tilted_chain(40, 0.1, 10, true, 0);
  const ChainRun gauss = run_tilted_chain(40, 0.1, 10, false, 0);
  EXPECT_LE(newton.iterations, 3.5) << gauss.iterations;
  EXPECT_GE(gauss.iterations, 3 * newton.iterations) << newton.iterations << " " << gauss.iterations;
  // (Gauss-Newton stops at the 50-iteration cap here, short of the minimiser.)
}

TEST(Sim, AccuracyAwareStopKeepsTheConvergedTrajectory) {
  // The solver error it leaves is a small fraction of the discretisation error.
  const ChainRun full = run_tilted_chain(10, 0.05, 60, true, 0);
  const ChainRun early = run_tilted_chain(10, 0.05, 60, true, 1e-2);
  const ChainRun half_step = run_tilted_chain(10, 0.025, 120, true, 0);
  const double solver_error = (early.qpos - full.qpos).lpNorm<Eigen::Infinity>();
  const double discretisation_error = (half_step.qpos - full.qpos).lpNorm<Eigen::Infinity>();
  EXPECT_LT(early.iterations, full.iterations - 0.5);
  EXPECT_LT(solver_error, 0.05 * discretisation_error) << discretisation_error;
}

TEST(Sim, JointRangeStopsThePendulumAtItsLimit) {
  // A pendulum thrown at 5 rad/s towards a 0.5 rad limit: it stops there (penetration
  // of the stiff penalty only) and bounces back.
  Model m = test::pendulum(1.0);
  m.joints[0].limited = true;
  m.joints[0].range_min = -0.5;
  m.joints[0].range_max = 0.5;
  for (Integrator integ : {Integrator::Pbad3, Integrator::Euler}) {
    SimOptions o;
    o.integrator = integ;
    o.dt = integ == Integrator::Euler ? 0.0005 : 0.005;
    o.contact.limit_stiffness = 1e5;
    State s = state_init(m);
    s.qvel[0] = 5;
    SimWorkspace ws;
    const double e0 = state_energy(m, o, s, ws).total;
    double qmax = 0;
    while (s.time < 0.5) {
      ASSERT_TRUE(sim_step(m, o, s, ws));
      qmax = std::max(qmax, s.qpos[0]);
    }
    EXPECT_GT(qmax, 0.5) << integrator_name(integ);
    EXPECT_LT(qmax, 0.5 + 0.03) << integrator_name(integ);  // free flight would reach 2.1 rad
    // Euler keeps the bounce's energy; PBAD's backward stencil damps the stiff
    // penalty mode (omega dt ~ 1.6 here) but never adds energy.
    const double e1 = state_energy(m, o, s, ws).total, kinetic0 = 12.5;
    if (integ == Integrator::Euler) EXPECT_NEAR(e1, e0, 0.05 * kinetic0);
    else EXPECT_LT(e1, e0 + 0.01 * kinetic0);
  }
}

TEST(Sim, BallJointConeStopsTheSwing) {
  // A ball-jointed pendulum thrown sideways at 4 rad/s with a 0.5 rad cone: the total
  // rotation angle stops at the cone (stiff penalty) instead of the free swing's ~1.4 rad.
  const Model free_model = model_from_mjcf(
      "<mujoco><worldbody><body><joint type=\"ball\"/><inertial pos=\"0 0 -1\" mass=\"1\" "
      "diaginertia=\"1e-4 1e-4 1e-4\"/></body></worldbody></mujoco>",
      "ball.xml");
  Model m = free_model;
  m.joints[0].limited = true;
  m.joints[0].range_max = 0.5;
  for (Integrator integ : {Integrator::Pbad3, Integrator::Euler}) {
    SimOptions o;
    o.integrator = integ;
    o.dt = integ == Integrator::Euler ? 0.0005 : 0.005;
    o.contact.limit_stiffness = 1e5;
    double amax = 0;
    for (const Model* model : {&free_model, static_cast<const Model*>(&m)}) {
      State s = state_init(*model);
      s.qvel << 3.2, 2.4, 0;  // local angular velocity, 4 rad/s about a tilted axis
      SimWorkspace ws;
      double angle = 0;
      while (s.time < 0.6) {
        ASSERT_TRUE(sim_step(*model, o, s, ws));
        const Quat q(s.qpos[0], s.qpos[1], s.qpos[2], s.qpos[3]);
        angle = std::max(angle, Eigen::AngleAxisd(q.normalized()).angle());
      }
      if (model == &free_model) {
        EXPECT_GT(angle, 1.2) << integrator_name(integ);
      }
      amax = angle;
    }
    EXPECT_GT(amax, 0.5) << integrator_name(integ);
    EXPECT_LT(amax, 0.5 + 0.03) << integrator_name(integ);
  }
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

TEST(Sim, LbfgsSolverReachesTheLevenbergMarquardtSolution) {
  const Model m = model_from_mjcf(chain_mjcf(8), "chain.xml");
  SimOptions lm, lb;
  lm.integrator = lb.integrator = Integrator::Pbad3;
  lm.dt = lb.dt = 0.02;
  lm.lm_tolerance = lb.lm_tolerance = 1e-10;
  lm.lm_relative_tolerance = lb.lm_relative_tolerance = 0;
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
