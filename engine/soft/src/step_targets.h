// Per-step contact data of the soft steps (simulator.cpp: reduced_step, full_step):
// the inertial targets, lagged friction and the swept-segment contact planes of one
// step, and the per-node contact + friction energy they define. The energy is inline:
// it runs per node in every energy evaluation of the step.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "pliant/soft/environment.h"
#include "pliant/soft/simulator.h"

namespace pliant::soft {

// Per-step data shared by the energy evaluations of one step.
struct StepTargets {
  Eigen::VectorXd xt;          // inertial + gravity + drag target per node
  Eigen::VectorXd x_start;     // positions at the start of the step (friction slip origin)
  Eigen::VectorXd mu_lambda;   // lagged friction normal force times mu per node
  std::vector<Eigen::Vector3d> normal;
  // Approximate continuous collision (thin parts, fast motion): when the segment
  // from a node's start to its inertial target enters an obstacle deeper than
  // delta, the node gets, for this step, a penalty plane tangent at the entry point
  // (or at its projection when it is already inside) with the stiffness that stops
  // it within delta (implicit Euler estimate depth = D / (1 + k dt^2)). Catches thin
  // obstacles the target jumps over and keeps a one-cell-thick sheet from passing
  // through the ground; resting contact (target depth below delta) is unaffected.
  Eigen::VectorXd ccd_k;       // per unit mass (1/s^2); 0: inactive
  std::vector<Eigen::Vector3d> ccd_point, ccd_normal;
};

// Fills t in place (no allocation once t has the lattice's sizes).
void make_targets(const Character& ch, const Environment& env, double dt, const Eigen::VectorXd& x,
                  const Eigen::VectorXd& x_prev, StepTargets& t);

// Contact + friction of node j at position xj: energy, and gradient/Hessian in x_j.
inline double node_environment(const Environment& env, const StepTargets& t, double m, int j,
                               const Eigen::Vector3d& xj, double eps, Eigen::Vector3d* g, Eigen::Matrix3d* H) {
  double e = contact_potential(env, m, xj, g, H);
  if (t.ccd_k[j] > 0) {
    const Eigen::Vector3d& nrm = t.ccd_normal[j];
    const double d = -nrm.dot(xj - t.ccd_point[j]);
    if (d > 0) {
      const double k = t.ccd_k[j] * m;
      e += 0.5 * k * d * d;
      if (g) *g -= k * d * nrm;
      if (H) *H += k * nrm * nrm.transpose();
    }
  }
  if (t.mu_lambda[j] > 0)
    e += friction_potential(t.mu_lambda[j], t.normal[j], xj - t.x_start.segment<3>(3 * j), eps, g, H);
  return e;
}

// Whether node j at xj has any environment term this step (contact, friction, CCD).
inline bool touches(const Environment& env, const StepTargets& t, int j, const Eigen::Vector3d& xj) {
  if (t.mu_lambda[j] > 0 || t.ccd_k[j] > 0) return true;
  for (const auto& o : env.obstacles)
    if (obstacle_depth(o, xj, nullptr) > 0) return true;
  return false;
}

}  // namespace pliant::soft
