// PBAD's step energy (pbad_energy.cpp): the exact Hessian against finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "sim_internal.h"

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
  // Support points (contact_support.cpp): an ellipsoid and a cylinder pressed into a
  // tilted plane, turning on hinges; their curvature term [n] H [n] is in the model.
  for (const char* shape : {R"(type="ellipsoid" size="0.08 0.05 0.12" pos="0.02 0 0" euler="20 10 0")",
                            R"(type="cylinder" size="0.06 0.1" pos="0 0.03 0" euler="70 10 0")"}) {
    const Model curved = model_from_mjcf(std::string(R"(<mujoco><worldbody><geom type="plane" euler="6 -4 0"/>
      <body pos="0 0 0.1"><joint type="slide" axis="0 0 1"/><joint type="hinge" axis="0 1 0"/>
        <joint type="hinge" axis="1 0 0.3"/><geom )") + shape + "/></body></worldbody></mujoco>",
                                         "curved.xml");
    State c = state_init(curved);
    c.qpos << -0.02, 0.3, -0.2;
    c.qvel << -1, 0.5, 2;
    expect_exact_hessian(curved, c, o);
  }
}

// A body-body contact in the exact-Hessian LM model: Gauss-Newton only (pbad_energy.cpp).
// A ball pressed 2 mm into a tilted free box: moving or turning the ball alone, the
// model's curvature (the ball's block plus the pair's rank-1 terms) equals the
// energy's second difference; its depth follows its centre, so turning it changes
// nothing but the inertia term. The old per-body geometric term (at the surface point)
// gave its tilts -9.24 instead of +3.43 (LM zigzagged on a capsule turning about its
// axis in the pile: 50 iterations at step 15). The box's tilts keep the term the
// model leaves out (-f . (w x v) at the ball's centre): 544 vs 565, 1101 vs 1122.
// A box pressed into the floor at q_i, evaluated lifted 0.5 m clear of it and slid
// 0.3 m: every point-floor test is culled there, yet the friction of the points that
// carried a normal force at q_i stays in the energy (mu fn (|slip| - ...) each).
TEST(Sim, FrictionOfPressedPointsOutOfReachStaysInTheEnergy) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
    <body pos="0 0 0.095"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body></worldbody></mujoco>)",
                                  "box.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::Coulomb;
  o.contact.mu = 0.5;
  const auto energy_lifted = [&](bool pressed, double* fn_sum) {
    State s = state_init(m);
    SimWorkspace ws;
    sim_prepare(m, ws);
    if (!pressed) s.normal_force_prev.assign(ws.points.size() * ws.obstacles.size(), 0.0);  // no force at q_i
    PbadStep p;
    pbad_begin(m, o, s, p, ws);
    *fn_sum = 0;
    for (double f : s.normal_force_prev) *fn_sum += f;
    VecX q = p.q;
    q[0] += 0.3;
    q[2] += 0.5;
    return pbad_evaluate(m, o, s, p, q, ws);
  };
  double fn = 0, none = 0;
  const double e_pressed = energy_lifted(true, &fn), e_free = energy_lifted(false, &none);
  EXPECT_EQ(none, 0);
  ASSERT_GT(fn, 0);
  const double eps = o.contact.slip_eps;
  const double expected = o.contact.mu * fn * (std::sqrt(0.09 + eps * eps) - eps);
  EXPECT_NEAR(e_pressed - e_free, expected, 1e-9 * expected);
}

TEST(Sim, PairContactModelIsExactForTheBallTurningOnABox) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody>
    <body pos="0 0 0" euler="3 2 10"><freejoint/><geom type="box" size="0.15 0.1 0.05"/></body>
    <body pos="0.03 0.02 0.087"><freejoint/><geom type="sphere" size="0.04"/></body>
    </worldbody></mujoco>)", "ball_on_box.xml");
  SimOptions o;
  o.contact.self_collision = true;
  o.contact.friction = FrictionModel::None;
  State s = state_init(m);
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  const VecX q = p.q;
  const double e0 = pbad_evaluate(m, o, s, p, q, ws);
  ASSERT_EQ(ws.pair_contacts.size(), 1u);
  EXPECT_GT(ws.pair_contacts[0].depth, 1e-3);
  const std::vector<Mat6> blocks = ws.h_exact;
  const std::vector<PairTerm> terms = ws.pair_terms;
  const Kinematics k = ws.kin;
  for (int i = 0; i < m.nv; ++i) {
    const int body = i < 6 ? 1 : 2;
    const Vec6 t = k.cdof[i];  // (angular, linear at the origin)
    const auto velocity = [&](int b, const Vec3& x) {
      return b == body ? Vec3(t.tail<3>() + t.head<3>().cross(x)) : Vec3::Zero();
    };
    double model = t.dot(blocks[body] * t);
    for (const PairTerm& pt : terms) {
      const double u = pt.dir.dot(velocity(pt.body_b, pt.point_b) - velocity(pt.body_a, pt.point_a));
      model += pt.weight * u * u;
    }
    const double h = 1e-4;
    VecX dq = VecX::Zero(m.nv);
    dq[i] = 1;
    VecX qp = q, qm = q;
    qpos_integrate(m, qp, dq, h);
    qpos_integrate(m, qm, dq, -h);
    const double fd = (pbad_energy(m, o, s, p, qp, ws, false) + pbad_energy(m, o, s, p, qm, ws, false) - 2 * e0) / (h * h);
    if (i < 3 || i >= 6) EXPECT_NEAR(model, fd, 1e-4 * std::abs(fd) + 1e-3) << "dof " << i;
    else EXPECT_NEAR(model, fd, 0.05 * fd) << "dof " << i;  // the box's tilts: the left-out term
  }
}

}  // namespace
}  // namespace pliant::articulated
