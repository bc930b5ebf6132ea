// Environment forces (ALGORITHMS.md section 3, Pan & Manocha TOG 2018 section 5):
// - penalty contact with the ground plane and static obstacles (planes, spheres):
//   E = k m_j d^2 / 2 per lattice node with penetration depth d (k in 1/s^2, scaled
//   by the node mass so the rest penetration g/k does not depend on resolution);
// - smoothed Coulomb friction as a lagged dissipative potential (the normal force is
//   taken from the start of the step, the tangential slip is smoothed below
//   eps_v * dt with the C1 profile of Li et al. 2020 (IPC)), so static friction holds
//   a body at rest up to a creep speed below eps_v;
// - fluid drag per lattice boundary face (patch) with area A, outward normal n and
//   velocity U relative to the fluid:
//     F = -rho A / 2 (C_d max(n.U, 0)^2 n + C_f |U| U).
//   The original form -rho A |U| max(n.U, 0) n has a kink when U is tangential (its
//   derivative jumps from 0 to rho A |U| n n^T at n.U = 0, Fig. 4.3); the squared
//   ramp is C1 there, and |U| U is C1 everywhere.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace pliant::soft {

struct Obstacle {
  enum Type { Plane, Sphere } type = Plane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // plane point or sphere centre
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // plane: solid below (n . (x - p) < 0)
  double radius_m = 0;
};

struct Environment {
  bool water = false;
  Eigen::Vector3d gravity_m_per_s2{0, -9.81, 0};
  std::vector<Obstacle> obstacles;  // the ground is obstacles[0] when present
  double contact_stiffness_per_s2 = 2e4;
  double friction = 0.5;
  double friction_eps_m_per_s = 1e-3;
  double fluid_density_kg_per_m3 = 1000;
  double drag_coefficient = 1.0;
  double skin_coefficient = 0.02;
};

// Penetration depth (>= 0 inside) and outward normal of the obstacle at x.
double obstacle_depth(const Obstacle& o, const Eigen::Vector3d& x, Eigen::Vector3d* normal);

// Contact potential of one node of mass m: value, gradient g and Hessian H (added).
double contact_potential(const Environment& env, double m, const Eigen::Vector3d& x, Eigen::Vector3d* g,
                         Eigen::Matrix3d* H);
// Normal force magnitude per obstacle at x (for lagged friction): sum over touching
// obstacles; also returns the normal of the deepest contact.
double contact_normal_force(const Environment& env, double m, const Eigen::Vector3d& x, Eigen::Vector3d* normal);

// Friction potential for slip u = x - x_start with lagged normal force lambda and
// contact normal n; eps = eps_v * dt.
double friction_potential(double mu_lambda, const Eigen::Vector3d& n, const Eigen::Vector3d& u, double eps,
                          Eigen::Vector3d* g, Eigen::Matrix3d* H);

// Drag force on one patch with area vector a (|a| = area, direction = outward normal)
// moving at U relative to the fluid.
Eigen::Vector3d drag_force(const Environment& env, const Eigen::Vector3d& area_vector, const Eigen::Vector3d& U);

}  // namespace pliant::soft
