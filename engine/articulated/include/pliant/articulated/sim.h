// Time integration of a Model: PBAD (position-based collocation, Pan & Manocha,
// WAFR 2018; dissertation ch. 5) and explicit baselines.
//
// PBAD: each step finds q_{i+1} as the minimiser of
//   E(q) = sum_bodies w/dt^2 * integral rho |X(q, p) - Y(p)|^2 dp + V(q) + contact(q)
//          + friction(q) - tau . (q - q_i)
// whose stationarity is Newton-Euler's equation with the body-point acceleration
// replaced by a backward finite difference of positions, collocated at t_{i+1}:
//   pbad2: X'' ~ (X_{i+1} - 2 X_i + X_{i-1}) / dt^2                (w = 1/2)
//   pbad3: X'' ~ (2 X_{i+1} - 5 X_i + 4 X_{i-1} - X_{i-2}) / dt^2  (w = 1, 2nd-order accurate)
//   pbad4: X'' ~ (5 X_{i+1} - 14 X_i + 14 X_{i-1} - 6 X_{i-2} + X_{i-3}) / (2 dt^2)  (w = 5/4)
//          = pbad3's stencil + 1/2 of the 4th difference: still 2nd-order accurate, and
//          the one member of that family whose O((omega dt)^4) energy damping per step
//          vanishes (left: O((omega dt)^6)); its extra roots (|z| = 0.45) are damped and it
//          stays stable for any omega dt on y'' = -omega^2 y (see README, "pbad4").
// Y is the same stencil applied to the past frames. Because X is affine in p per
// body, the integral is exact with mass, centre and second moment (12 numbers of
// pose per body). Solver: Levenberg-Marquardt; its Gauss-Newton matrix is
// (2w/dt^2) M(q) plus the contact terms, solved in O(N) by the articulated-body
// recursion (tree_solve), so one iteration costs O(N + contacts). A step starts from
// the quadratic predictor, or from q_i when its energy is lower (unresolved whips).
// The state's velocity after a PBAD step is the mass-weighted fit of the joint
// velocities to the body points' (3 X_{i+1} - 4 X_i + X_{i-1}) / (2 dt), one more tree
// solve: independent of the joint parametrisation (hinge pairs near gimbal lock).
// Euler: semi-implicit (symplectic) Euler on M qacc = tau - bias; RK4: classic.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "pliant/articulated/contact.h"
#include "pliant/articulated/dynamics.h"

namespace pliant::articulated {

enum class Integrator { Pbad2, Pbad3, Euler, Rk4, Pbad4 };  // new ones appended
// True for the PBAD family (pbad2/3/4).
bool integrator_is_pbad(Integrator i);
// PBAD's per-step minimiser: Levenberg-Marquardt on the exact Hessian (Gauss-Newton
// blocks plus the geometric term of the forces' curvature, still O(N) through
// tree_solve) or on the Gauss-Newton model alone, or L-BFGS preconditioned by the
// Gauss-Newton solve (all O(N) per iteration).
enum class Solver { Lm, Lbfgs };
Integrator integrator_from_name(const std::string& name);  // throws std::invalid_argument
std::string integrator_name(Integrator i);

struct SimOptions {
  Integrator integrator = Integrator::Pbad3;
  double dt = 0.01;
  ContactOptions contact;
  Solver solver = Solver::Lm;
  int lm_max_iterations = 50;
  // LM matrix: exact Hessian (Newton; converges in a few iterations at large dt,
  // where the chain's tension makes the geometric term comparable to M/dt^2) or the
  // Gauss-Newton matrix (2w/dt^2) M(q) + contact terms (PD, linear convergence).
  // Where the exact Hessian is indefinite LM takes the Gauss-Newton step there.
  bool exact_hessian = true;
  // Stop when max |dq| of a step is below this (rad or m), or when max |gradient| is
  // below it times the model's weight (N) times 1 m.
  double lm_tolerance = 1e-7;
  // Accuracy-aware stop (0: off): once the next Newton step is below this times the
  // step's correction to the quadratic predictor (a measure of the step's truncation
  // error), apply it and stop.
  double lm_relative_tolerance = 1e-2;
};

struct State {
  double time = 0;
  int step = 0;
  VecX qpos, qvel, ctrl;
  std::vector<VecX> past;        // PBAD: q_{i-1}, q_{i-2} (pbad4: and q_{i-3})
  std::vector<double> normal_force_prev;  // PBAD friction: normal force of each contact slot last step
};

struct StepInfo {
  int iterations = 0;
  bool converged = true;
  double energy_residual = 0;  // max |gradient| at the end (PBAD)
};

// Friction of an obstacle corner/sphere against a moving mesh (contact.h): the mesh's
// material point under it at q_i, the obstacle point, its normal and normal force.
struct FeatureAnchor {
  int body;
  Vec3 local, point, normal;
  double normal_force;
  double mu = -1;  // the contact's Coulomb coefficient (contact_mu, resolved)
  int condim = 3;  // 4 / 6: torsional / rolling friction with these coefficients (m)
  double torsion = 0, roll = 0;
};

// Friction of a body-body contact (find_pair_contacts) found at q_i: the material
// points of both bodies at the contact point (local frames), its normal and normal
// force; the slip is the two points' relative displacement over the step.
struct PairAnchor {
  int body_a, body_b;
  Vec3 local_a, local_b, normal;
  double normal_force;
  double mu = -1;  // the contact's Coulomb coefficient (contact_mu, resolved)
  int condim = 3;  // 4 / 6: torsional / rolling friction with these coefficients (m)
  double torsion = 0, roll = 0;
};

struct PbadStep {
  std::vector<Vec3> y;  // target centre per body
  std::vector<Mat3> a;  // target rotation per body
  std::vector<Vec3> prev_points;  // world positions of contact points at q_i
  // Their body-frame places at q_i (a support point's moves on its body: friction acts
  // on the material point that touched at q_i, so an ellipsoid rolls).
  std::vector<Vec3> prev_local;
  std::vector<char> point_pressed;  // per contact point: a normal force on it at q_i (friction)
  bool any_spin = false;          // condim 4 / 6 somewhere (any_spin_friction)
  std::vector<Mat3> prev_rot;     // body rotations at q_i (contact with friction on)
  VecX q;               // current iterate
  VecX past1;           // q_{i-1} (start-up frame on the first step)
  VecX q_pred;          // predictor (quadratic extrapolation)
  bool step_ready = false;  // ws.step/diag/rhs already hold the next LM solve
  double energy = 0, lambda = 1e-6, weight = 0.5;
  bool any_damping = false, any_limits = false, any_frictionloss = false;
  // Joint armature (rotor inertia in joint space): the stencil's target displacement
  // from q_i per dof, -(c_2 (q_{i-1} - q_i) + c_3 (q_{i-2} - q_i) + ...) / c_0.
  bool any_armature = false;
  VecX armature_target;
  bool any_mesh_features = false;  // a moving mesh and a static box or sphere (contact.h)
  std::vector<FeatureAnchor> feature_anchors;  // their contacts at q_i (friction)
  bool any_pairs = false;  // self_collision on or explicit pairs, and candidate geom pairs exist
  std::vector<PairAnchor> pair_anchors;  // body-body contacts at q_i (friction)
  double grad_tol = 0;
  std::vector<VecX> s_hist, y_hist;  // L-BFGS pairs
  int iterations = 0;
  bool done = false;
};

// One rank-1 term weight * u u^T of a body-body contact's Gauss-Newton matrix, u the
// generalized force of a unit force `dir` at point_b on body_b and -dir at point_a on
// body_a (normal: weight k; friction: one term per tangent direction). The LM solve
// adds them to the tree solve's per-body blocks exactly (Woodbury, lm_solve.cpp).
struct PairTerm {
  int body_a, body_b;
  Vec3 point_a, point_b, dir;
  double weight;
};
// A term as lm_solve uses it: weight * u u^T, u the generalized force of wrench wb on
// body_b and wa on body_a (world frame). A body pair with more than
// kMaxTermsPerBodyPair terms has them merged into at most 12 (their sum is a 12 x 12
// matrix in the two bodies' wrench space, factored by pivoted LDL^T).
struct WrenchTerm {
  int body_a, body_b;
  Vec6 wa, wb;
  double weight;
};
constexpr int kMaxTermsPerBodyPair = 12;

// Per-trajectory scratch (no allocation once warm).
struct SimWorkspace {
  Kinematics kin;
  VecX kin_at;  // qpos of kin when it is complete (cdof, cinert), else empty
  std::vector<Kinematics> frame_kin;  // poses of recent frames q_i .. q_{i-3}
  std::vector<VecX> frame_q;
  std::vector<long> frame_stamp;
  long frame_clock = 0;
  TreeWorkspace tree;
  std::vector<Mat6> h;        // Gauss-Newton blocks (LM damping scale, L-BFGS)
  std::vector<Mat6> h_exact;  // plus the transposed geometric blocks (Newton)
  std::vector<Mat3> moment;   // per body sum x f^T of the energy's point gradients
  std::vector<Vec3> force;    // per body sum f
  std::vector<Vec6> w;
  VecX limit_force, limit_h;  // joint-range penalty gradient and Hessian diagonal
  VecX grad, step, q_trial, diag, arm, rhs, tau, dq;
  std::vector<Contact> contacts;
  std::vector<Contact> feature_contacts;  // obstacle corners against moving meshes (PBAD energy)
  std::vector<ContactPoint> points;  // cached from the model on first use
  std::vector<GeomPair> pairs;       // body-body candidates (contact_geom_pairs), cached
  PairBroadphase broadphase;         // over pairs (pair_broadphase), cached with them
  std::vector<PairContact> pair_contacts;
  std::vector<PairTerm> pair_terms;  // at the last evaluation with derivatives
  std::vector<WrenchTerm> wrench_terms;  // lm_solve's (pair_terms, merged per body pair)
  // pair_terms as (body pair key, index), sorted: runs of one pair start at run_begin;
  // run_order lists the runs in order of appearance.
  std::vector<std::pair<long, int>> term_order;
  std::vector<int> run_begin, run_order;
  Eigen::MatrixXd pair_u, pair_y;  // columns u, A^-1 u (capacity grows)
  std::vector<std::array<int, 2>> col_trees;  // trees each column was last written at (-1: none)
  VecX pair_alpha;
  // Nonzero rows of each column u (the two bodies' ancestors' dofs): term t's are
  // pair_nz[pair_nz_begin[t] .. pair_nz_begin[t + 1]).
  std::vector<int> pair_nz, pair_nz_begin;
  // The trees each term touches (1 or 2), the terms of each tree, and the groups of
  // terms coupled through shared trees (the capacitance's diagonal blocks).
  Forest forest;  // model_forest, cached
  std::vector<std::array<int, 2>> term_trees;
  std::vector<int> term_tree_count, term_stamp, term_pos, tree_link, tree_group, term_group, group_terms,
      group_begin, group_fill;
  std::vector<std::vector<int>> tree_terms;
  Eigen::MatrixXd group_cap;
  VecX group_alpha;
  std::vector<int> obstacles;
  std::vector<MeshBvh> obstacle_trees;  // per obstacle: a mesh's tree (obstacle_trees), cached
  std::vector<MeshBvh> mesh_trees;      // per geom: a moving mesh's tree (moving_mesh_trees), cached
  bool geom_mix = false;  // geom_contact_params_set(model), cached
  const Model* cached_for = nullptr;
  PbadStep pbad;  // sim_step's PBAD iterate
};
// Caches the model's contact points and obstacles in ws (cheap when already done).
void sim_prepare(const Model& m, SimWorkspace& ws);

// Swing-cone / twist-range penalty of ball joint j (joint_limits.cpp) at quaternion
// qb (w x y z): energy, gradient and exact Hessian in the joint's local rotation
// vector (q exp(dv) at dv = 0). The LM model takes hessian_diagonal_bound(H), a
// diagonal D with D - H positive semi-definite (Gershgorin), because the tree solve
// takes joint-space terms as a diagonal.
double ball_swing_twist_penalty(const Joint& j, double k, Eigen::Vector4d qb, Vec3* grad, Mat3* hess);
Vec3 hessian_diagonal_bound(const Mat3& h);

State state_init(const Model& m);
// One step of the chosen integrator; returns false if the state became non-finite.
bool sim_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws, StepInfo* info = nullptr);

// PBAD internals exposed for the batched scheduler: begin (prediction and targets),
// one LM iteration (returns true when converged), finish (shift history, velocity).
void pbad_begin(const Model& m, const SimOptions& o, State& s, PbadStep& p, SimWorkspace& ws);
bool pbad_iterate(const Model& m, const SimOptions& o, const State& s, PbadStep& p, SimWorkspace& ws);
// PBAD energy at q for the step set up by pbad_begin, with its gradient in ws.grad and
// the Gauss-Newton / exact blocks in ws.h / ws.h_exact (tests, diagnostics).
double pbad_evaluate(const Model& m, const SimOptions& o, const State& s, const PbadStep& p, const VecX& q,
                     SimWorkspace& ws);
void pbad_finish(const Model& m, const SimOptions& o, State& s, const PbadStep& p, SimWorkspace& ws);

// Total energy (kinetic + gravity + contact penalty) of a state.
struct Energy {
  double kinetic = 0, potential = 0, total = 0;
};
Energy state_energy(const Model& m, const SimOptions& o, const State& s, SimWorkspace& ws);

}  // namespace pliant::articulated
