// Per-step contact targets of the soft steps (see step_targets.h).
#include "step_targets.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace pliant::soft {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

// First point where the segment a -> b enters obstacle o (a outside), with the
// obstacle's outward normal there.
bool segment_entry(const Obstacle& o, const Vector3d& a, const Vector3d& b, Vector3d* p, Vector3d* nrm) {
  const Vector3d d = b - a;
  if (o.type == Obstacle::Plane) {
    const double da = -o.normal.dot(a - o.point), db = -o.normal.dot(b - o.point);
    if (db <= 0 || da > 0) return false;
    *p = a + (-da / (db - da)) * d;
    *nrm = o.normal;
    return true;
  }
  // |a + t d - c|^2 = r^2, smallest root in [0, 1].
  const Vector3d f = a - o.point;
  const double A = d.squaredNorm(), B = 2 * f.dot(d), C = f.squaredNorm() - o.radius_m * o.radius_m;
  if (A <= 0) return false;
  const double disc = B * B - 4 * A * C;
  if (disc < 0) return false;
  const double tt = (-B - std::sqrt(disc)) / (2 * A);
  if (tt < 0 || tt > 1) return false;
  *p = a + tt * d;
  *nrm = (*p - o.point).normalized();
  return true;
}

}  // namespace

// Fills t in place (no allocation once t has the lattice's sizes).
void make_targets(const Character& ch, const Environment& env, double dt, const VectorXd& x, const VectorXd& x_prev,
                  StepTargets& t) {
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes();
  t.x_start = x;
  t.xt = 2 * x - x_prev;
  for (int j = 0; j < n; ++j) t.xt.segment<3>(3 * j) += dt * dt * env.gravity_m_per_s2;
  if (env.water) {
    for (const auto& f : lat.boundary_faces) {
      const Vector3d a = 0.5 * (x.segment<3>(3 * f[2]) - x.segment<3>(3 * f[0]))
                                   .cross(x.segment<3>(3 * f[3]) - x.segment<3>(3 * f[1]));
      Vector3d U = Vector3d::Zero();
      for (int c = 0; c < 4; ++c) U += 0.25 / dt * (x.segment<3>(3 * f[c]) - x_prev.segment<3>(3 * f[c]));
      const Vector3d F = drag_force(env, a, U);
      for (int c = 0; c < 4; ++c) t.xt.segment<3>(3 * f[c]) += dt * dt * 0.25 * F / lat.node_mass_kg[f[c]];
    }
  }
  t.mu_lambda.setZero(n);
  t.normal.assign(n, Vector3d::UnitY());
  for (int j = 0; j < n; ++j)
    t.mu_lambda[j] = env.friction * contact_normal_force(env, lat.node_mass_kg[j], x.segment<3>(3 * j), &t.normal[j]);
  t.ccd_k.setZero(n);
  t.ccd_point.assign(n, Vector3d::Zero());
  t.ccd_normal.assign(n, Vector3d::UnitY());
  const double delta = 0.25 * lat.cell_size_m;
  for (int j = 0; j < n; ++j) {
    const Vector3d a = x.segment<3>(3 * j), b = t.xt.segment<3>(3 * j);
    for (const auto& o : env.obstacles) {
      Vector3d p, nrm;
      const double da = obstacle_depth(o, a, &nrm);
      if (da > 0) {
        p = a + da * nrm;  // already inside: tangent plane at its projection
      } else if (!segment_entry(o, a, b, &p, &nrm)) {
        continue;
      }
      const double D = -nrm.dot(b - p);  // depth of the target below the tangent plane
      if (D <= delta) continue;
      const double k = std::max(env.contact_stiffness_per_s2, (D / delta - 1) / (dt * dt));
      if (k > t.ccd_k[j]) t.ccd_k[j] = k, t.ccd_point[j] = p, t.ccd_normal[j] = nrm;
    }
  }
}

}  // namespace pliant::soft
