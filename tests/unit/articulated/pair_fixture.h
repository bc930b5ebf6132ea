// Body-body contact test helpers shared by test_contact_pairs.cpp, test_contact_mesh_pairs.cpp, test_contact_capsules.cpp and test_mesh_contact.cpp.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "contact_internal.h"
#include "sim_internal.h"

namespace pliant::articulated::pair_test {

// Two free bodies a and b (MJCF geoms given), no obstacles.
inline Model two_bodies(const std::string& pos_a, const std::string& geom_a, const std::string& pos_b,
                 const std::string& geom_b, const std::string& gravity = "0 0 -9.81") {
  return model_from_mjcf("<mujoco><option gravity=\"" + gravity + "\"/><worldbody><body name=\"a\" pos=\"" + pos_a +
                             "\"><freejoint/>" + geom_a + "</body><body name=\"b\" pos=\"" + pos_b +
                             "\"><freejoint/>" + geom_b + "</body></worldbody></mujoco>",
                         "pair.xml");
}

inline std::vector<PairContact> pair_contacts_at(const Model& m, const VecX& q) {
  Kinematics k;
  kinematics(m, q, &k);
  std::vector<PairContact> c;
  find_pair_contacts(m, k, contact_geom_pairs(m), &c);
  return c;
}

// Two free bodies (velocities qvel[0..2] and qvel[6..8]) sent at each other, no
// friction, LM run to 1e-12, dt 0.005, 60 steps: the largest relative change of
// sum m v (step 1 on), the most pair contacts at once, and whether the relative x
// velocity changed sign (a bounce).
struct CollisionMomentum {
  double worst = 0;
  size_t most_contacts = 0;
  bool bounced = false;
};
inline CollisionMomentum collide_two_free_bodies(const Model& m) {
  SimOptions o;
  o.dt = 0.005;
  o.contact.self_collision = true;
  o.contact.friction = FrictionModel::None;
  o.lm_relative_tolerance = 0;
  o.lm_tolerance = 1e-12;
  State s = state_init(m);
  s.qvel.head<3>() << 1.0, 0.1, 0;
  s.qvel.segment<3>(6) << -0.5, 0, 0.05;
  SimWorkspace ws;
  const auto momentum = [&](const State& st) {
    return Vec3(m.bodies[1].mass * st.qvel.head<3>() + m.bodies[2].mass * st.qvel.segment<3>(6));
  };
  const Vec3 p0 = momentum(s);
  const double vx0 = s.qvel[0] - s.qvel[6];
  CollisionMomentum r;
  for (int i = 0; i < 60; ++i) {
    if (!sim_step(m, o, s, ws)) {
      ADD_FAILURE() << "step " << i << " failed";
      return r;
    }
    if (i > 0) r.worst = std::max(r.worst, (momentum(s) - p0).norm() / p0.norm());
    r.most_contacts = std::max(r.most_contacts, pair_contacts_at(m, s.qpos).size());
  }
  r.bounced = (s.qvel[0] - s.qvel[6]) * vx0 < 0;
  return r;
}

// PBAD's gradient with body-body penalty and Coulomb friction against central
// differences of its energy; the LM matrix's body-body part against the Gauss-Newton
// k sum grad(d) grad(d)^T from finite differences of each contact's depth, a-b
// coupling included. Returns the number of contacts.
inline size_t expect_pair_derivatives(const Model& m) {
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  EXPECT_FALSE(p.pair_anchors.empty());
  VecX dv(m.nv);
  for (int i = 0; i < m.nv; ++i) dv[i] = 0.0015 * std::sin(1.3 * i + 0.4);
  VecX q = s.qpos;
  qpos_integrate(m, q, dv, 1.0);
  const std::vector<PairContact> contacts = pair_contacts_at(m, q);
  EXPECT_FALSE(contacts.empty());
  const auto moved = [&](int i, double h) {
    VecX e = VecX::Zero(m.nv), qq = q;
    e[i] = h;
    qpos_integrate(m, qq, e, 1.0);
    return qq;
  };
  pbad_evaluate(m, o, s, p, q, ws);
  const VecX g = ws.grad;
  const double eps = 1e-7;
  for (int i = 0; i < m.nv; ++i) {
    const double fd = (pbad_evaluate(m, o, s, p, moved(i, eps), ws) - pbad_evaluate(m, o, s, p, moved(i, -eps), ws)) / (2 * eps);
    EXPECT_NEAR(g[i], fd, 1e-6 * (1 + g.norm())) << i;
  }
  // Gauss-Newton: k sum_c grad(d_c) grad(d_c)^T in joint space.
  Eigen::MatrixXd gn = Eigen::MatrixXd::Zero(m.nv, m.nv);
  for (size_t c = 0; c < contacts.size(); ++c) {
    VecX grad_d(m.nv);
    for (int i = 0; i < m.nv; ++i) {
      const auto cp = pair_contacts_at(m, moved(i, 1e-7)), cm = pair_contacts_at(m, moved(i, -1e-7));
      EXPECT_EQ(cp.size(), contacts.size());
      EXPECT_EQ(cm.size(), contacts.size());
      if (cp.size() != contacts.size() || cm.size() != contacts.size()) return 0;
      grad_d[i] = (cp[c].depth - cm[c].depth) / 2e-7;
    }
    gn += o.contact.stiffness * grad_d * grad_d.transpose();
  }
  // The LM matrix's body-body part: (tree blocks + rank-1 terms) minus the tree
  // blocks alone, from both inverses (lm_solve, tree_solve) at q, frictionless.
  o.contact.friction = FrictionModel::None;
  pbad_evaluate(m, o, s, p, q, ws);
  ws.arm = VecX::Zero(m.nv);
  Eigen::MatrixXd full_inv(m.nv, m.nv), tree_inv(m.nv, m.nv);
  for (int i = 0; i < m.nv; ++i) {
    VecX x;
    const VecX e = VecX::Unit(m.nv, i);
    lm_solve(m, ws.h, e, &x, ws);
    full_inv.col(i) = x;
    tree_solve(m, ws.kin, ws.h, ws.arm, e, &x, &ws.tree);
    tree_inv.col(i) = x;
  }
  const Eigen::MatrixXd pair_part = full_inv.inverse() - tree_inv.inverse();
  EXPECT_LT((pair_part - gn).norm(), 1e-5 * gn.norm());
  EXPECT_GT(gn.block(0, 6, 6, 6).norm(), 0.1 * gn.norm());  // the a-b coupling per-body blocks cannot hold
  return contacts.size();
}

// Geometric overlap of every capsule-box geom pair at q, independent of the contact
// code's closed form: r - min over 4001 axis points of the box's signed distance
// (the sampled minimum of a convex function: within 1e-4 m of it for these sizes).
inline double deepest_capsule_in_box(const Model& m, const VecX& q) {
  Kinematics k;
  kinematics(m, q, &k);
  double worst = 0;
  for (const Geom& c : m.geoms) {
    if (c.type != GeomType::Capsule || c.body == 0) continue;
    const Vec3 cc = k.xpos[c.body] + k.xmat[c.body] * c.pos;
    const Vec3 axis = k.xmat[c.body] * c.quat.toRotationMatrix().col(2);
    for (const Geom& b : m.geoms) {
      if (b.type != GeomType::Box || b.body == c.body) continue;
      const Vec3 bc = k.xpos[b.body] + k.xmat[b.body] * b.pos;
      const Mat3 br = k.xmat[b.body] * b.quat.toRotationMatrix();
      double dmin = 1e300;
      Vec3 n;
      for (int i = 0; i <= 4000; ++i) {
        const Vec3 x = cc + axis * (c.size[1] * (2.0 * i / 4000 - 1));
        dmin = std::min(dmin, contact_internal::shape_distance(GeomType::Box, b.size, bc, br, x, &n));
      }
      worst = std::max(worst, c.size[0] - dmin);
    }
  }
  return worst;
}

// Geometric overlap of every box-box geom pair at q: the deepest of 201 points along
// each edge of one box inside the other (both ways; an edge pressed into a face shows
// here, corners alone would not).
inline double deepest_box_in_box(const Model& m, const VecX& q) {
  Kinematics k;
  kinematics(m, q, &k);
  double worst = 0;
  for (const Geom& a : m.geoms)
    for (const Geom& b : m.geoms) {
      if (a.type != GeomType::Box || b.type != GeomType::Box || a.body == b.body) continue;
      const Vec3 ac = k.xpos[a.body] + k.xmat[a.body] * a.pos, bc = k.xpos[b.body] + k.xmat[b.body] * b.pos;
      const Mat3 ar = k.xmat[a.body] * a.quat.toRotationMatrix(), br = k.xmat[b.body] * b.quat.toRotationMatrix();
      Vec3 n;
      for (int ax = 0; ax < 3; ++ax)
        for (int e = 0; e < 4; ++e)
          for (int i = 0; i <= 200; ++i) {
            const int u = (ax + 1) % 3, v = (ax + 2) % 3;
            Vec3 l;
            l[ax] = a.size[ax] * (2.0 * i / 200 - 1);
            l[u] = (e & 1 ? 1 : -1) * a.size[u];
            l[v] = (e & 2 ? 1 : -1) * a.size[v];
            worst = std::max(worst, -contact_internal::shape_distance(GeomType::Box, b.size, bc, br, ac + ar * l, &n));
          }
    }
  return worst;
}

}  // namespace pliant::articulated::pair_test
