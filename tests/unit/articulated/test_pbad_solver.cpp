// PBAD's minimiser (pbad_solver.cpp): Gauss-Newton fallback, stationarity, Newton vs
// Gauss-Newton, the accuracy-aware stop and L-BFGS.
#include <gtest/gtest.h>

#include "pliant/articulated/sim.h"
#include "sim_fixture.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// In the whip the Newton model at the predictor is often indefinite (compressed links).
// LM used to raise lambda until it was definite (1e-6 -> 1e-2) and then needed several
// accepted steps to get back below the final correction's 1e-4; it now takes the
// Gauss-Newton step there: 100-link whip at dt 0.05, 3.6 -> 2.5 iterations per step
// (cost 1.84x -> 1.33x of linear from 10 links), same drift.
TEST(Sim, IndefiniteNewtonModelTakesTheGaussNewtonStep) {
  const test::WhipRun r = test::run_whip(100, Integrator::Pbad3, 0.05, 8.0, 1e9);
  ASSERT_TRUE(r.ok) << r.failed_at;
  EXPECT_LT(r.iterations_per_step, 2.9);
  EXPECT_LT(r.drift, 0.3);
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

// lm_solve's Woodbury solve with the body-body terms of three separate contact groups
// (two boxes, two spheres, an arm touching a ball): against the dense matrix A +
// sum w u u^T, A from tree_solve's inverse and u from point Jacobians (not
// lm_solve's own columns). Each group's capacitance block is solved on its own.
TEST(Sim, LmSolveWithSeparateContactGroupsMatchesTheDenseSolve) {
  const Model m = model_from_mjcf(
      "<mujoco><worldbody>"
      "<body name=\"a\" pos=\"0 0 1\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\"/></body>"
      "<body name=\"arm\" pos=\"6 0 1\"><joint type=\"hinge\" axis=\"0 1 0\"/>"
      "<geom type=\"capsule\" fromto=\"0 0 0 0.5 0 0\" size=\"0.05\"/>"
      "<body name=\"fore\" pos=\"0.5 0 0\"><joint type=\"hinge\" axis=\"0 0 1\"/>"
      "<geom type=\"capsule\" fromto=\"0 0 0 0.5 0 0\" size=\"0.05\"/></body></body>"
      "<body name=\"c\" pos=\"3 0 1\"><freejoint/><geom type=\"sphere\" size=\"0.1\"/></body>"
      "<body name=\"b\" pos=\"0.02 0.01 1.19\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\"/></body>"
      "<body name=\"e\" pos=\"6.75 0 1.14\"><freejoint/><geom type=\"sphere\" size=\"0.1\"/></body>"
      "<body name=\"d\" pos=\"3.05 0 1.18\"><freejoint/><geom type=\"sphere\" size=\"0.1\"/></body>"
      "</worldbody></mujoco>",
      "groups.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  pbad_evaluate(m, o, s, p, s.qpos, ws);
  ASSERT_GE(ws.pair_terms.size(), 3u);
  ws.arm = VecX::Constant(m.nv, 0.3);
  VecX rhs(m.nv), x;
  for (int i = 0; i < m.nv; ++i) rhs[i] = std::sin(0.9 * i + 0.1);
  lm_solve(m, ws.h, rhs, &x, ws);
  EXPECT_EQ(ws.group_begin.size(), 4u);  // three groups
  Eigen::MatrixXd tree_inv(m.nv, m.nv);
  for (int i = 0; i < m.nv; ++i) {
    VecX col;
    tree_solve(m, ws.kin, ws.h, ws.arm, VecX::Unit(m.nv, i), &col, &ws.tree);
    tree_inv.col(i) = col;
  }
  Eigen::MatrixXd a = tree_inv.inverse();
  for (const PairTerm& t : ws.pair_terms) {
    const VecX u = point_jacobian(m, ws.kin, t.body_b, t.point_b).transpose() * t.dir -
                   point_jacobian(m, ws.kin, t.body_a, t.point_a).transpose() * t.dir;
    a += t.weight * u * u.transpose();
  }
  const VecX dense = a.partialPivLu().solve(rhs);
  EXPECT_LT((x - dense).norm(), 1e-9 * dense.norm());
  EXPECT_GT((x - tree_inv * rhs).norm(), 1e-3 * dense.norm());  // the terms matter
}

}  // namespace
}  // namespace pliant::articulated
