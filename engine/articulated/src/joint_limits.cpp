// Joint-range penalties (limit_terms, shared by PBAD's energy and the explicit
// forces): hinge/slide ranges and springs, ball cones, and ball joints' swing cone and
// twist range.
//
// Ball joints' swing cone and twist range (a Pliant extension, scene "joint_limits").
// Swing-twist split about the joint's axis a (body frame): swing angle
// phi = acos(a . R^T a) (how far the axis tilts), twist angle psi = 2 atan2(v . a, w)
// of the unit quaternion (w, v) taken with w >= 0, in (-pi, pi]. Penalties
// 1/2 k (phi - swing_max)^2 beyond the cone and 1/2 k (psi - bound)^2 outside
// [twist_min, twist_max]. Derivatives are taken in the joint's own velocity
// coordinates, q' = q exp(dv) at dv = 0 (the same local rotation vector as the
// velocity and the LM step), to second order: R'^T a = b - dv x b + dv x (dv x b)/2
// with b = R^T a, and exp(dv) = (1 - |dv|^2/8, dv/2) + O(|dv|^3).
#include <algorithm>
#include <cmath>

#include "pliant/articulated/sim.h"
#include "sim_internal.h"

namespace pliant::articulated {

double ball_swing_twist_penalty(const Joint& j, double k, Eigen::Vector4d qb, Vec3* grad, Mat3* hess) {
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  qb.normalize();
  if (qb[0] < 0) qb = -qb;
  const Vec3 a = j.axis, v = qb.tail<3>();
  const double w = qb[0];
  double e = 0;
  if (j.swing_max >= 0) {
    const Mat3 r = Quat(w, v.x(), v.y(), v.z()).toRotationMatrix();
    const Vec3 b = r.transpose() * a;
    const double c = std::clamp(a.dot(b), -1.0, 1.0);
    const double s = std::sqrt(std::max(0.0, 1 - c * c));
    const double d = std::acos(c) - j.swing_max;
    // (s = 0 with d > 0 is the axis turned over exactly: no direction to push in.)
    if (d > 0 && s > 1e-12) {
      e += 0.5 * k * d * d;
      const Vec3 gc = a.cross(b);  // c(dv) = c + gc.dv + dv^T hc dv / 2
      const Mat3 hc = 0.5 * (a * b.transpose() + b * a.transpose()) - c * Mat3::Identity();
      const Vec3 gphi = -gc / s;
      if (grad) *grad += k * d * gphi;
      if (hess) *hess += k * (gphi * gphi.transpose() + d * (-hc / s - c / (s * s * s) * gc * gc.transpose()));
    }
  }
  if (j.twist_limited) {
    const double x = v.dot(a), y = w, r2 = x * x + y * y;
    const double psi = 2 * std::atan2(x, y);
    const double d = psi > j.twist_max ? psi - j.twist_max : psi < j.twist_min ? psi - j.twist_min : 0;
    if (d != 0 && r2 > 1e-300) {
      e += 0.5 * k * d * d;
      const Vec3 gx = 0.5 * (w * a + a.cross(v)), gy = -0.5 * v;
      // psi = 2 atan2(x, y); the Hessians of x and y (-x/4 I, -y/4 I) cancel in it.
      const Vec3 gpsi = 2 * (y * gx - x * gy) / r2;
      const Mat3 hpsi = 2 / (r2 * r2) *
                        (-2 * x * y * gx * gx.transpose() + 2 * x * y * gy * gy.transpose() +
                         (x * x - y * y) * (gx * gy.transpose() + gy * gx.transpose()));
      if (grad) *grad += k * d * gpsi;
      if (hess) *hess += k * (gpsi * gpsi.transpose() + d * hpsi);
    }
  }
  return e;
}

Vec3 hessian_diagonal_bound(const Mat3& h) {
  Vec3 d;
  for (int i = 0; i < 3; ++i) {
    double off = 0;
    for (int c = 0; c < 3; ++c)
      if (c != i) off += std::abs(h(i, c));
    d[i] = std::max(0.0, h(i, i) + off);
  }
  return d;
}

// All joint-range penalties of a configuration (sim_internal.h): hinge/slide ranges,
// ball cones and swing/twist limits, for PBAD's energy and the explicit forces.
double limit_terms(const Model& m, const SimOptions& o, const VecX& q, VecX* force, VecX* hdiag) {
  const double k = o.contact.limit_stiffness;
  if (force) force->setZero(m.nv);
  if (hdiag) hdiag->setZero(m.nv);
  double e = 0;
  for (const Joint& j : m.joints) {
    if (j.type == JointType::Ball && (j.swing_max >= 0 || j.twist_limited)) {
      Vec3 g;
      Mat3 h;
      const Eigen::Vector4d qb(q[j.qadr], q[j.qadr + 1], q[j.qadr + 2], q[j.qadr + 3]);
      e += ball_swing_twist_penalty(j, k, qb, force ? &g : nullptr, hdiag ? &h : nullptr);
      if (force) force->segment<3>(j.vadr) += g;
      if (hdiag) hdiag->segment<3>(j.vadr) += hessian_diagonal_bound(h);
    }
    if (j.stiffness > 0 && (j.type == JointType::Hinge || j.type == JointType::Slide)) {
      // The joint's spring (always on, two-sided): 1/2 k_s (q - springref)^2.
      const double d = q[j.qadr] - j.springref;
      e += 0.5 * j.stiffness * d * d;
      if (force) (*force)[j.vadr] += j.stiffness * d;
      if (hdiag) (*hdiag)[j.vadr] += j.stiffness;
    }
    if (!j.limited) continue;
    if (j.type == JointType::Ball) {
      // Cone: rotation angle theta = |log q| <= range_max. With the local velocity
      // (q' = q exp(dv)), d theta / d dv = the rotation's unit axis n; the Hessian
      // k n n^T is replaced by k I (diagonal for the tree solve; exact along n, stiffer
      // across, so LM steps stay conservative).
      Eigen::Vector4d qb(q[j.qadr], q[j.qadr + 1], q[j.qadr + 2], q[j.qadr + 3]);
      qb.normalize();
      if (qb[0] < 0) qb = -qb;
      const Vec3 v = qb.tail<3>();
      const double sv = v.norm();
      const double theta = 2 * std::atan2(sv, qb[0]);
      const double d = theta - j.range_max;
      if (d <= 0 || sv < 1e-300) continue;
      e += 0.5 * k * d * d;
      if (force) force->segment<3>(j.vadr) += k * d * v / sv;
      if (hdiag) hdiag->segment<3>(j.vadr).array() += k;
      continue;
    }
    const double x = q[j.qadr];
    const double d = x > j.range_max ? x - j.range_max : x < j.range_min ? x - j.range_min : 0;
    if (d == 0) continue;
    e += 0.5 * k * d * d;
    if (force) (*force)[j.vadr] += k * d;
    if (hdiag) (*hdiag)[j.vadr] += k;
  }
  return e;
}

bool any_limits(const Model& m) {
  for (const Joint& j : m.joints)
    if (j.limited || j.swing_max >= 0 || j.twist_limited || j.stiffness > 0) return true;
  return false;
}

}  // namespace pliant::articulated
