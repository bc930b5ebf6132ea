// Kinematics and dynamics of a Model in world coordinates. Spatial vectors are
// (angular; linear) about the world origin (Featherstone's Plucker coordinates with
// a fixed frame): a body twist is (omega, v_O), v_O the velocity of the body point
// at the world origin; a wrench is (moment about the origin, force). With every
// quantity in one frame the recursions need no transforms: twists add along the
// tree and wrenches add towards the root.
#pragma once
#include <vector>

#include "pliant/articulated/model.h"

namespace pliant::articulated {

struct Kinematics {
  std::vector<Vec3> xpos;    // body origin, world
  std::vector<Quat> xquat;   // body orientation
  std::vector<Mat3> xmat;
  std::vector<Vec3> xcom;    // centre of mass, world
  std::vector<Vec6> cdof;    // motion subspace of each dof (twist per unit velocity)
  std::vector<Mat6> cinert;  // spatial inertia of each body about the world origin
};

// Forward kinematics (MuJoCo's order: body offset, then joints in order). With
// poses_only, cdof and cinert are left stale (PBAD's energy-only evaluations).
void kinematics(const Model& m, const VecX& qpos, Kinematics* k, bool poses_only = false);

// qpos <- qpos (+) scale * dv: hinge/slide add, quaternions rotate by exp(dv) in the
// local frame (free-joint position adds in the world frame). Quaternions renormalised.
void qpos_integrate(const Model& m, VecX& qpos, const VecX& dv, double scale);
// dv with q0 (+) dv == q1 (ball/free rotations through the quaternion log).
VecX qpos_difference(const Model& m, const VecX& q1, const VecX& q0);

// Spatial cross products.
Vec6 cross_motion(const Vec6& v, const Vec6& u);
Vec6 cross_force(const Vec6& v, const Vec6& f);
// Spatial inertia about the world origin of mass m, centre c, rotational inertia ic
// (about the centre, world axes).
Mat6 spatial_inertia(double mass, const Vec3& c, const Mat3& ic);
// Wrench (moment about origin, force) of force f applied at world point x.
inline Vec6 point_wrench(const Vec3& x, const Vec3& f) {
  Vec6 w;
  w << x.cross(f), f;
  return w;
}
// 6x6 form of a 3x3 point stiffness K at world point x (delta x = v + omega x X).
Mat6 point_hessian(const Vec3& x, const Mat3& K);

// Transposed geometric block of a body loaded by forces f_k at points x_k (given as
// moment = sum x_k f_k^T and force = sum f_k, f_k the energy's gradient at x_k): the
// term sum_k f_k . d2x_k/dq_i dq_j = S_i^T Q S_j (i the ancestor-or-earlier dof;
// d2x/dq_i dq_j = omega_i x xdot_j), Q = [[moment - tr(moment) I, -[force]x], [0, 0]].
// Returns Q^T, the form tree_solve takes (added to the Gauss-Newton block).
Mat6 geometric_block_transposed(const Mat3& moment, const Vec3& force);

// Scratch for the O(N) solves (one per thread / trajectory).
struct TreeWorkspace {
  std::vector<Mat6> ia;   // articulated inertias
  std::vector<Vec6> pa;   // articulated bias
  std::vector<Vec6> acc;
  // Per body with n joint dofs (fixed-size storage, first n columns / entries used):
  std::vector<Mat6> u;     // ia^T S (6 x n)
  std::vector<Mat6> dinv;  // inverse of the joint's pivot block (n x n)
  std::vector<Vec6> ures;  // joint residual (n)
};

// Solves (sum_b Phi_b^T H_b Phi_b + diag(armature)) x = rhs in O(N) with the
// articulated-body recursion (Featherstone's ABA with zero velocity): H_b is a 6x6
// per body, Phi_b its world-frame Jacobian. With H_b = cinert it computes M^-1 rhs.
// H_b may be non-symmetric: the matrix solved is then the symmetric one whose entry
// (j, i), dof i an ancestor-or-earlier dof of j, is S_j^T (sum_{b below j} H_b) S_i,
// which is the exact Hessian of a pose energy when H_b = Gauss-Newton block +
// transposed geometric block (pose_geometric_block); PBAD's Newton steps use it.
// The matrix must be non-singular (LM adds its damping through armature). Returns
// whether it is positive definite (all pivots of the elimination positive).
bool tree_solve(const Model& m, const Kinematics& k, const std::vector<Mat6>& h,
                const VecX& armature, const VecX& rhs, VecX* x, TreeWorkspace* ws);

// Solves the same matrix as the last tree_solve with ws (its elimination kept in ws)
// for another right-hand side: only the vectors move, several times cheaper than
// tree_solve (PBAD's body-body contact terms, Woodbury).
void tree_resolve(const Model& m, const Kinematics& k, const VecX& rhs, VecX* x, TreeWorkspace* ws);

// The model's trees: bodies grouped by the child of the world that their chain of
// parents starts from (a free object is a tree of one body). The tree solve's matrix
// has no entry between two trees, so a right-hand side that is zero outside some
// trees has its solution there too (forest.cpp).
struct Forest {
  std::vector<int> body_tree;            // tree of each body (-1 for the world)
  std::vector<std::vector<int>> bodies;  // per tree, ascending
  std::vector<std::vector<int>> dofs;    // per tree, ascending
};
Forest model_forest(const Model& m);

// tree_resolve for a right-hand side that is zero outside trees[0 .. count): the same
// arithmetic on those trees' bodies only, writing x at their dofs and nowhere else
// (elsewhere the solution is zero). Body-body contact terms touch two trees each.
void tree_resolve_in(const Model& m, const Kinematics& k, const Forest& f, const int* trees, int count,
                     const Eigen::Ref<const VecX>& rhs, Eigen::Ref<VecX> x, TreeWorkspace* ws);

// Diagonal of sum_b Phi_b^T H_b Phi_b (composite blocks), O(N).
void tree_diagonal(const Model& m, const Kinematics& k, const std::vector<Mat6>& h, VecX* diag,
                   TreeWorkspace* ws);

// Generalized force of sum_b Phi_b^T w_b for per-body wrenches w (O(N), backward pass).
void wrenches_to_generalized(const Model& m, const Kinematics& k, std::vector<Vec6>& w, VecX* tau);

// Bias force C(q, qdot) qdot + gravity + joint damping: M qacc = tau - bias
// (recursive Newton-Euler with qacc = 0).
VecX bias_force(const Model& m, const Kinematics& k, const VecX& qvel);
// Dense joint-space inertia (tests and small models only).
Eigen::MatrixXd mass_matrix(const Model& m, const Kinematics& k);

// Forward dynamics: qacc = M^-1 (tau - bias), O(N).
void forward_dynamics(const Model& m, const Kinematics& k, const VecX& qvel, const VecX& tau,
                      VecX* qacc, TreeWorkspace* ws);

double kinetic_energy(const Model& m, const Kinematics& k, const VecX& qvel);
double potential_energy(const Model& m, const Kinematics& k);  // gravity, zero at z=0

// World-frame linear Jacobian (3 x nv) of the body point at world position x.
Eigen::MatrixXd point_jacobian(const Model& m, const Kinematics& k, int body, const Vec3& x);

}  // namespace pliant::articulated
