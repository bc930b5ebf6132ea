// One PBAD step's set-up and wrap-up (sim.h): start-up frames, the stencil's targets
// from the past frames' poses (cached), the predictor, friction anchors (pbad_begin);
// the history shift, the body-point velocity and next step's normal forces
// (pbad_finish).
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// q(-dt) and q(-2 dt) before the first step. A multistep stencil needs its start-up
// frames on the true trajectory (a second-order Taylor guess leaves an O(dt^3) kink
// that excites fast modes, which PBAD then damps: 0.1% of the swing energy of a 10-link
// chain at dt 0.05). Without contact they come from RK4 run backwards in time with
// substeps of at most dt/4 and 10 ms (2.5 ms gave the same drifts to 5 digits for
// 10-100 links at dt 0.01-0.1 and cost 14% of a 10-link step at dt 0.04); with
// contact (stiff penalty, friction that would run backwards) or dry joint friction
// from the Taylor expansion with the initial acceleration.
void startup_past(const Model& m, const SimOptions& o, const State& s, SimWorkspace& ws, int frames,
                  std::vector<VecX>* past) {
  VecX a;
  accel(m, o, s, s.qpos, s.qvel, ws, &a);
  const double dt = o.dt;
  // Dry joint friction would run backwards too (a joint held by it would fall in the
  // past frames): Taylor with the friction-projected acceleration (zero where it sticks).
  const bool friction = any_frictionloss(m);
  if (friction && a.allFinite()) {
    VecX af;
    joint_friction_force(m, o, ws.kin, s.qvel + dt * a, &af);
    a += af;
  }
  if (!a.allFinite()) a.setZero();
  past->assign(frames, s.qpos);
  for (int f = 1; f <= frames; ++f)
    qpos_integrate(m, (*past)[f - 1], -f * dt * s.qvel + 0.5 * f * f * dt * dt * a, 1.0);
  if (friction) return;
  if (o.contact.enabled && (!ws.contacts.empty() || !ws.pair_contacts.empty())) return;  // accel() found contacts at q0
  const int sub = std::max(4, static_cast<int>(std::ceil(dt / 0.01)));
  const double h = -dt / sub;
  VecX q = s.qpos, v = s.qvel;
  for (int frame = 1; frame <= frames; ++frame) {
    for (int i = 0; i < sub; ++i) {
      rk4_advance(m, o, s, h, q, v, ws);
      if (!ws.contacts.empty() || !ws.pair_contacts.empty()) return;  // touched on the way back: keep Taylor
    }
    if (!q.allFinite() || !v.allFinite()) return;
    (*past)[frame - 1] = q;
  }
}

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
    find_contacts(m, ws.kin, ws.points, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &ws.contacts);
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
  // Armature: the same stencil on the joint coordinates, in the tangent space at q_i
  // (exact for hinges and slides; for ball / free rotations the per-step rotation
  // vectors are added as vectors, first order in the step's turn).
  p.any_armature = false;
  for (const Joint& j : m.joints) p.any_armature = p.any_armature || j.armature > 0;
  if (p.any_armature) {
    p.armature_target.setZero(m.nv);
    for (int f = 1; f <= used; ++f) p.armature_target -= c[f + 1] / c[0] * qpos_difference(m, s.past[f - 1], s.qpos);
  }
  p.prev_points.resize(ws.points.size());
  p.prev_local.resize(ws.points.size());
  for (size_t i = 0; i < ws.points.size(); ++i) {
    const int b = ws.points[i].body;
    p.prev_local[i] = contact_point_local(m, ws.points[i], k0.xmat[b]);
    p.prev_points[i] = k0.xpos[b] + k0.xmat[b] * p.prev_local[i];
  }
  const size_t no = ws.obstacles.size();
  p.point_pressed.assign(ws.points.size(), 0);
  for (size_t slot = 0; slot < s.normal_force_prev.size(); ++slot)
    if (s.normal_force_prev[slot] > 0) p.point_pressed[slot / no] = 1;
  // Torsional / rolling friction (condim 4 / 6) measure each body's rotation from q_i.
  // Sliding friction at sphere / capsule / margin contact points maps the contact arm
  // back to q_i with the same rotations (pbad_energy.cpp).
  p.any_spin = o.contact.enabled && o.contact.friction == FrictionModel::Coulomb && any_spin_friction(m);
  if (o.contact.enabled && o.contact.friction != FrictionModel::None) {
    p.prev_rot.resize(nb);
    for (int b = 0; b < nb; ++b) p.prev_rot[b] = k0.xmat[b];
  }
  // Prediction: quadratic extrapolation q_i (+) (2 (q_i - q_{i-1}) - (q_{i-1} - q_{i-2})).
  p.any_damping = false;
  for (const Joint& j : m.joints) p.any_damping = p.any_damping || j.damping > 0;
  p.any_frictionloss = any_frictionloss(m);
  p.any_limits = any_limits(m);
  bool moving_mesh = false, static_feature = false;
  for (const Geom& g : m.geoms) {
    moving_mesh = moving_mesh || (g.body != 0 && g.contact && g.type == GeomType::Mesh);
    static_feature = static_feature || (g.body == 0 && g.contact &&
                                      (g.type == GeomType::Box || g.type == GeomType::Sphere || g.type == GeomType::Mesh));
  }
  p.any_mesh_features = moving_mesh && static_feature;  // box corners, spheres, static mesh vertices
  p.feature_anchors.clear();
  if (p.any_mesh_features && o.contact.enabled) {
    ws.feature_contacts.clear();
    mesh_feature_contacts(m, k0, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &ws.feature_contacts);
    for (const Contact& c : ws.feature_contacts)
      if (!c.mix.frictionless)  // condim 1: no friction anchor
        p.feature_anchors.push_back({c.body, k0.xmat[c.body].transpose() * (c.point - k0.xpos[c.body]), c.point,
                                     c.normal, o.contact.stiffness * c.depth, contact_mu(c.mix, o.contact.mu),
                                     c.mix.condim, c.mix.torsion, c.mix.roll});
  }
  p.any_pairs = pair_contact_on(m, o.contact) && !ws.pairs.empty();
  p.pair_anchors.clear();
  if (p.any_pairs && o.contact.friction != FrictionModel::None) {
    find_pair_contacts(m, k0, ws.pairs, &ws.pair_contacts, o.contact.self_collision, &ws.broadphase);
    for (const PairContact& c : ws.pair_contacts)
      if (!c.mix.frictionless)  // condim 1: no friction anchor
        p.pair_anchors.push_back({c.body_a, c.body_b, k0.xmat[c.body_a].transpose() * (c.point - k0.xpos[c.body_a]),
                                  k0.xmat[c.body_b].transpose() * (c.point - k0.xpos[c.body_b]), c.normal,
                                  o.contact.stiffness * c.depth * c.gain, contact_mu(c.mix, o.contact.mu), c.mix.condim,
                                  c.mix.torsion, c.mix.roll});
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
  } else {
    // The check left q_i's joint motion (zero) in ws.dq, where lm_armature reads the
    // iterate's: frictionloss's weight F / |dq| became F / eps (2e5 for F = 0.02), every
    // Newton step ~1e-8 rad, and the step ended at the predictor after one iteration.
    ws.dq = qpos_difference(m, p.q, s.qpos);
  }
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
  find_contacts(m, ws.kin, ws.points, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &ws.contacts);
  for (const Contact& c : ws.contacts)
    if (c.slot >= 0) s.normal_force_prev[c.slot] = o.contact.stiffness * c.depth;
  frame_store(s.qpos, ws);  // next step's q_i
  s.time += o.dt;
  ++s.step;
}

}  // namespace pliant::articulated
