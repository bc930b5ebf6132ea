// Contact, friction and drag (see environment.h).
#include "pliant/soft/environment.h"

#include <Eigen/Geometry>
#include <cmath>

namespace pliant::soft {

double obstacle_depth(const Obstacle& o, const Eigen::Vector3d& x, Eigen::Vector3d* normal) {
  if (o.type == Obstacle::Plane) {
    if (normal) *normal = o.normal;
    return -o.normal.dot(x - o.point);
  }
  const Eigen::Vector3d d = x - o.point;
  const double r = d.norm();
  if (normal) *normal = r > 0 ? Eigen::Vector3d(d / r) : Eigen::Vector3d::UnitY();
  return o.radius_m - r;
}

double contact_potential(const Environment& env, double m, const Eigen::Vector3d& x, Eigen::Vector3d* g,
                         Eigen::Matrix3d* H) {
  double e = 0;
  const double k = env.contact_stiffness_per_s2 * m;
  for (const auto& o : env.obstacles) {
    Eigen::Vector3d n;
    const double d = obstacle_depth(o, x, &n);
    if (d <= 0) continue;
    e += 0.5 * k * d * d;
    if (g) *g -= k * d * n;
    // Gauss-Newton part (exact for planes; drops the sphere's curvature term).
    if (H) *H += k * n * n.transpose();
  }
  return e;
}

double contact_normal_force(const Environment& env, double m, const Eigen::Vector3d& x, Eigen::Vector3d* normal) {
  double total = 0, deepest = 0;
  for (const auto& o : env.obstacles) {
    Eigen::Vector3d n;
    const double d = obstacle_depth(o, x, &n);
    if (d <= 0) continue;
    total += env.contact_stiffness_per_s2 * m * d;
    if (d > deepest) {
      deepest = d;
      if (normal) *normal = n;
    }
  }
  return total;
}

double friction_potential(double mu_lambda, const Eigen::Vector3d& n, const Eigen::Vector3d& u, double eps,
                          Eigen::Vector3d* g, Eigen::Matrix3d* H) {
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
  const Eigen::Vector3d ut = P * u;
  const double s = ut.norm();
  double f0, f1_over_s, f1_prime;
  if (s < eps) {
    f0 = -s * s * s / (3 * eps * eps) + s * s / eps + eps / 3;
    f1_over_s = -s / (eps * eps) + 2 / eps;
    f1_prime = -2 * s / (eps * eps) + 2 / eps;
  } else {
    f0 = s;
    f1_over_s = 1 / s;
    f1_prime = 0;
  }
  if (g) *g += mu_lambda * f1_over_s * ut;
  if (H) {
    Eigen::Matrix3d h = f1_over_s * P;
    if (s > 1e-14) {
      const Eigen::Vector3d t = ut / s;
      h += (f1_prime - f1_over_s) * t * t.transpose();
    }
    *H += mu_lambda * h;
  }
  return mu_lambda * f0;
}

Eigen::Vector3d drag_force(const Environment& env, const Eigen::Vector3d& a, const Eigen::Vector3d& U) {
  const double area = a.norm();
  if (area <= 0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d n = a / area;
  const double un = std::max(0.0, n.dot(U));
  return -0.5 * env.fluid_density_kg_per_m3 * area *
         (env.drag_coefficient * un * un * n + env.skin_coefficient * U.norm() * U);
}

}  // namespace pliant::soft
