#include <gtest/gtest.h>

#include <random>

#include "pliant/articulated/dynamics.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

struct RandomState {
  Model m = test::mixed_model();
  VecX q, v;
  Kinematics k;
  RandomState() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    q = m.qpos0;
    VecX dv(m.nv);
    v.resize(m.nv);
    for (int i = 0; i < m.nv; ++i) {
      dv[i] = u(rng);
      v[i] = u(rng);
    }
    qpos_integrate(m, q, dv, 1.0);
    kinematics(m, q, &k);
  }
};

TEST(Dynamics, MassMatrixFromPointMassesAndKineticEnergy) {
  RandomState s;
  const Eigen::MatrixXd mm = mass_matrix(s.m, s.k);
  EXPECT_LT((mm - mm.transpose()).norm(), 1e-12);
  EXPECT_GT(mm.llt().info() == Eigen::Success, 0);
  EXPECT_NEAR(0.5 * s.v.dot(mm * s.v), kinetic_energy(s.m, s.k, s.v), 1e-10);
}

TEST(Dynamics, TreeSolveMatchesDenseSolve) {
  RandomState s;
  const Eigen::MatrixXd mm = mass_matrix(s.m, s.k);
  VecX arm = VecX::LinSpaced(s.m.nv, 0.01, 0.2);
  VecX x;
  TreeWorkspace ws;
  tree_solve(s.m, s.k, s.k.cinert, arm, s.v, &x, &ws);
  const VecX ref = (mm + Eigen::MatrixXd(arm.asDiagonal())).ldlt().solve(s.v);
  EXPECT_LT((x - ref).norm(), 1e-9 * ref.norm());
  VecX d;
  tree_diagonal(s.m, s.k, s.k.cinert, &d, &ws);
  EXPECT_LT((d - mm.diagonal()).norm(), 1e-10);
}

// tree_resolve reuses the last tree_solve's elimination for a new right-hand side.
TEST(Dynamics, TreeResolveMatchesTreeSolve) {
  RandomState s;
  const VecX arm = VecX::LinSpaced(s.m.nv, 0.01, 0.2);
  TreeWorkspace ws, fresh;
  VecX x, ref;
  tree_solve(s.m, s.k, s.k.cinert, arm, s.v, &x, &ws);
  const VecX other = VecX::LinSpaced(s.m.nv, -1, 2);
  tree_resolve(s.m, s.k, other, &x, &ws);
  tree_solve(s.m, s.k, s.k.cinert, arm, other, &ref, &fresh);
  EXPECT_LT((x - ref).norm(), 1e-12 * ref.norm());
}

// The fixed-size joint blocks (6, 3 and 2 dofs here) report definiteness and still
// solve an indefinite (non-singular) system, as the LM loop's first tries need.
TEST(Dynamics, TreeSolveReportsDefinitenessAndSolvesIndefiniteSystems) {
  RandomState s;
  const Eigen::MatrixXd mm = mass_matrix(s.m, s.k);
  TreeWorkspace ws;
  VecX x;
  const VecX pd = VecX::Constant(s.m.nv, 1e-3);
  EXPECT_TRUE(tree_solve(s.m, s.k, s.k.cinert, pd, s.v, &x, &ws));
  // Shift the spectrum by about half the largest eigenvalue: indefinite.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(mm);
  const double shift = 0.5 * (eig.eigenvalues()[s.m.nv / 2] + eig.eigenvalues()[s.m.nv / 2 - 1]);
  const VecX arm = VecX::Constant(s.m.nv, -shift);
  EXPECT_FALSE(tree_solve(s.m, s.k, s.k.cinert, arm, s.v, &x, &ws));
  const Eigen::MatrixXd a = mm + Eigen::MatrixXd(arm.asDiagonal());
  const VecX ref = a.fullPivLu().solve(s.v);
  EXPECT_LT((x - ref).norm(), 1e-6 * ref.norm());
}

TEST(Dynamics, GravityBiasIsPotentialGradient) {
  RandomState s;
  const VecX bias = bias_force(s.m, s.k, VecX::Zero(s.m.nv));
  const double h = 1e-6;
  for (int d = 0; d < s.m.nv; ++d) {
    VecX e = VecX::Zero(s.m.nv);
    e[d] = 1;
    VecX qp = s.q, qm = s.q;
    qpos_integrate(s.m, qp, e, h);
    qpos_integrate(s.m, qm, e, -h);
    Kinematics kp, km;
    kinematics(s.m, qp, &kp);
    kinematics(s.m, qm, &km);
    EXPECT_NEAR((potential_energy(s.m, kp) - potential_energy(s.m, km)) / (2 * h), bias[d], 1e-6);
  }
}

TEST(Dynamics, VelocityBiasMatchesLagrangian) {
  // Power balance: dT/dt = qdot . (tau - bias_v) with tau = 0 and no gravity, i.e.
  // d/dt (1/2 v^T M v) along the motion equals -v^T (C v) + v^T M a = 0 (C v is
  // workless when qacc = M^-1 (-C v)). Check T is conserved to first order.
  RandomState s;
  s.m.gravity.setZero();
  VecX a;
  TreeWorkspace ws;
  forward_dynamics(s.m, s.k, s.v, VecX::Zero(s.m.nv), &a, &ws);
  const double h = 1e-6;
  VecX qp = s.q;
  qpos_integrate(s.m, qp, s.v, h);
  const VecX vp = s.v + h * a;
  Kinematics kp;
  kinematics(s.m, qp, &kp);
  const double t0 = kinetic_energy(s.m, s.k, s.v), t1 = kinetic_energy(s.m, kp, vp);
  EXPECT_LT(std::abs(t1 - t0) / h, 1e-4 * (1 + t0));
}

}  // namespace
}  // namespace pliant::articulated
