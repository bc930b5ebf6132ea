// Reduced forward simulation (Pan & Manocha TOG 2018, section 4): node positions
//   x_j(p) = R (Xbar_j + U_j q) + c
// with local deformation q in the modal basis, translation c and rotation R (the
// floating frame; Xbar is the rest shape about its centre of mass). One step of
// implicit Euler is the minimization (optimization-based implicit Euler)
//   E(p) = sum_j m_j / (2 dt^2) |x_j(p) - xt_j|^2 + E_el(q) - u^T q
//          + beta / (2 dt) (q - q_t)^T Omega (q - q_t) + contact + friction,
//   xt_j = 2 x_j(t) - x_j(t-1) + dt^2 (g + f_drag_j / m_j),
// solved by Gauss-Newton (rotation by increments, R <- exp([dw]) R) with a
// backtracking line search. E_el is the stable neo-Hookean energy of the embedded
// lattice at X + U q (rotation invariant, so it does not depend on R, c), summed
// over the cubature cells with their weights; its reduced Hessian U^T K(q) U is
// accumulated per cell (fem.h elastic_reduced), so Newton converges quadratically
// and rollouts are smooth enough for finite-difference Jacobians. Drag is explicit (from
// the velocity at the start of the step). `full_step` solves the same problem with
// every node free (sparse Newton with CHOLMOD) for validation and benchmarks.
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "pliant/soft/body.h"
#include "pliant/soft/environment.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"

namespace pliant::soft {

struct Character {
  SurfaceMesh surface;
  Lattice lattice;
  Material material;
  Lame lame;
  ModalBasis basis;
  CellWeights cubature;          // empty: every cell
  Eigen::VectorXd rest;          // 3N rest positions X
  Eigen::VectorXd rest_local;    // 3N, Xbar = X - centre of mass
  Eigen::Vector3d rest_com = Eigen::Vector3d::Zero();
  Eigen::VectorXd mode_scale;    // r: largest node displacement of each unit mode
  double mass_kg = 0;
  // Set by enable_rotation_strain: the local shape is the rotation-strain map of q
  // (rotation_strain.h) instead of Xbar + U q; shared by copies (read-only).
  std::shared_ptr<const RotationStrain> rotation_strain;
};

// Training of the nonlinear POD basis: `runs` full-space simulations (no gravity, no
// contact), each under its own random smooth body force (a sum of three cosine waves
// over the rest shape, random directions and wave vectors, suddenly applied) whose
// amplitude would bend the first linear mode by `strain` x the body's diagonal.
struct PodTraining {
  int runs = 20;
  int frames = 40;       // steps per run; every step is a snapshot
  double dt_s = 0.01;
  double strain = 0.2;
  unsigned seed = 7;
  int linear_modes = 8;  // the lowest linear modes kept (at most r - 1); POD fills the rest
};

// Builds rest data, modes (r) of a lattice, plus the modal derivatives of the first
// `derivative_modes` modes (k (k + 1) / 2 more basis vectors). With pod, the basis is
// instead the r-vector POD of the training snapshots (pod_snapshots).
Character make_character(SurfaceMesh surface, Lattice lattice, const Material& mat, int modes,
                         int derivative_modes = 0, const PodTraining* pod = nullptr);

// Switches the character to rotation-strain coordinates over its current basis
// (character.basis "rotation_strain"): factors the lattice Laplacian once (CHOLMOD).
// With reduced, also builds the reduced reconstruction (rotation_strain.h: POD of the
// remainder + cell cubature, trained on `reduction_poses` random poses up to
// rotation_strain_training_amplitude x the lattice size) that the step, positions and
// frames then use. Off by default: 2.2x faster spider playback, but not accurate
// enough on the large T bend (engine/soft/README.md).
void enable_rotation_strain(Character& ch, bool reduced = false, const RsReductionSettings& settings = {},
                            int reduction_poses = 24);

// Local shape (3N, centre of mass at 0, before R and c) for modal coordinates q:
// Xbar + U q, or the rotation-strain reconstruction; jacobian (optional) dlocal/dq.
// Allocates nothing when local/jacobian already have their sizes.
void local_shape(const Character& ch, const Eigen::VectorXd& q, Eigen::VectorXd& local,
                 Eigen::MatrixXd* jacobian = nullptr);

struct SimParams {
  double dt_s = 1.0 / 30;
  int max_newton = 30;
  double newton_tol = 1e-9;     // on the step, relative to the cell size
  double modal_damping_s = 0.01;
  // Opt-in (0: off, the default): also stop a step's Newton when the decrement |g.d| is
  // below this x max(1, |E|), where the energy's Armijo test only sees round-off
  // (engine/soft/README.md, Missing: 1e-13 makes playback 1.1-1.7x faster but moves
  // every trajectory and the optimizer's paths; not the default yet).
  double newton_decrement_stop = 0;
};

struct SoftState {
  int frame = 0;
  double time_s = 0;
  Eigen::VectorXd q, q_prev;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(), R_prev = Eigen::Matrix3d::Identity();
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), c_prev = Eigen::Vector3d::Zero();
};

struct StepStats {
  int newton_iterations = 0;
  double final_step = 0;
  bool converged = false;
};

// exp([w]x): the rotation by |w| about w (the floating frame's update).
Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& w);

// At rest, centre of mass at rest_com + offset, moving with velocity v0.
SoftState initial_state(const Character& ch, const Eigen::Vector3d& offset, const Eigen::Vector3d& v0, double dt);

// Node positions (3N) of a state (allocates nothing when x has its size).
void node_positions(const Character& ch, const SoftState& s, Eigen::VectorXd& x);
Eigen::Vector3d centre_of_mass(const Character& ch, const SoftState& s);

// One implicit Euler step under modal control forces u (r values, generalized
// forces on q; net force and torque on the body are zero: internal actuation).
// Throws std::runtime_error naming the frame when the state turns non-finite.
// Buffers live in a thread-local workspace: after the first step of a character
// (per thread) a step allocates nothing (linear and POD bases; the rotation-strain
// solve uses CHOLMOD's preallocated dense buffers). With rotation-strain
// coordinates the Hessian is Gauss-Newton (J^T M J / dt^2 + J^T K J); from a step's
// second iteration on it adds the map's curvature term (rotation_strain_curvature,
// evaluated once per step), Gauss-Newton again where that makes it indefinite.
// nodal_force (3N, optional): external forces on the lattice nodes (N).
void reduced_step(const Character& ch, const Environment& env, const SimParams& sp, const Eigen::VectorXd& u,
                  SoftState& s, StepStats* stats = nullptr, const Eigen::VectorXd* nodal_force = nullptr);

// Full-space step: positions x (3N), previous x_prev; nodal force f (3N, may be
// empty). Same energy with every node free, except the modal damping term (it is
// defined on modal coordinates); validation runs set modal_damping_s = 0.
void full_step(const Character& ch, const Environment& env, const SimParams& sp, const Eigen::VectorXd& f,
               Eigen::VectorXd& x, Eigen::VectorXd& x_prev, StepStats* stats = nullptr);

// Local displacements (best rigid fit to the rest shape removed, 3N each) of the full
// simulations described by PodTraining.
std::vector<Eigen::VectorXd> pod_snapshots(const Character& ch, const PodTraining& t);

}  // namespace pliant::soft
