// PBAD's step energy (sim.h): the stencil's body-point term (exact with mass, centre
// and second moment), gravity, contact and friction penalties, actuator work, joint
// damping and range penalties; its gradient through the per-body wrenches and its
// Gauss-Newton / exact (plus geometric) Hessian blocks for the O(N) tree solve.
#include <cmath>

#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// Gradient of dry joint friction's F (sqrt(dq^2 + eps^2) - eps) per dof. On a ball or
// free joint's rotation, dq = log(R_i^T R) and q moves by R exp(delta), so d dq / d delta
// is the inverse right Jacobian of SO(3), Jr^-1(phi) = I + [phi]/2 + c [phi]^2, and the
// gradient in delta is its transpose times the one in dq (c = 1/th^2 - (1 + cos th) /
// (2 th sin th), 1/12 at th -> 0).
void add_frictionloss_gradient(const Model& m, const SimOptions& o, const VecX& dq, VecX* grad) {
  for (const Joint& j : m.joints) {
    if (j.frictionloss <= 0) continue;
    const int n = joint_nv(j.type);
    VecX g(n);
    for (int i = 0; i < n; ++i) {
      const double eps = frictionloss_eps(o, j, i), d = dq[j.vadr + i];
      g[i] = j.frictionloss * d / std::sqrt(d * d + eps * eps);
    }
    const int rot = j.type == JointType::Ball ? 0 : j.type == JointType::Free ? 3 : -1;
    if (rot >= 0) {
      const Vec3 phi = dq.segment<3>(j.vadr + rot);
      const double th = phi.norm();
      const double cf = th < 1e-4 ? 1.0 / 12 : 1 / (th * th) - (1 + std::cos(th)) / (2 * th * std::sin(th));
      const Vec3 gr = g.segment<3>(rot);
      g.segment<3>(rot) = gr - 0.5 * phi.cross(gr) + cf * phi.cross(phi.cross(gr));
    }
    grad->segment(j.vadr, n) += g;
  }
}

// A point force f at x on body b: its wrench, and for the exact Hessian's geometric
// term its moment x f^T and its sum.
void add_point_force(SimWorkspace& ws, int b, const Vec3& x, const Vec3& f, bool exact) {
  ws.w[b] += point_wrench(x, f);
  if (exact) {
    ws.moment[b] += x * f.transpose();
    ws.force[b] += f;
  }
}

// Friction on the tangential slip st under normal force fn, as a dissipation
// potential: dry Coulomb mu fn (sqrt(|st|^2 + eps^2) - eps) or C_k's g/2 |st|^2.
// Returns the energy; *g is the coefficient of its gradient g st and of its
// Gauss-Newton Hessian g P_t. mu: the contact's Coulomb coefficient (contact_mu: its
// geoms' or an explicit pair's, else the scene's); C_k ignores it (contact.h).
double slip_friction(const SimOptions& o, double fn, const Vec3& st, double* g, double mu) {
  if (o.contact.friction == FrictionModel::Coulomb) {
    const double eps = o.contact.slip_eps, r = std::sqrt(st.squaredNorm() + eps * eps);
    *g = mu * fn / r;
    return mu * fn * (r - eps);
  }
  *g = o.contact.ck * fn / o.dt;
  return 0.5 * *g * st.squaredNorm();
}

// Torsional / rolling friction (condim 4 / 6) of a contact between body b and body a
// (0: the world, which does not turn) on their relative rotation over the step,
// phi = phi_b - phi_a (rotation_increment, spin_friction): the gradient J^T dE/dphi
// as a pure torque on each body, the Gauss-Newton block J^T H J on each body's own
// block (the a-b coupling is left out, as for the exact Hessian's geometric term).
double spin_term(SimWorkspace& ws, const SimOptions& o, const Kinematics& k, const PbadStep& p, int b, int a,
                 double fn, const Vec3& n, const ContactMix& mix, bool derivs) {
  Mat3 jb, ja;
  Vec3 phi = rotation_increment(k.xmat[b], p.prev_rot[b], &jb);
  if (a > 0) phi -= rotation_increment(k.xmat[a], p.prev_rot[a], &ja);
  Vec3 g;
  Mat3 h;
  const double e = spin_friction(fn, n, phi, mix.torsion, mix.condim == 6 ? mix.roll : 0, o.contact.spin_eps, &g,
                                 derivs ? &h : nullptr);
  if (derivs) {
    ws.w[b].head<3>() += jb.transpose() * g;
    ws.h[b].topLeftCorner<3, 3>() += jb.transpose() * h * jb;
    if (a > 0) {
      ws.w[a].head<3>() -= ja.transpose() * g;
      ws.h[a].topLeftCorner<3, 3>() += ja.transpose() * h * ja;
    }
  }
  return e;
}

// Sliding friction of a body-obstacle contact whose point sits a reach rho = radius +
// margin inside the body (sphere, capsule end, a margin): on the slip of the body's
// material point that touched at q_i (x_i - rho n), not the centre's, so that a ball
// can roll (the centre's slip would brake rolling as if it slid) and a sliding ball
// spins up (n held at its current value, as P_t is). Euler/RK4 use the same point's
// velocity (explicit_integrators.cpp).
double contact_point_friction(SimWorkspace& ws, const SimOptions& o, const Kinematics& k, const PbadStep& p,
                              const ContactPoint& cp, const Vec3& x_prev, const Vec3& x, const Vec3& n, double fn,
                              double reach, const ContactMix& mix, bool derivs, bool exact) {
  const Mat3 pt = Mat3::Identity() - n * n.transpose();
  const Vec3 arm = reach * n;
  const Vec3 xf = x - k.xmat[cp.body] * (p.prev_rot[cp.body].transpose() * arm);
  const Vec3 st = pt * (xf - (x_prev - arm));
  double g;
  const double e = slip_friction(o, fn, st, &g, contact_mu(mix, o.contact.mu));
  if (derivs) {
    add_point_force(ws, cp.body, xf, g * st, exact);
    ws.h[cp.body] += point_hessian(xf, g * pt);
  }
  return e;
}

// A condim 4 / 6 body-obstacle contact's friction: sliding friction at the contact
// point, then the torsional / rolling term.
[[gnu::noinline]] double spin_contact_friction(SimWorkspace& ws, const SimOptions& o, const Kinematics& k,
                                               const PbadStep& p, const ContactPoint& cp, const Vec3& x_prev,
                                               const Vec3& x, const Vec3& n, double fn, const ContactMix& mix,
                                               bool derivs, bool exact) {
  return contact_point_friction(ws, o, k, p, cp, x_prev, x, n, fn, cp.radius + mix.margin, mix, derivs, exact) +
         spin_term(ws, o, k, p, cp.body, 0, fn, n, mix, derivs);
}

}  // namespace

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
    ObstacleCull cull;
    const int nprev = static_cast<int>(s.normal_force_prev.size());
    for (size_t i = 0; i < ws.points.size(); ++i) {
      const ContactPoint& cp = ws.points[i];
      cull.update(m, k, cp, ws.obstacles, ws.geom_mix);
      // Out of every obstacle's reach and without a normal force at q_i: no term at all
      // (the obstacle loop below was most of this function's time in a pile of meshes).
      if (cull.skip_all() && i < p.point_pressed.size() && !p.point_pressed[i]) continue;
      // A support point (contact.h) moves on its body: its normal term acts at the
      // current deepest point, its friction on the material point xm that touched at q_i.
      const bool support = cp.support != PointSupport::Fixed;
      Mat3 curvature;
      const Vec3 local = support ? support_point_local(m, cp, k.xmat[cp.body], exact ? &curvature : nullptr) : cp.local;
      const Vec3 x = k.xpos[cp.body] + k.xmat[cp.body] * local;
      const Vec3 xm = support ? Vec3(k.xpos[cp.body] + k.xmat[cp.body] * p.prev_local[i]) : x;
      for (int ob = 0; ob < no; ++ob) {
        const int slot = static_cast<int>(i) * no + ob;
        // Out of reach and without last step's normal force (no friction term either).
        if (cull.skip(ob) && (slot >= nprev || s.normal_force_prev[slot] <= 0)) continue;
        if (cp.role != PointRole::All && !point_meets(m, cp, ws.obstacles[ob])) continue;
        Vec3 n;
        const MeshBvh* tree = ob < static_cast<int>(ws.obstacle_trees.size()) ? &ws.obstacle_trees[ob] : nullptr;
        const ContactMix mix = ws.geom_mix ? point_contact_mix(m, cp, ws.obstacles[ob]) : ContactMix{};
        const double dist = obstacle_distance(m.geoms[ws.obstacles[ob]], tree, x, &n) - (cp.radius + mix.margin);
        if (dist < 0) {
          e += 0.5 * kk * dist * dist;
          if (derivs) {
            add_point_force(ws, cp.body, x, kk * dist * n, exact);
            ws.h[cp.body] += point_hessian(x, kk * n * n.transpose());
            if (exact && support) {
              // + kk dist [n] H [n] on the rotation block (contact.h), entered through the
              // moment M (geometric_block_transposed takes M^T - tr(M) I): M = C - tr(C)/2 I.
              Mat3 nx;  // [n], the cross product matrix
              nx << 0, -n.z(), n.y(), n.z(), 0, -n.x(), -n.y(), n.x(), 0;
              const Mat3 cc = kk * dist * nx * curvature * nx;
              ws.moment[cp.body] += cc - 0.5 * cc.trace() * Mat3::Identity();
            }
          }
        }
        const double fn = slot < static_cast<int>(s.normal_force_prev.size()) ? s.normal_force_prev[slot] : 0;
        if (fn <= 0 || o.contact.friction == FrictionModel::None || mix.frictionless) continue;
        if (mix.condim > 3 && p.any_spin) {  // out of line: no work here for condim <= 3
          e += spin_contact_friction(ws, o, k, p, cp, p.prev_points[i], xm, n, fn, mix, derivs, exact);
          continue;
        }
        if (cp.radius + mix.margin > 0) {
          e += contact_point_friction(ws, o, k, p, cp, p.prev_points[i], xm, n, fn, cp.radius + mix.margin, mix,
                                      derivs, exact);
          continue;
        }
        const Mat3 pt = Mat3::Identity() - n * n.transpose();
        const Vec3 st = pt * (xm - p.prev_points[i]);
        double g;
        e += slip_friction(o, fn, st, &g, contact_mu(mix, o.contact.mu));
        if (derivs) {
          add_point_force(ws, cp.body, xm, g * st, exact);
          ws.h[cp.body] += point_hessian(xm, g * pt);
        }
      }
    }
  }
  if (o.contact.enabled && p.any_mesh_features) {
    // Obstacle corners against moving meshes (contact.h): normal penalty only, with
    // its Gauss-Newton Hessian.
    ws.feature_contacts.clear();
    mesh_feature_contacts(m, k, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &ws.feature_contacts);
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
      double g;
      e += slip_friction(o, fa.normal_force, st, &g, fa.mu);
      if (derivs) {
        add_point_force(ws, fa.body, x, g * st, exact);
        ws.h[fa.body] += point_hessian(x, g * pt);
      }
      if (fa.condim > 3 && p.any_spin) {
        ContactMix mix;
        mix.condim = fa.condim;
        mix.torsion = fa.torsion;
        mix.roll = fa.roll;
        e += spin_term(ws, o, k, p, fa.body, 0, fa.normal_force, fa.normal, mix, derivs);
      }
    }
  }
  if (derivs) ws.pair_terms.clear();
  if (o.contact.enabled && p.any_pairs) {
    // Body-body contact (contact.h): the penalty couples bodies a and b, which per-body
    // blocks cannot express (dropping the a-b block cost 19 LM iterations per step in
    // the pile scene), so its Gauss-Newton matrix goes to the solver as rank-1 terms
    // (ws.pair_terms, added by Woodbury's identity); the gradient is exact.
    find_pair_contacts(m, k, ws.pairs, &ws.pair_contacts, o.contact.self_collision, &ws.broadphase);
    const double kk = o.contact.stiffness;
    for (const PairContact& c : ws.pair_contacts) {
      e += 0.5 * kk * c.depth * c.depth;
      if (!derivs) continue;
      const Vec3 f = kk * c.depth * c.gain * c.normal;  // force on b; the energy's gradient at b's point is -f
      // Gauss-Newton only (no geometric term), as mesh feature contacts: the depth's
      // second-order change is a function of the two bodies' relative motion only,
      // -f . (w_rel x v_rel) at b's point, which per-body blocks cannot hold. The
      // per-body split it had (-f on b at the surface point, +f on a) was wrong for
      // either body moving alone: a ball turning about its centre got curvature -9.2
      // instead of +3.4, and a capsule turning about its axis in the pile (step 15) 2.65x
      // too little, so LM zigzagged to its 50-iteration cap (README, "Pair contacts'
      // Hessian").
      add_point_force(ws, c.body_b, c.point, -f, false);
      add_point_force(ws, c.body_a, c.point, f, false);
      ws.pair_terms.push_back({c.body_a, c.body_b, c.point, c.point, c.normal, kk * c.gain * c.gain});
    }
    // Friction on the relative slip of the two bodies' material points that met at q_i.
    for (const PairAnchor& pa : p.pair_anchors) {
      if (o.contact.friction == FrictionModel::None) break;
      const Vec3 xa = k.xpos[pa.body_a] + k.xmat[pa.body_a] * pa.local_a;
      const Vec3 xb = k.xpos[pa.body_b] + k.xmat[pa.body_b] * pa.local_b;
      const Mat3 pt = Mat3::Identity() - pa.normal * pa.normal.transpose();
      const Vec3 st = pt * (xb - xa);
      double g;
      e += slip_friction(o, pa.normal_force, st, &g, pa.mu);
      if (!derivs) continue;
      add_point_force(ws, pa.body_b, xb, g * st, exact);
      add_point_force(ws, pa.body_a, xa, -(g * st), exact);
      // g P = g (t1 t1^T + t2 t2^T): two rank-1 terms.
      const Vec3 t1 = pa.normal.unitOrthogonal(), t2 = pa.normal.cross(t1);
      ws.pair_terms.push_back({pa.body_a, pa.body_b, xa, xb, t1, g});
      ws.pair_terms.push_back({pa.body_a, pa.body_b, xa, xb, t2, g});
    }
    if (p.any_spin)
      for (const PairAnchor& pa : p.pair_anchors)
        if (pa.condim > 3) {
          ContactMix mix;
          mix.condim = pa.condim;
          mix.torsion = pa.torsion;
          mix.roll = pa.roll;
          e += spin_term(ws, o, k, p, pa.body_b, pa.body_a, pa.normal_force, pa.normal, mix, derivs);
        }
  }
  // Actuator work, joint damping and dry friction (dissipation potentials: dt d v^2 / 2
  // and dt F |v| with v = dq / dt) and armature (the stencil's inertial term on the
  // joint coordinates, c a (dq - target)^2 as c m |dx|^2 above) in joint space.
  const bool joint_terms = !m.actuators.empty() || p.any_damping || p.any_armature || p.any_frictionloss;
  if (joint_terms) {
    actuator_forces(m, s, &ws.tau);
    ws.dq = qpos_difference(m, q, s.qpos);
    e -= ws.tau.dot(ws.dq);
    for (const Joint& j : m.joints)
      for (int i = 0; i < joint_nv(j.type); ++i) {
        const int v = j.vadr + i;
        e += 0.5 * j.damping / o.dt * ws.dq[v] * ws.dq[v];
        if (j.frictionloss > 0) {
          const double eps = frictionloss_eps(o, j, i);
          e += j.frictionloss * (std::sqrt(ws.dq[v] * ws.dq[v] + eps * eps) - eps);
        }
        if (p.any_armature) e += c * j.armature * (ws.dq[v] - p.armature_target[v]) * (ws.dq[v] - p.armature_target[v]);
      }
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
        for (int i = 0; i < joint_nv(j.type); ++i) {
          const int v = j.vadr + i;
          ws.grad[v] += j.damping / o.dt * ws.dq[v];
          if (p.any_armature) ws.grad[v] += 2 * c * j.armature * (ws.dq[v] - p.armature_target[v]);
        }
      if (p.any_frictionloss) add_frictionloss_gradient(m, o, ws.dq, &ws.grad);
    }
  }
  return e;
}

double pbad_evaluate(const Model& m, const SimOptions& o, const State& s, const PbadStep& p, const VecX& q,
                     SimWorkspace& ws) {
  return pbad_energy(m, o, s, p, q, ws, true);
}

}  // namespace pliant::articulated
