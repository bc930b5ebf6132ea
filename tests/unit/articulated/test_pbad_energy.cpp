// PBAD's step energy (pbad_energy.cpp): the exact Hessian against finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"

namespace pliant::articulated {
namespace {

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

}  // namespace
}  // namespace pliant::articulated
