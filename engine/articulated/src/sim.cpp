// Integrators: PBAD steps by Levenberg-Marquardt (see sim.h for the energy) and the
// explicit baselines.
#include "pliant/articulated/sim.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pliant::articulated {
namespace {

Mat3 second_moment(const Mat3& inertia) {  // integral rho p p^T about the centre
  return 0.5 * inertia.trace() * Mat3::Identity() - inertia;
}

void actuator_forces(const Model& m, const State& s, VecX* tau) {
  tau->setZero(m.nv);
  for (size_t a = 0; a < m.actuators.size() && a < static_cast<size_t>(s.ctrl.size()); ++a) {
    const Actuator& act = m.actuators[a];
    const double c = std::clamp(s.ctrl[a], act.ctrl_min, act.ctrl_max);
    (*tau)[m.joints[act.joint].vadr] += act.gear * c;
  }
}

// Joint-range penalty 1/2 k (q - bound)^2 beyond each limited hinge/slide: returns the
// energy; optionally its gradient and (diagonal) Hessian in joint space.
double limit_terms(const Model& m, const SimOptions& o, const VecX& q, VecX* force, VecX* hdiag) {
  const double k = o.contact.limit_stiffness;
  if (force) force->setZero(m.nv);
  if (hdiag) hdiag->setZero(m.nv);
  double e = 0;
  for (const Joint& j : m.joints) {
    if (j.type == JointType::Ball && (j.swing_max >= 0 || j.twist_limited)) {
      Vec3 g;
      Mat3 h;
      const Eigen::Vector4d qb(q[j.qadr], q[j.qadr + 1], q[j.qadr + 2], q[j.qadr + 3]);
      e += ball_swing_twist_penalty(j, k, qb, force ? &g : nullptr, hdiag ? &h : nullptr);
      if (force) force->segment<3>(j.vadr) += g;
      if (hdiag) hdiag->segment<3>(j.vadr) += hessian_diagonal_bound(h);
    }
    if (!j.limited) continue;
    if (j.type == JointType::Ball) {
      // Cone: rotation angle theta = |log q| <= range_max. With the local velocity
      // (q' = q exp(dv)), d theta / d dv = the rotation's unit axis n; the Hessian
      // k n n^T is replaced by k I (diagonal for the tree solve; exact along n, stiffer
      // across, so LM steps stay conservative).
      Eigen::Vector4d qb(q[j.qadr], q[j.qadr + 1], q[j.qadr + 2], q[j.qadr + 3]);
      qb.normalize();
      if (qb[0] < 0) qb = -qb;
      const Vec3 v = qb.tail<3>();
      const double sv = v.norm();
      const double theta = 2 * std::atan2(sv, qb[0]);
      const double d = theta - j.range_max;
      if (d <= 0 || sv < 1e-300) continue;
      e += 0.5 * k * d * d;
      if (force) force->segment<3>(j.vadr) += k * d * v / sv;
      if (hdiag) hdiag->segment<3>(j.vadr).array() += k;
      continue;
    }
    const double x = q[j.qadr];
    const double d = x > j.range_max ? x - j.range_max : x < j.range_min ? x - j.range_min : 0;
    if (d == 0) continue;
    e += 0.5 * k * d * d;
    if (force) (*force)[j.vadr] = k * d;
    if (hdiag) (*hdiag)[j.vadr] = k;
  }
  return e;
}

bool any_limits(const Model& m) {
  for (const Joint& j : m.joints)
    if (j.limited || j.swing_max >= 0 || j.twist_limited) return true;
  return false;
}

void lm_armature(const Model& m, const SimOptions& o, const PbadStep& p, double lambda, SimWorkspace& ws);

// Energy of PBAD at q; with derivs also per-body wrenches (gradient) and Gauss-Newton
// blocks in ws.w / ws.h and the generalized gradient in ws.grad.
// With poses (kinematics at q, derivs false) the kinematics pass is skipped.
double pbad_energy(const Model& m, const SimOptions& o, const State& s, const PbadStep& p,
                   const VecX& q, SimWorkspace& ws, bool derivs, const Kinematics* poses = nullptr) {
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

// Generalized contact + actuator forces for explicit integrators at (k, qvel).
void explicit_forces(const Model& m, const SimOptions& o, const State& s, const Kinematics& k, const VecX& qpos,
                     const VecX& qvel, SimWorkspace& ws, VecX* tau, std::vector<Contact>* record) {
  actuator_forces(m, s, tau);
  if (any_limits(m)) {
    limit_terms(m, o, qpos, &ws.limit_force, nullptr);
    *tau -= ws.limit_force;
  }
  ws.contacts.clear();
  if (!o.contact.enabled || ws.points.empty() || ws.obstacles.empty()) return;
  find_contacts(m, k, ws.points, ws.obstacles, &ws.contacts);
  if (ws.contacts.empty()) return;
  const int nb = static_cast<int>(m.bodies.size());
  std::vector<Vec6> v(nb), w(nb, Vec6::Zero());
  v[0].setZero();
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    v[b] = v[body.parent];
    for (int d = body.dof_begin; d < body.dof_begin + body.dof_count; ++d) v[b] += k.cdof[d] * qvel[d];
  }
  for (Contact& c : ws.contacts) {
    const Vec3 vp = v[c.body].tail<3>() + v[c.body].head<3>().cross(c.point);
    const double vn = vp.dot(c.normal);
    const double fn = std::max(0.0, o.contact.stiffness * c.depth - o.contact.damping * vn);
    const Vec3 vt = vp - vn * c.normal;
    Vec3 ft = Vec3::Zero();
    if (o.contact.friction == FrictionModel::Coulomb) {
      const double eps = o.contact.slip_eps / o.dt;
      ft = -o.contact.mu * fn * vt / std::sqrt(vt.squaredNorm() + eps * eps);
    } else if (o.contact.friction == FrictionModel::Ck) {
      ft = -o.contact.ck * fn * vt;
    }
    c.force = fn * c.normal + ft;
    w[c.body] += point_wrench(c.point, c.force);
  }
  VecX tc;
  wrenches_to_generalized(m, k, w, &tc);
  *tau += tc;
  if (record) *record = ws.contacts;
}

void accel(const Model& m, const SimOptions& o, const State& s, const VecX& q, const VecX& v,
           SimWorkspace& ws, VecX* a) {
  kinematics(m, q, &ws.kin);
  ws.kin_at.resize(0);
  VecX tau;
  explicit_forces(m, o, s, ws.kin, q, v, ws, &tau, nullptr);
  forward_dynamics(m, ws.kin, v, tau, a, &ws.tree);
}

bool finite(const VecX& v) { return v.allFinite(); }

// q(-dt) and q(-2 dt) before the first step. A multistep stencil needs its start-up
// frames on the true trajectory (a second-order Taylor guess leaves an O(dt^3) kink
// that excites fast modes, which PBAD then damps: 0.1% of the swing energy of a 10-link
// chain at dt 0.05). Without contact they come from RK4 run backwards in time with
// substeps of at most dt/4 and 10 ms (2.5 ms gave the same drifts to 5 digits for
// 10-100 links at dt 0.01-0.1 and cost 14% of a 10-link step at dt 0.04); with
// contact (stiff penalty, friction that would run backwards) from the Taylor
// expansion with the initial acceleration.
void startup_past(const Model& m, const SimOptions& o, const State& s, SimWorkspace& ws, int frames,
                  std::vector<VecX>* past) {
  VecX a;
  accel(m, o, s, s.qpos, s.qvel, ws, &a);
  if (!a.allFinite()) a.setZero();
  const double dt = o.dt;
  past->assign(frames, s.qpos);
  for (int f = 1; f <= frames; ++f)
    qpos_integrate(m, (*past)[f - 1], -f * dt * s.qvel + 0.5 * f * f * dt * dt * a, 1.0);
  if (o.contact.enabled && !ws.contacts.empty()) return;  // accel() found contacts at q0
  const int sub = std::max(4, static_cast<int>(std::ceil(dt / 0.01)));
  const double h = -dt / sub;
  VecX q = s.qpos, v = s.qvel, a1, a2, a3, a4, qs;
  for (int frame = 1; frame <= frames; ++frame) {
    for (int i = 0; i < sub; ++i) {
      accel(m, o, s, q, v, ws, &a1);
      qs = q;
      qpos_integrate(m, qs, v, h / 2);
      const VecX v2 = v + h / 2 * a1;
      accel(m, o, s, qs, v2, ws, &a2);
      qs = q;
      qpos_integrate(m, qs, v2, h / 2);
      const VecX v3 = v + h / 2 * a2;
      accel(m, o, s, qs, v3, ws, &a3);
      qs = q;
      qpos_integrate(m, qs, v3, h);
      const VecX v4 = v + h * a3;
      accel(m, o, s, qs, v4, ws, &a4);
      qpos_integrate(m, q, (v + 2 * v2 + 2 * v3 + v4) / 6, h);
      v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
      if (!ws.contacts.empty()) return;  // touched an obstacle on the way back: keep Taylor
    }
    if (!q.allFinite() || !v.allFinite()) return;
    (*past)[frame - 1] = q;
  }
}

}  // namespace

Integrator integrator_from_name(const std::string& name) {
  if (name == "pbad2") return Integrator::Pbad2;
  if (name == "pbad3") return Integrator::Pbad3;
  if (name == "pbad4") return Integrator::Pbad4;
  if (name == "euler") return Integrator::Euler;
  if (name == "rk4") return Integrator::Rk4;
  throw std::invalid_argument("unknown integrator \"" + name + "\"");
}

std::string integrator_name(Integrator i) {
  switch (i) {
    case Integrator::Pbad2: return "pbad2";
    case Integrator::Pbad3: return "pbad3";
    case Integrator::Pbad4: return "pbad4";
    case Integrator::Euler: return "euler";
    case Integrator::Rk4: return "rk4";
  }
  return "?";
}

bool integrator_is_pbad(Integrator i) {
  return i == Integrator::Pbad2 || i == Integrator::Pbad3 || i == Integrator::Pbad4;
}

void sim_prepare(const Model& m, SimWorkspace& ws) {
  if (ws.cached_for == &m) return;
  ws.points = contact_points(m);
  ws.obstacles = contact_obstacles(m);
  ws.cached_for = &m;
}

State state_init(const Model& m) {
  State s;
  s.qpos = m.qpos0;
  s.qvel = VecX::Zero(m.nv);
  s.ctrl = VecX::Zero(m.actuators.size());
  return s;
}

namespace {

// Poses of a past frame: PBAD needs q_i .. q_{i-k} every step, and all but q_i were
// already computed in earlier steps (least recently used of kFrameSlots slots).
constexpr int kFrameSlots = 4;
const Kinematics& frame_kinematics(const Model& m, const VecX& q, SimWorkspace& ws) {
  ws.frame_kin.resize(kFrameSlots);
  ws.frame_q.resize(kFrameSlots);
  ws.frame_stamp.resize(kFrameSlots, 0);
  int slot = 0;
  for (int i = 0; i < kFrameSlots; ++i) {
    if (ws.frame_q[i].size() == q.size() && ws.frame_q[i] == q) {
      ws.frame_stamp[i] = ++ws.frame_clock;
      return ws.frame_kin[i];
    }
    if (ws.frame_stamp[i] < ws.frame_stamp[slot]) slot = i;
  }
  kinematics(m, q, &ws.frame_kin[slot], true);
  ws.frame_q[slot] = q;
  ws.frame_stamp[slot] = ++ws.frame_clock;
  return ws.frame_kin[slot];
}

// Hands ws.kin (computed at q) to the frame cache without copying.
void frame_store(const VecX& q, SimWorkspace& ws) {
  ws.frame_kin.resize(kFrameSlots);
  ws.frame_q.resize(kFrameSlots);
  ws.frame_stamp.resize(kFrameSlots, 0);
  int slot = 0;
  for (int i = 1; i < kFrameSlots; ++i)
    if (ws.frame_stamp[i] < ws.frame_stamp[slot]) slot = i;
  std::swap(ws.frame_kin[slot], ws.kin);
  ws.frame_q[slot] = q;
  ws.frame_stamp[slot] = ++ws.frame_clock;
  ws.kin_at.resize(0);
}

}  // namespace

void pbad_begin(const Model& m, const SimOptions& o, State& s, PbadStep& p, SimWorkspace& ws) {
  sim_prepare(m, ws);
  if (s.normal_force_prev.size() != ws.points.size() * ws.obstacles.size()) {
    // First step: friction uses the normal forces of the initial state.
    kinematics(m, s.qpos, &ws.kin);
    ws.kin_at.resize(0);
    s.normal_force_prev.assign(ws.points.size() * ws.obstacles.size(), 0.0);
    find_contacts(m, ws.kin, ws.points, ws.obstacles, &ws.contacts);
    for (const Contact& c : ws.contacts)
      if (c.slot >= 0) s.normal_force_prev[c.slot] = o.contact.stiffness * c.depth;
  }
  // Past frames; before the first step they come from a Taylor expansion with the
  // initial acceleration (a constant-velocity past would make the start first-order).
  // Stencil weights c_0 q_{i+1} + c_1 q_i + ... (sim.h): the target is
  // Y = -(c_1 X_i + c_2 X_{i-1} + ...) / c_0 and the energy weight c_0 / 2.
  static const double kPbad2[] = {1, -2, 1}, kPbad3[] = {2, -5, 4, -1}, kPbad4[] = {2.5, -7, 7, -3, 0.5};
  const double* c = o.integrator == Integrator::Pbad4 ? kPbad4 : o.integrator == Integrator::Pbad3 ? kPbad3 : kPbad2;
  const int frames = o.integrator == Integrator::Pbad4 ? 3 : 2;  // past frames q_{i-1}, ...
  const int used = o.integrator == Integrator::Pbad2 ? 1 : frames;  // frames the stencil reads
  if (static_cast<int>(s.past.size()) < frames) startup_past(m, o, s, ws, frames, &s.past);
  const VecX& q1 = s.past[0];
  p.past1 = q1;
  const Kinematics* kf[4];
  kf[0] = &frame_kinematics(m, s.qpos, ws);
  for (int f = 1; f <= used; ++f) kf[f] = &frame_kinematics(m, s.past[f - 1], ws);
  const Kinematics& k0 = *kf[0];
  const int nb = static_cast<int>(m.bodies.size());
  p.y.resize(nb);
  p.a.resize(nb);
  for (int b = 0; b < nb; ++b) {
    p.y[b] = -c[1] / c[0] * kf[0]->xcom[b];
    p.a[b] = -c[1] / c[0] * kf[0]->xmat[b];
    for (int f = 1; f <= used; ++f) {
      p.y[b] -= c[f + 1] / c[0] * kf[f]->xcom[b];
      p.a[b] -= c[f + 1] / c[0] * kf[f]->xmat[b];
    }
  }
  p.weight = 0.5 * c[0];
  p.prev_points.resize(ws.points.size());
  for (size_t i = 0; i < ws.points.size(); ++i)
    p.prev_points[i] = k0.xpos[ws.points[i].body] + k0.xmat[ws.points[i].body] * ws.points[i].local;
  // Prediction: quadratic extrapolation q_i (+) (2 (q_i - q_{i-1}) - (q_{i-1} - q_{i-2})).
  p.any_damping = false;
  for (const Joint& j : m.joints) p.any_damping = p.any_damping || j.damping > 0;
  p.any_limits = any_limits(m);
  bool moving_mesh = false, box_or_sphere = false;
  for (const Geom& g : m.geoms) {
    moving_mesh = moving_mesh || (g.body != 0 && g.contact && g.type == GeomType::Mesh);
    box_or_sphere = box_or_sphere || (g.body == 0 && g.contact && (g.type == GeomType::Box || g.type == GeomType::Sphere));
  }
  p.any_mesh_features = moving_mesh && box_or_sphere;
  p.feature_anchors.clear();
  if (p.any_mesh_features && o.contact.enabled) {
    ws.feature_contacts.clear();
    mesh_feature_contacts(m, k0, ws.obstacles, &ws.feature_contacts);
    for (const Contact& c : ws.feature_contacts)
      p.feature_anchors.push_back({c.body, k0.xmat[c.body].transpose() * (c.point - k0.xpos[c.body]), c.point, c.normal,
                                   o.contact.stiffness * c.depth});
  }
  p.q = s.qpos;
  qpos_integrate(m, p.q, 2 * qpos_difference(m, s.qpos, q1) - qpos_difference(m, q1, s.past[1]), 1.0);
  p.q_pred = p.q;
  p.step_ready = false;
  p.lambda = std::clamp(p.lambda, 1e-6, 1e-2);  // warm start from the previous step
  // Generalized-force tolerance: lm_tolerance times the model's weight times 1 m.
  double weight = 0;
  for (const Body& b : m.bodies) weight += b.mass;
  p.grad_tol = o.lm_tolerance * (weight * m.gravity.norm() + 1e-3);
  p.s_hist.clear();
  p.y_hist.clear();
  p.iterations = 0;
  p.done = false;
  p.energy = pbad_energy(m, o, s, p, p.q, ws, true);
  // Where the motion is not resolved (a whip's crack: tip links turning ~1 rad per
  // step) the quadratic predictor can overshoot into a region whose energy is far above
  // staying at q_i (100 links, dt 0.01: 404 vs -146 J), and LM from there wandered for
  // 30-50 iterations into other minimisers; start from q_i then (its poses are cached,
  // so the check costs one O(N) energy sum).
  if (pbad_energy(m, o, s, p, s.qpos, ws, false, &k0) < p.energy) {
    p.q = s.qpos;
    p.energy = pbad_energy(m, o, s, p, p.q, ws, true);
  }
}

double pbad_evaluate(const Model& m, const SimOptions& o, const State& s, const PbadStep& p, const VecX& q,
                     SimWorkspace& ws) {
  return pbad_energy(m, o, s, p, q, ws, true);
}

namespace {

// L-BFGS iteration preconditioned by the Gauss-Newton matrix: the two-loop recursion
// with H0^-1 applied by tree_solve, so the curvature the Gauss-Newton model misses
// (gravity, the stencil residual times the second derivative of X) is learnt from
// the last gradient differences; O(N) per iteration; Armijo backtracking on E.
bool lbfgs_iterate(const Model& m, const SimOptions& o, const State& s, PbadStep& p, SimWorkspace& ws) {
  const int hist = static_cast<int>(p.s_hist.size());
  VecX q = ws.grad;
  std::vector<double> alpha(hist);
  for (int i = hist - 1; i >= 0; --i) {
    alpha[i] = p.s_hist[i].dot(q) / p.y_hist[i].dot(p.s_hist[i]);
    q -= alpha[i] * p.y_hist[i];
  }
  tree_diagonal(m, ws.kin, ws.h, &ws.diag, &ws.tree);
  lm_armature(m, o, p, 1e-9, ws);
  tree_solve(m, ws.kin, ws.h, ws.arm, q, &ws.step, &ws.tree);
  for (int i = 0; i < hist; ++i) {
    const double beta = p.y_hist[i].dot(ws.step) / p.y_hist[i].dot(p.s_hist[i]);
    ws.step += p.s_hist[i] * (alpha[i] - beta);
  }
  ws.step = -ws.step;
  double slope = ws.grad.dot(ws.step);
  if (!(slope < 0)) {  // not a descent direction: restart from the preconditioner alone
    p.s_hist.clear();
    p.y_hist.clear();
    tree_solve(m, ws.kin, ws.h, ws.arm, ws.grad, &ws.step, &ws.tree);
    ws.step = -ws.step;
    slope = ws.grad.dot(ws.step);
    if (!(slope < 0)) return true;
  }
  const VecX g_old = ws.grad;
  double t = 1;
  for (int tries = 0; tries < 20; ++tries, t *= 0.5) {
    ws.q_trial = p.q;
    qpos_integrate(m, ws.q_trial, ws.step, t);
    if (!ws.q_trial.allFinite()) continue;
    const double e_trial = pbad_energy(m, o, s, p, ws.q_trial, ws, false);
    const double step_max = t * ws.step.lpNorm<Eigen::Infinity>();
    const bool tiny = step_max < o.lm_tolerance;
    if (tiny || e_trial <= p.energy + 1e-4 * t * slope) {
      const bool stalled = p.energy - e_trial < 1e-14 * (std::abs(p.energy) + 1e-300);
      p.q = ws.q_trial;
      p.energy = pbad_energy(m, o, s, p, p.q, ws, true);
      VecX sv = t * ws.step, yv = ws.grad - g_old;
      if (sv.dot(yv) > 1e-12 * sv.norm() * yv.norm()) {
        if (p.s_hist.size() >= 6) {
          p.s_hist.erase(p.s_hist.begin());
          p.y_hist.erase(p.y_hist.begin());
        }
        p.s_hist.push_back(std::move(sv));
        p.y_hist.push_back(std::move(yv));
      }
      return tiny || stalled || ws.grad.lpNorm<Eigen::Infinity>() < p.grad_tol;
    }
  }
  return true;  // no decrease along a descent direction: at a minimum to round-off
}

}  // namespace

namespace {

// Joint-space diagonal of the LM matrix: damping lambda * diag(Gauss-Newton), the
// joints' viscous damping (dissipation potential / dt) and active range penalties.
void lm_armature(const Model& m, const SimOptions& o, const PbadStep& p, double lambda, SimWorkspace& ws) {
  ws.arm = lambda * ws.diag;
  if (p.any_damping)
    for (const Joint& j : m.joints)
      for (int i = 0; i < joint_nv(j.type); ++i) ws.arm[j.vadr + i] += j.damping / o.dt;
  if (p.any_limits) ws.arm += ws.limit_h;
}

// Accuracy-aware stop: solves for the next step at the new iterate (the solve the
// next iteration would start with). If it is below lm_relative_tolerance times the
// step's correction to the quadratic predictor (a measure of the step's truncation
// error, Milne's device), it is applied without the energy test and the step ends:
// the solver error stays a small fraction of the discretisation error instead of
// being driven to round-off. Otherwise the solve is kept for the next iteration.
bool final_correction(const Model& m, const SimOptions& o, PbadStep& p, SimWorkspace& ws) {
  // Only an (almost) undamped Newton step measures the remaining error: a step shrunk
  // by LM damping (indefinite model in a whipping chain) is small without being close.
  if (p.lambda > 1e-4) return false;
  tree_diagonal(m, ws.kin, ws.h, &ws.diag, &ws.tree);
  ws.rhs = -ws.grad;
  lm_armature(m, o, p, p.lambda, ws);
  if (!tree_solve(m, ws.kin, o.exact_hessian ? ws.h_exact : ws.h, ws.arm, ws.rhs, &ws.step, &ws.tree))
    return false;  // the next iteration damps and solves again
  const double correction = qpos_difference(m, p.q, p.q_pred).lpNorm<Eigen::Infinity>();
  if (ws.step.lpNorm<Eigen::Infinity>() > o.lm_relative_tolerance * correction) {
    p.step_ready = true;
    return false;
  }
  qpos_integrate(m, p.q, ws.step, 1.0);
  ws.kin_at.resize(0);  // ws.kin is no longer at p.q
  return true;
}

}  // namespace

bool pbad_iterate(const Model& m, const SimOptions& o, const State& s, PbadStep& p, SimWorkspace& ws) {
  if (p.done) return true;
  ++p.iterations;
  if (o.solver == Solver::Lbfgs) {
    p.done = lbfgs_iterate(m, o, s, p, ws) || p.iterations >= o.lm_max_iterations;
    if (p.done) pbad_energy(m, o, s, p, p.q, ws, true);
    return p.done;
  }
  const std::vector<Mat6>& blocks = o.exact_hessian ? ws.h_exact : ws.h;
  if (!p.step_ready) {
    tree_diagonal(m, ws.kin, ws.h, &ws.diag, &ws.tree);
    ws.rhs = -ws.grad;
  }
  for (int tries = 0; tries < 12; ++tries) {
    if (!(p.step_ready && tries == 0)) {
      lm_armature(m, o, p, p.lambda, ws);
      // An indefinite Newton model (compressed links in a whip, contact) could lead to
      // a saddle: take the Gauss-Newton step (positive definite) at the same damping
      // instead. Raising lambda until the Newton model was definite (1e-6 -> 1e-2 in the
      // whip) left it above the final correction's 1e-4 for several accepted steps:
      // 100-link whip at dt 0.05, 3.57 -> 2.49 iterations per step, same drift, every
      // whip of the sweep bounded with pbad3 and pbad4 (judged with the body-point
      // velocity; with the old joint-space velocity this looked unsafe).
      if (!tree_solve(m, ws.kin, blocks, ws.arm, ws.rhs, &ws.step, &ws.tree) &&
          (&blocks == &ws.h || !tree_solve(m, ws.kin, ws.h, ws.arm, ws.rhs, &ws.step, &ws.tree))) {
        p.lambda *= 10;
        continue;
      }
    }
    p.step_ready = false;
    const double step_max = ws.step.lpNorm<Eigen::Infinity>();
    ws.q_trial = p.q;
    qpos_integrate(m, ws.q_trial, ws.step, 1.0);
    if (!ws.q_trial.allFinite()) {
      p.lambda *= 10;
      continue;
    }
    const bool tiny = step_max < o.lm_tolerance;
    // The trial is evaluated with derivatives: Newton steps are nearly always
    // accepted, and a rejected one re-evaluates the current point.
    const double e_trial = pbad_energy(m, o, s, p, ws.q_trial, ws, true);
    if (tiny || e_trial <= p.energy) {
      // Decrease at the round-off floor of E (E ~ m/dt^2 |X - Y|^2 + V): converged.
      const bool stalled = p.energy - e_trial < 1e-14 * (std::abs(p.energy) + 1e-300);
      std::swap(p.q, ws.q_trial);
      p.energy = e_trial;
      // Marquardt's original factor 10 both ways: after the whip's indefinite models
      // raised lambda, 0.3 needed ~4 accepted steps to get back below the final
      // correction's 1e-4 (100-link whip at dt 0.05: 4.8 -> 3.6 iterations per step,
      // same trajectory; smooth swings unchanged).
      p.lambda = std::max(p.lambda * 0.1, 1e-12);
      if (tiny || stalled || p.iterations >= o.lm_max_iterations || ws.grad.lpNorm<Eigen::Infinity>() < p.grad_tol)
        p.done = true;
      else if (o.lm_relative_tolerance > 0)
        p.done = final_correction(m, o, p, ws);
      return p.done;
    }
    pbad_energy(m, o, s, p, p.q, ws, true);
    p.lambda *= 10;
  }
  // No decrease possible: at a minimum to round-off.
  p.done = true;
  return true;
}

namespace {

// Velocity of the state from positions, independent of the joint parametrisation: the
// mass-weighted least-squares fit J(q_{i+1}) v ~ Xdot of the second-order backward
// difference of every body point, Xdot = (3 X_{i+1} - 4 X_i + X_{i-1}) / (2 dt):
// M v = sum_b int rho J^T Xdot (one O(N) tree solve with the spatial inertias); the
// joints' armature keeps the joint-space difference. Where two hinges pass near
// gimbal lock (a whip's tip links at 100+ rad/s) the joint angles' own difference
// quotient is wrong by orders of magnitude (Euler rates vary within a step) while the
// body points move smoothly; with ws.kin complete at s.qpos.
void projected_velocity(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws) {
  const Kinematics& k2 = frame_kinematics(m, s.past[1], ws);
  const Kinematics& k1 = frame_kinematics(m, s.past[0], ws);
  const Kinematics& k = ws.kin;
  const int nb = static_cast<int>(m.bodies.size());
  ws.w.resize(nb);
  ws.w[0].setZero();
  const double inv = 1 / (2 * o.dt);
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    const Vec3 cdot = (3 * k.xcom[b] - 4 * k1.xcom[b] + k2.xcom[b]) * inv;
    const Mat3 rdot = (3 * k.xmat[b] - 4 * k1.xmat[b] + k2.xmat[b]) * inv;
    const Mat3 rs = k.xmat[b] * second_moment(body.inertia);
    Vec3 spin = Vec3::Zero();  // int rho (R p) x (Rdot p) over the body
    for (int c = 0; c < 3; ++c) spin += rs.col(c).cross(rdot.col(c));
    ws.w[b].head<3>() = body.mass * k.xcom[b].cross(cdot) + spin;
    ws.w[b].tail<3>() = body.mass * cdot;
  }
  wrenches_to_generalized(m, k, ws.w, &ws.rhs);
  ws.arm.setZero(m.nv);
  for (const Joint& j : m.joints)
    for (int i = 0; i < joint_nv(j.type); ++i) ws.arm[j.vadr + i] = j.armature;
  ws.rhs += ws.arm.cwiseProduct(s.qvel);
  tree_solve(m, k, k.cinert, ws.arm, ws.rhs, &ws.dq, &ws.tree);
  if (ws.dq.allFinite()) s.qvel = ws.dq;
}

}  // namespace

void pbad_finish(const Model& m, const SimOptions& o, State& s, const PbadStep& p, SimWorkspace& ws) {
  const VecX& q1 = p.past1;
  const VecX a = qpos_difference(m, p.q, s.qpos);
  const VecX b = qpos_difference(m, s.qpos, q1);
  // Second-order backward difference in joint space, the schemes' order; the state's
  // velocity is its body-point form (projected_velocity), which this one only seeds
  // (armature) and replaces if the projection fails.
  s.qvel = (3 * a - b) / (2 * o.dt);
  // Shift the history q_{i-1} .. q_{i-k} (reusing the vectors' storage).
  if (s.past.empty()) s.past.push_back(q1);  // pbad_begin always fills it; defensive
  for (size_t f = s.past.size() - 1; f > 0; --f) std::swap(s.past[f], s.past[f - 1]);
  std::swap(s.past[0], s.qpos);
  s.qpos = p.q;
  // Full kinematics (the velocity's tree solve needs cdof and cinert); the poses serve
  // next step's friction (normal forces) and go to the past-frame cache.
  if (!(ws.kin_at.size() == s.qpos.size() && ws.kin_at == s.qpos)) {
    kinematics(m, s.qpos, &ws.kin);
    ws.kin_at = s.qpos;
  }
  projected_velocity(m, o, s, ws);
  s.normal_force_prev.assign(ws.points.size() * ws.obstacles.size(), 0.0);
  find_contacts(m, ws.kin, ws.points, ws.obstacles, &ws.contacts);
  for (const Contact& c : ws.contacts)
    if (c.slot >= 0) s.normal_force_prev[c.slot] = o.contact.stiffness * c.depth;
  frame_store(s.qpos, ws);  // next step's q_i
  s.time += o.dt;
  ++s.step;
}

bool sim_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws, StepInfo* info) {
  sim_prepare(m, ws);
  const double dt = o.dt;
  StepInfo si;
  switch (o.integrator) {
    case Integrator::Pbad2:
    case Integrator::Pbad3:
    case Integrator::Pbad4: {
      PbadStep& p = ws.pbad;
      pbad_begin(m, o, s, p, ws);
      while (!pbad_iterate(m, o, s, p, ws)) {
      }
      si.iterations = p.iterations;
      si.converged = p.iterations < o.lm_max_iterations;
      si.energy_residual = ws.grad.lpNorm<Eigen::Infinity>();
      pbad_finish(m, o, s, p, ws);
      break;
    }
    case Integrator::Euler: {
      VecX a;
      accel(m, o, s, s.qpos, s.qvel, ws, &a);
      s.qvel += dt * a;
      qpos_integrate(m, s.qpos, s.qvel, dt);
      s.time += dt;
      ++s.step;
      break;
    }
    case Integrator::Rk4: {
      const VecX q0 = s.qpos, v0 = s.qvel;
      VecX a1, a2, a3, a4;
      accel(m, o, s, q0, v0, ws, &a1);
      VecX q = q0;
      qpos_integrate(m, q, v0, dt / 2);
      const VecX v2 = v0 + dt / 2 * a1;
      accel(m, o, s, q, v2, ws, &a2);
      q = q0;
      qpos_integrate(m, q, v2, dt / 2);
      const VecX v3 = v0 + dt / 2 * a2;
      accel(m, o, s, q, v3, ws, &a3);
      q = q0;
      qpos_integrate(m, q, v3, dt);
      const VecX v4 = v0 + dt * a3;
      accel(m, o, s, q, v4, ws, &a4);
      s.qpos = q0;
      qpos_integrate(m, s.qpos, (v0 + 2 * v2 + 2 * v3 + v4) / 6, dt);
      s.qvel = v0 + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
      s.time += dt;
      ++s.step;
      break;
    }
  }
  if (info) *info = si;
  return finite(s.qpos) && finite(s.qvel);
}

Energy state_energy(const Model& m, const SimOptions& o, const State& s, SimWorkspace& ws) {
  sim_prepare(m, ws);
  kinematics(m, s.qpos, &ws.kin);
  ws.kin_at.resize(0);
  Energy e;
  e.kinetic = kinetic_energy(m, ws.kin, s.qvel);
  e.potential = potential_energy(m, ws.kin) + limit_terms(m, o, s.qpos, nullptr, nullptr);
  if (o.contact.enabled) {
    find_contacts(m, ws.kin, ws.points, ws.obstacles, &ws.contacts);
    for (const Contact& c : ws.contacts) e.potential += 0.5 * o.contact.stiffness * c.depth * c.depth;
  }
  e.total = e.kinetic + e.potential;
  return e;
}

}  // namespace pliant::articulated
