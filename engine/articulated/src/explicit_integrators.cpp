// Explicit baselines (sim.h): semi-implicit (symplectic) Euler and classic RK4 on
// M qacc = tau - bias, with penalty contact (spring-damper normal, regularised Coulomb
// or Ck friction), joint-range penalties, actuator forces and dry joint friction.
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// Generalized contact + actuator forces for explicit integrators at (k, qvel).
void explicit_forces(const Model& m, const SimOptions& o, const State& s, const Kinematics& k, const VecX& qpos,
                     const VecX& qvel, SimWorkspace& ws, VecX* tau, std::vector<Contact>* record) {
  actuator_forces(m, s, tau);
  if (any_limits(m)) {
    limit_terms(m, o, qpos, &ws.limit_force, nullptr);
    *tau -= ws.limit_force;
  }
  ws.contacts.clear();
  ws.pair_contacts.clear();
  if (!o.contact.enabled) return;
  if (!ws.points.empty() && !ws.obstacles.empty()) find_contacts(m, k, ws.points, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &ws.contacts);
  if (pair_contact_on(m, o.contact)) find_pair_contacts(m, k, ws.pairs, &ws.pair_contacts, o.contact.self_collision, &ws.broadphase);
  if (ws.contacts.empty() && ws.pair_contacts.empty()) return;
  const int nb = static_cast<int>(m.bodies.size());
  std::vector<Vec6> v(nb), w(nb, Vec6::Zero());
  v[0].setZero();
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    v[b] = v[body.parent];
    for (int d = body.dof_begin; d < body.dof_begin + body.dof_count; ++d) v[b] += k.cdof[d] * qvel[d];
  }
  // Spring-damper normal force and regularised friction on the point's velocity
  // (relative to the other body's material point for body-body contacts).
  const auto contact_force = [&](const Vec3& vp, const Vec3& n, double depth, double mu, bool frictionless = false) {
    const double vn = vp.dot(n);
    const double fn = std::max(0.0, o.contact.stiffness * depth - o.contact.damping * vn);
    const Vec3 vt = vp - vn * n;
    Vec3 ft = Vec3::Zero();
    if (frictionless) {
    } else if (o.contact.friction == FrictionModel::Coulomb) {
      const double eps = o.contact.slip_eps / o.dt;
      ft = -mu * fn * vt / std::sqrt(vt.squaredNorm() + eps * eps);
    } else if (o.contact.friction == FrictionModel::Ck) {
      ft = -o.contact.ck * fn * vt;
    }
    return Vec3(fn * n + ft);
  };
  // Torsional / rolling friction (condim 4 / 6, coulomb model) on the relative angular
  // velocity: spin_friction's gradient at phi = omega dt, i.e. regularised with eps/dt.
  const auto spin_torque = [&](int b, int a, double fn, const Vec3& n, const ContactMix& mix) {
    if (o.contact.friction != FrictionModel::Coulomb || fn <= 0) return;
    Vec3 g;
    const Vec3 om = v[b].head<3>() - (a > 0 ? Vec3(v[a].head<3>()) : Vec3::Zero());
    spin_friction(fn, n, om * o.dt, mix.torsion, mix.condim == 6 ? mix.roll : 0, o.contact.spin_eps, &g, nullptr);
    w[b].head<3>() -= g;
    if (a > 0) w[a].head<3>() += g;
  };
  for (Contact& c : ws.contacts) {
    c.force = contact_force(v[c.body].tail<3>() + v[c.body].head<3>().cross(c.point), c.normal, c.depth,
                            contact_mu(c.mix, o.contact.mu), c.mix.frictionless);
    w[c.body] += point_wrench(c.point, c.force);
    if (c.mix.condim > 3) spin_torque(c.body, 0, c.force.dot(c.normal), c.normal, c.mix);
  }
  for (const PairContact& c : ws.pair_contacts) {
    const Vec3 va = v[c.body_a].tail<3>() + v[c.body_a].head<3>().cross(c.point);
    const Vec3 vb = v[c.body_b].tail<3>() + v[c.body_b].head<3>().cross(c.point);
    const Vec3 f =
        contact_force(vb - va, c.normal, c.depth * c.gain, contact_mu(c.mix, o.contact.mu), c.mix.frictionless);
    w[c.body_b] += point_wrench(c.point, f);
    w[c.body_a] -= point_wrench(c.point, f);
    if (c.mix.condim > 3) spin_torque(c.body_b, c.body_a, f.dot(c.normal), c.normal, c.mix);
  }
  VecX tc;
  wrenches_to_generalized(m, k, w, &tc);
  *tau += tc;
  if (record) *record = ws.contacts;
}

}  // namespace

void accel(const Model& m, const SimOptions& o, const State& s, const VecX& q, const VecX& v,
           SimWorkspace& ws, VecX* a, const VecX* extra_force) {
  kinematics(m, q, &ws.kin);
  ws.kin_at.resize(0);
  VecX tau;
  explicit_forces(m, o, s, ws.kin, q, v, ws, &tau, nullptr);
  if (extra_force) tau += *extra_force;
  forward_dynamics(m, ws.kin, v, tau, a, &ws.tree);
}

// Semi-implicit Euler; with dry joint friction the velocity update is the projected one
// (v_pred + M^-1 lambda: a joint that can stick ends the step at rest).
void euler_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws) {
  const double dt = o.dt;
  VecX a;
  accel(m, o, s, s.qpos, s.qvel, ws, &a);
  if (any_frictionloss(m)) {
    VecX af;
    joint_friction_force(m, o, ws.kin, s.qvel + dt * a, &af);
    a += af;
  }
  s.qvel += dt * a;
  qpos_integrate(m, s.qpos, s.qvel, dt);
  s.time += dt;
  ++s.step;
}

void rk4_advance(const Model& m, const SimOptions& o, const State& s, double h, VecX& q, VecX& v,
                 SimWorkspace& ws, const VecX* extra_force, const VecX* first_accel) {
  VecX a1, a2, a3, a4, qs;
  if (first_accel) a1 = *first_accel;
  else accel(m, o, s, q, v, ws, &a1, extra_force);
  qs = q;
  qpos_integrate(m, qs, v, h / 2);
  const VecX v2 = v + h / 2 * a1;
  accel(m, o, s, qs, v2, ws, &a2, extra_force);
  qs = q;
  qpos_integrate(m, qs, v2, h / 2);
  const VecX v3 = v + h / 2 * a2;
  accel(m, o, s, qs, v3, ws, &a3, extra_force);
  qs = q;
  qpos_integrate(m, qs, v3, h);
  const VecX v4 = v + h * a3;
  accel(m, o, s, qs, v4, ws, &a4, extra_force);
  qpos_integrate(m, q, (v + 2 * v2 + 2 * v3 + v4) / 6, h);
  v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
}

// Classic RK4; dry joint friction enters as Euler's friction force of this step (from
// the first stage's acceleration) held constant over the stages: a sticking joint stays
// put, a sliding one decelerates at F / I, but the friction part is first order in dt.
void rk4_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws) {
  VecX q = s.qpos, v = s.qvel;  // accel reads s (actuators) while the stages run
  if (any_frictionloss(m)) {
    VecX a, af;
    accel(m, o, s, q, v, ws, &a);
    const VecX friction = joint_friction_force(m, o, ws.kin, v + o.dt * a, &af);
    a += af;  // the first stage with the friction force (accel is linear in it)
    rk4_advance(m, o, s, o.dt, q, v, ws, &friction, &a);
  } else {
    rk4_advance(m, o, s, o.dt, q, v, ws);
  }
  s.qpos = q;
  s.qvel = v;
  s.time += o.dt;
  ++s.step;
}

}  // namespace pliant::articulated
