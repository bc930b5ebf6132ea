// Internals shared by the integrator files: sim.cpp (entry points, state helpers),
// explicit_integrators.cpp (Euler, RK4), pbad_energy.cpp (the step's energy and its
// derivatives), pbad_solver.cpp (LM / L-BFGS iterations), pbad_step.cpp (begin/finish)
// and joint_limits.cpp (range penalties).
#pragma once
#include <vector>

#include "pliant/articulated/sim.h"

namespace pliant::articulated {

inline Mat3 second_moment(const Mat3& inertia) {  // integral rho p p^T about the centre
  return 0.5 * inertia.trace() * Mat3::Identity() - inertia;
}

// Generalized actuator forces gear * clamp(ctrl) (sim.cpp).
void actuator_forces(const Model& m, const State& s, VecX* tau);

// Joint-range penalty 1/2 k (q - bound)^2 beyond each limited hinge/slide (and ball
// cone / swing-twist limits) plus the hinge/slide springs 1/2 k_s (q - springref)^2:
// returns the energy; optionally its gradient and (diagonal) Hessian in joint space
// (joint_limits.cpp). any_limits: whether a model has any of these terms.
double limit_terms(const Model& m, const SimOptions& o, const VecX& q, VecX* force, VecX* hdiag);
bool any_limits(const Model& m);

// Regularisation of joint i-th dof's dry friction (Joint::frictionloss): F (sqrt(dq^2 +
// eps^2) - eps) per step, eps the contact's slip_eps for linear dofs (slide, a free
// joint's translation) and spin_eps for rotations, so it holds a joint as the contact
// friction holds a point.
inline double frictionloss_eps(const SimOptions& o, const Joint& j, int i) {
  const bool linear = j.type == JointType::Slide || (j.type == JointType::Free && i < 3);
  return linear ? o.contact.slip_eps : o.contact.spin_eps;
}

// Torsional / rolling friction (condim 4 / 6, spin_friction.cpp). Whether any geom or
// explicit pair asks for it (the loops skip it otherwise).
bool any_spin_friction(const Model& m);
// A body's rotation over the step, world frame: phi = axial(R R0^T) (the rotation
// vector's sin-scaled form, = the rotation vector to O(|phi|^3)), and its Jacobian
// d phi / d theta for a world-frame rotation increment theta of R.
Vec3 rotation_increment(const Mat3& r, const Mat3& r0, Mat3* jac);
// Dissipation potential of a contact with normal n and normal force fn on the relative
// rotation phi: mu_t fn (sqrt(phi_n^2 + eps^2) - eps) + mu_r fn (sqrt(|phi_t|^2 + eps^2)
// - eps) (phi_n = n.phi, phi_t = phi - phi_n n; mu_r 0 for condim 4). Returns it, its
// gradient in phi and (hess non-null) its Gauss-Newton Hessian g_n n n^T + g_t P_t.
// Explicit integrators call it with phi = omega dt: torque -grad.
double spin_friction(double fn, const Vec3& n, const Vec3& phi, double mu_t, double mu_r, double eps, Vec3* grad,
                     Mat3* hess);

// Energy of PBAD at q; with derivs also per-body wrenches (gradient) and Gauss-Newton
// blocks in ws.w / ws.h and the generalized gradient in ws.grad.
// With poses (kinematics at q, derivs false) the kinematics pass is skipped
// (pbad_energy.cpp).
double pbad_energy(const Model& m, const SimOptions& o, const State& s, const PbadStep& p,
                   const VecX& q, SimWorkspace& ws, bool derivs, const Kinematics* poses = nullptr);

// LM's linear solve: tree_solve with the per-body blocks and ws.arm, plus the
// body-body contacts' rank-1 terms (ws.pair_terms) by Woodbury's identity
// (A + U W U^T)^-1 r = z - A^-1 U (W^-1 + U^T A^-1 U)^-1 U^T z, z = A^-1 r: one
// resolve (A's elimination reused) per term on the trees it touches, the capacitance
// per group of terms coupled through shared trees. Returns tree_solve's
// positive-definiteness flag for A (lm_solve.cpp); with indefinite_fails an
// indefinite A returns false at once, x then holding A's solve only (LM's callers fall
// back to Gauss-Newton or raise lambda and never use it).
bool lm_solve(const Model& m, const std::vector<Mat6>& blocks, const VecX& rhs, VecX* x, SimWorkspace& ws,
              bool indefinite_fails = false);

// Dry joint friction in the explicit integrators and PBAD's start-up (joint_friction.cpp):
// whether any joint has frictionloss, and the constant generalized force over the next
// step that stops the friction dofs of v_pred = v + dt a where the bound F dt allows and
// opposes them with it where not (k complete at q); accel gets M^-1 of it.
bool any_frictionloss(const Model& m);
VecX joint_friction_force(const Model& m, const SimOptions& o, const Kinematics& k, const VecX& v_pred, VecX* accel);

// Joint accelerations of the explicit integrators at (q, v), with contact, limit and
// actuator forces (explicit_integrators.cpp); PBAD's start-up frames use it too.
// extra_force: a generalized force added to tau (dry joint friction held over a step).
void accel(const Model& m, const SimOptions& o, const State& s, const VecX& q, const VecX& v,
           SimWorkspace& ws, VecX* a, const VecX* extra_force = nullptr);
// One step of semi-implicit Euler / classic RK4 (explicit_integrators.cpp).
void euler_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws);
void rk4_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws);
// One classic RK4 step of (q, v) by h, in place (h < 0 runs backwards: PBAD's
// start-up frames). ws.contacts / ws.pair_contacts hold the last stage's contacts.
// first_accel: the first stage's acceleration when the caller already has it (with
// extra_force included).
void rk4_advance(const Model& m, const SimOptions& o, const State& s, double h, VecX& q, VecX& v,
                 SimWorkspace& ws, const VecX* extra_force = nullptr, const VecX* first_accel = nullptr);

}  // namespace pliant::articulated
