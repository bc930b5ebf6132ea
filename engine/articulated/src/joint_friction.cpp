// Dry joint friction (Joint::frictionloss, MuJoCo's frictionloss) for the explicit
// integrators and PBAD's start-up frames: the friction impulse of one step, a small
// box-constrained QP on the friction dofs. PBAD's own term (F |dq| per step) is in
// pbad_energy.cpp.
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim_internal.h"

namespace pliant::articulated {

bool any_frictionloss(const Model& m) {
  for (const Joint& j : m.joints)
    if (j.frictionloss > 0) return true;
  return false;
}

// Dry joint friction over the next step as a constant generalized force: the impulses
// lambda (|lambda_i| <= F_i dt) that bring the predicted velocity v_pred = v + dt a
// (a without friction, k at q) to rest on the friction dofs if
// they can, and oppose it with the full bound if not: min 1/2 l^T W l + v_pred^T l over
// the box, W = the friction dofs' block of M^-1, by projected Gauss-Seidel (W is SPD,
// so it converges). Returns lambda / dt on every dof (0 off the friction dofs) and, in
// accel, the acceleration M^-1 lambda / dt it causes. Dense M: O(nv^3) per call, for
// the comparison integrators (PBAD's term is O(nv)).
VecX joint_friction_force(const Model& m, const SimOptions& o, const Kinematics& k, const VecX& v_pred, VecX* accel) {
  std::vector<int> dof;
  std::vector<double> bound;
  for (const Joint& j : m.joints) {
    if (j.frictionloss <= 0) continue;
    for (int i = 0; i < joint_nv(j.type); ++i) {
      dof.push_back(j.vadr + i);
      bound.push_back(j.frictionloss * o.dt);
    }
  }
  const int nf = static_cast<int>(dof.size());
  const Eigen::LLT<Eigen::MatrixXd> llt(mass_matrix(m, k));
  Eigen::MatrixXd sel = Eigen::MatrixXd::Zero(m.nv, nf);
  for (int f = 0; f < nf; ++f) sel(dof[f], f) = 1;
  const Eigen::MatrixXd minv_cols = llt.solve(sel);  // M^-1 columns of the friction dofs
  Eigen::MatrixXd w(nf, nf);
  for (int f = 0; f < nf; ++f) w.row(f) = minv_cols.row(dof[f]);
  VecX lambda = VecX::Zero(nf), vel(nf);
  for (int f = 0; f < nf; ++f) vel[f] = v_pred[dof[f]];
  for (int sweep = 0; sweep < 200; ++sweep) {
    double change = 0;
    for (int f = 0; f < nf; ++f) {
      const double r = vel[f] + w.row(f).dot(lambda);
      const double l = std::clamp(lambda[f] - r / w(f, f), -bound[f], bound[f]);
      change = std::max(change, std::abs(l - lambda[f]) / bound[f]);
      lambda[f] = l;
    }
    if (change < 1e-12) break;
  }
  VecX force = VecX::Zero(m.nv);
  for (int f = 0; f < nf; ++f) force[dof[f]] = lambda[f] / o.dt;
  *accel = minv_cols * lambda / o.dt;
  return force;
}

}  // namespace pliant::articulated
