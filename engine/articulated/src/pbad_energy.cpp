// PBAD's step energy (sim.h): the stencil's body-point term (exact with mass, centre
// and second moment), gravity, contact and friction penalties, actuator work, joint
// damping and range penalties; its gradient through the per-body wrenches and its
// Gauss-Newton / exact (plus geometric) Hessian blocks for the O(N) tree solve.
#include <cmath>

#include "sim_internal.h"

namespace pliant::articulated {

// With derivs: per-body wrenches and blocks in ws.w / ws.h (ws.h_exact), the
// generalized gradient in ws.grad (sim_internal.h).
double pbad_energy(const Model& m, const SimOptions& o, const State& s, const PbadStep& p,
                   const VecX& q, SimWorkspace& ws, bool derivs, const Kinematics* poses) {
  if (!poses) {
    kinematics(m, q, &ws.kin, !derivs);
    if (derivs) ws.kin_at = q;  // full kinematics at q (pbad_finish reuses it)
    else ws.kin_at.resize(0);
  }
  const Kinematics& k = poses ? *poses : ws.kin;
  const int nb = static_cast<int>(m.bodies.size());
  const double c = p.weight / (o.dt * o.dt);
  double e = 0;
  const bool exact = derivs && o.exact_hessian && o.solver == Solver::Lm;
  if (derivs) {
    ws.w.resize(nb);
    ws.h.resize(nb);
    ws.w[0].setZero();
    ws.h[0].setZero();
    ws.moment.resize(nb);
    ws.force.resize(nb);
    ws.moment[0].setZero();
    ws.force[0].setZero();
  }
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    const Vec3 dx = k.xcom[b] - p.y[b];
    const Mat3 d = k.xmat[b] - p.a[b];
    const Mat3 sm = second_moment(body.inertia);
    const Mat3 rs = k.xmat[b] * sm;
    e += c * (body.mass * dx.squaredNorm() + (d * sm).cwiseProduct(d).sum()) -
         body.mass * m.gravity.dot(k.xcom[b]);
    if (!derivs) continue;
    const Vec3 f = 2 * c * body.mass * dx - body.mass * m.gravity;
    Vec3 rot = Vec3::Zero();
    for (int a = 0; a < 3; ++a) rot += rs.col(a).cross(d.col(a));
    ws.w[b].head<3>() = 2 * c * rot + k.xcom[b].cross(f);
    ws.w[b].tail<3>() = f;
    ws.h[b] = 2 * c * k.cinert[b];
    if (exact) {
      // Geometric term: integral of x f(p)^T with f(p) = rho (2c (X(p) - Y(p)) - g),
      // exact with the body's mass, centre and second moment.
      ws.moment[b] = k.xcom[b] * f.transpose() + 2 * c * rs * d.transpose();
      ws.force[b] = f;
    }
  }
  if (o.contact.enabled && !ws.points.empty() && !ws.obstacles.empty()) {
    const int no = static_cast<int>(ws.obstacles.size());
    const double kk = o.contact.stiffness;
    for (size_t i = 0; i < ws.points.size(); ++i) {
      const ContactPoint& cp = ws.points[i];
      const Vec3 x = k.xpos[cp.body] + k.xmat[cp.body] * cp.local;
      for (int ob = 0; ob < no; ++ob) {
        const int slot = static_cast<int>(i) * no + ob;
        Vec3 n;
        const double dist = obstacle_distance(m.geoms[ws.obstacles[ob]], x, &n) - cp.radius;
        if (dist < 0) {
          e += 0.5 * kk * dist * dist;
          if (derivs) {
            ws.w[cp.body] += point_wrench(x, kk * dist * n);
            ws.h[cp.body] += point_hessian(x, kk * n * n.transpose());
            if (exact) {
              ws.moment[cp.body] += x * (kk * dist * n).transpose();
              ws.force[cp.body] += kk * dist * n;
            }
          }
        }
        const double fn = slot < static_cast<int>(s.normal_force_prev.size()) ? s.normal_force_prev[slot] : 0;
        if (fn <= 0 || o.contact.friction == FrictionModel::None) continue;
        const Mat3 pt = Mat3::Identity() - n * n.transpose();
        const Vec3 st = pt * (x - p.prev_points[i]);
        if (o.contact.friction == FrictionModel::Coulomb) {
          const double eps = o.contact.slip_eps, r = std::sqrt(st.squaredNorm() + eps * eps);
          e += o.contact.mu * fn * (r - eps);
          if (derivs) {
            const Vec3 ff = o.contact.mu * fn / r * st;
            ws.w[cp.body] += point_wrench(x, ff);
            ws.h[cp.body] += point_hessian(x, (o.contact.mu * fn / r) * pt);
            if (exact) {
              ws.moment[cp.body] += x * ff.transpose();
              ws.force[cp.body] += ff;
            }
          }
        } else {
          const double g = o.contact.ck * fn / o.dt;
          e += 0.5 * g * st.squaredNorm();
          if (derivs) {
            ws.w[cp.body] += point_wrench(x, g * st);
            ws.h[cp.body] += point_hessian(x, g * pt);
            if (exact) {
              ws.moment[cp.body] += x * (g * st).transpose();
              ws.force[cp.body] += g * st;
            }
          }
        }
      }
    }
  }
  if (o.contact.enabled && p.any_mesh_features) {
    // Obstacle corners against moving meshes (contact.h): normal penalty only, with
    // its Gauss-Newton Hessian.
    ws.feature_contacts.clear();
    mesh_feature_contacts(m, k, ws.obstacles, &ws.feature_contacts);
    const double kk = o.contact.stiffness;
    for (const Contact& c : ws.feature_contacts) {
      e += 0.5 * kk * c.depth * c.depth;
      if (derivs) {
        ws.w[c.body] += point_wrench(c.point, -kk * c.depth * c.normal);
        ws.h[c.body] += point_hessian(c.point, kk * c.normal * c.normal.transpose());
      }
    }
    // Friction as for body points, on the slip of the mesh's material point that was
    // under the obstacle point at q_i, with that contact's normal and normal force.
    for (const FeatureAnchor& fa : p.feature_anchors) {
      if (o.contact.friction == FrictionModel::None) break;
      const Vec3 x = k.xpos[fa.body] + k.xmat[fa.body] * fa.local;
      const Mat3 pt = Mat3::Identity() - fa.normal * fa.normal.transpose();
      const Vec3 st = pt * (x - fa.point);
      const bool coulomb = o.contact.friction == FrictionModel::Coulomb;
      const double eps = o.contact.slip_eps, r = std::sqrt(st.squaredNorm() + eps * eps);
      const double g = coulomb ? o.contact.mu * fa.normal_force / r : o.contact.ck * fa.normal_force / o.dt;
      e += coulomb ? o.contact.mu * fa.normal_force * (r - eps) : 0.5 * g * st.squaredNorm();
      if (derivs) {
        ws.w[fa.body] += point_wrench(x, g * st);
        ws.h[fa.body] += point_hessian(x, g * pt);
        if (exact) {
          ws.moment[fa.body] += x * (g * st).transpose();
          ws.force[fa.body] += g * st;
        }
      }
    }
  }
  if (derivs) ws.pair_terms.clear();
  if (o.contact.enabled && p.any_pairs) {
    // Body-body contact (contact.h): the penalty couples bodies a and b, which per-body
    // blocks cannot express (dropping the a-b block cost 19 LM iterations per step in
    // the pile scene), so its Gauss-Newton matrix goes to the solver as rank-1 terms
    // (ws.pair_terms, added by Woodbury's identity); the gradient is exact.
    find_pair_contacts(m, k, ws.pairs, &ws.pair_contacts);
    const double kk = o.contact.stiffness;
    for (const PairContact& c : ws.pair_contacts) {
      e += 0.5 * kk * c.depth * c.depth;
      if (!derivs) continue;
      const Vec3 f = kk * c.depth * c.normal;  // force on b; the energy's gradient at b's point is -f
      ws.w[c.body_b] -= point_wrench(c.point, f);
      ws.w[c.body_a] += point_wrench(c.point, f);
      ws.pair_terms.push_back({c.body_a, c.body_b, c.point, c.point, c.normal, kk});
      if (exact) {
        ws.moment[c.body_b] -= c.point * f.transpose();
        ws.force[c.body_b] -= f;
        ws.moment[c.body_a] += c.point * f.transpose();
        ws.force[c.body_a] += f;
      }
    }
    // Friction on the relative slip of the two bodies' material points that met at q_i.
    for (const PairAnchor& pa : p.pair_anchors) {
      if (o.contact.friction == FrictionModel::None) break;
      const Vec3 xa = k.xpos[pa.body_a] + k.xmat[pa.body_a] * pa.local_a;
      const Vec3 xb = k.xpos[pa.body_b] + k.xmat[pa.body_b] * pa.local_b;
      const Mat3 pt = Mat3::Identity() - pa.normal * pa.normal.transpose();
      const Vec3 st = pt * (xb - xa);
      const bool coulomb = o.contact.friction == FrictionModel::Coulomb;
      const double eps = o.contact.slip_eps, r = std::sqrt(st.squaredNorm() + eps * eps);
      const double g = coulomb ? o.contact.mu * pa.normal_force / r : o.contact.ck * pa.normal_force / o.dt;
      e += coulomb ? o.contact.mu * pa.normal_force * (r - eps) : 0.5 * g * st.squaredNorm();
      if (!derivs) continue;
      ws.w[pa.body_b] += point_wrench(xb, g * st);
      ws.w[pa.body_a] -= point_wrench(xa, g * st);
      // g P = g (t1 t1^T + t2 t2^T): two rank-1 terms.
      const Vec3 t1 = pa.normal.unitOrthogonal(), t2 = pa.normal.cross(t1);
      ws.pair_terms.push_back({pa.body_a, pa.body_b, xa, xb, t1, g});
      ws.pair_terms.push_back({pa.body_a, pa.body_b, xa, xb, t2, g});
      if (exact) {
        ws.moment[pa.body_b] += xb * (g * st).transpose();
        ws.force[pa.body_b] += g * st;
        ws.moment[pa.body_a] -= xa * (g * st).transpose();
        ws.force[pa.body_a] -= g * st;
      }
    }
  }
  // Actuator work and joint damping (dissipation potential) in joint space.
  const bool joint_terms = !m.actuators.empty() || p.any_damping;
  if (joint_terms) {
    actuator_forces(m, s, &ws.tau);
    ws.dq = qpos_difference(m, q, s.qpos);
    e -= ws.tau.dot(ws.dq);
    for (const Joint& j : m.joints)
      for (int i = 0; i < joint_nv(j.type); ++i)
        e += 0.5 * j.damping / o.dt * ws.dq[j.vadr + i] * ws.dq[j.vadr + i];
  }
  if (p.any_limits) e += limit_terms(m, o, q, derivs ? &ws.limit_force : nullptr, derivs ? &ws.limit_h : nullptr);
  if (exact) {
    ws.h_exact.resize(nb);
    ws.h_exact[0].setZero();
    for (int b = 1; b < nb; ++b) ws.h_exact[b] = ws.h[b] + geometric_block_transposed(ws.moment[b], ws.force[b]);
  }
  if (derivs) {
    wrenches_to_generalized(m, k, ws.w, &ws.grad);  // consumes ws.w
    if (p.any_limits) ws.grad += ws.limit_force;
    if (joint_terms) {
      ws.grad -= ws.tau;
      for (const Joint& j : m.joints)
        for (int i = 0; i < joint_nv(j.type); ++i) ws.grad[j.vadr + i] += j.damping / o.dt * ws.dq[j.vadr + i];
    }
  }
  return e;
}

double pbad_evaluate(const Model& m, const SimOptions& o, const State& s, const PbadStep& p, const VecX& q,
                     SimWorkspace& ws) {
  return pbad_energy(m, o, s, p, q, ws, true);
}

}  // namespace pliant::articulated
