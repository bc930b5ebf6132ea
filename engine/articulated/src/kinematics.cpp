// Forward kinematics, configuration arithmetic and Jacobians (world frame).
#include <cmath>

#include "pliant/articulated/dynamics.h"

namespace pliant::articulated {
namespace {

Quat quat_at(const VecX& q, int a) { return Quat(q[a], q[a + 1], q[a + 2], q[a + 3]).normalized(); }

void set_quat(VecX& q, int a, const Quat& r) {
  const Quat n = r.normalized();
  q[a] = n.w();
  q[a + 1] = n.x();
  q[a + 2] = n.y();
  q[a + 3] = n.z();
}

Quat quat_exp(const Vec3& w) {
  const double th = w.norm();
  if (th < 1e-12) return Quat(1, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  return Quat(Eigen::AngleAxisd(th, w / th));
}

Vec3 quat_log(Quat q) {
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2 * v;
  return v * (2 * std::atan2(s, q.w()) / s);
}

Vec6 twist(const Vec3& axis, const Vec3& anchor) {
  Vec6 s;
  s << axis, anchor.cross(axis);
  return s;
}

}  // namespace

void kinematics(const Model& m, const VecX& qpos, Kinematics* k, bool poses_only) {
  const size_t nb = m.bodies.size();
  k->xpos.resize(nb);
  k->xquat.resize(nb);
  k->xmat.resize(nb);
  k->xcom.resize(nb);
  k->cinert.resize(nb);
  k->cdof.resize(m.nv);
  k->xpos[0].setZero();
  k->xquat[0] = Quat::Identity();
  k->xmat[0].setIdentity();
  k->xcom[0].setZero();
  k->cinert[0].setZero();
  for (size_t b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    const int p = body.parent;
    Vec3 x = k->xpos[p] + k->xmat[p] * body.pos;
    Quat r = k->xquat[p] * body.quat;
    for (int ji : body.joints) {
      const Joint& j = m.joints[ji];
      switch (j.type) {
        case JointType::Free: {
          x = qpos.segment<3>(j.qadr);
          r = quat_at(qpos, j.qadr + 3);
          const Mat3 rm = r.toRotationMatrix();
          for (int a = 0; a < 3; ++a) {
            k->cdof[j.vadr + a] << Vec3::Zero(), Vec3::Unit(a);
            k->cdof[j.vadr + 3 + a] = twist(rm.col(a), x);
          }
          break;
        }
        case JointType::Ball: {
          const Vec3 anchor = x + r * j.pos;
          r = (r * quat_at(qpos, j.qadr)).normalized();
          const Mat3 rm = r.toRotationMatrix();
          x = anchor - rm * j.pos;
          for (int a = 0; a < 3; ++a) k->cdof[j.vadr + a] = twist(rm.col(a), anchor);
          break;
        }
        case JointType::Hinge: {
          // Anchor at the body origin (the common case): the rotation leaves x alone.
          const bool at_origin = j.pos.isZero(0);
          const Vec3 anchor = at_origin ? x : Vec3(x + r * j.pos);
          const double half = 0.5 * (qpos[j.qadr] - j.ref);
          const Vec3 sv = std::sin(half) * j.axis;
          if (!poses_only) k->cdof[j.vadr] = twist(r * j.axis, anchor);
          r = r * Quat(std::cos(half), sv.x(), sv.y(), sv.z());
          if (!at_origin) x = anchor - r * j.pos;
          break;
        }
        case JointType::Slide: {
          const Vec3 axis = r * j.axis;
          x += axis * (qpos[j.qadr] - j.ref);
          k->cdof[j.vadr] << Vec3::Zero(), axis;
          break;
        }
      }
    }
    r.normalize();
    k->xpos[b] = x;
    k->xquat[b] = r;
    k->xmat[b] = r.toRotationMatrix();
    k->xcom[b] = x + k->xmat[b] * body.com;
    if (!poses_only)
      k->cinert[b] = spatial_inertia(body.mass, k->xcom[b],
                                     k->xmat[b] * body.inertia * k->xmat[b].transpose());
  }
}

void qpos_integrate(const Model& m, VecX& qpos, const VecX& dv, double scale) {
  for (const Joint& j : m.joints) {
    switch (j.type) {
      case JointType::Hinge:
      case JointType::Slide: qpos[j.qadr] += scale * dv[j.vadr]; break;
      case JointType::Ball:
        set_quat(qpos, j.qadr, quat_at(qpos, j.qadr) * quat_exp(scale * dv.segment<3>(j.vadr)));
        break;
      case JointType::Free:
        qpos.segment<3>(j.qadr) += scale * dv.segment<3>(j.vadr);
        set_quat(qpos, j.qadr + 3,
                 quat_at(qpos, j.qadr + 3) * quat_exp(scale * dv.segment<3>(j.vadr + 3)));
        break;
    }
  }
}

VecX qpos_difference(const Model& m, const VecX& q1, const VecX& q0) {
  VecX dv(m.nv);
  for (const Joint& j : m.joints) {
    switch (j.type) {
      case JointType::Hinge:
      case JointType::Slide: dv[j.vadr] = q1[j.qadr] - q0[j.qadr]; break;
      case JointType::Ball:
        dv.segment<3>(j.vadr) = quat_log(quat_at(q0, j.qadr).conjugate() * quat_at(q1, j.qadr));
        break;
      case JointType::Free:
        dv.segment<3>(j.vadr) = q1.segment<3>(j.qadr) - q0.segment<3>(j.qadr);
        dv.segment<3>(j.vadr + 3) =
            quat_log(quat_at(q0, j.qadr + 3).conjugate() * quat_at(q1, j.qadr + 3));
        break;
    }
  }
  return dv;
}

Eigen::MatrixXd point_jacobian(const Model& m, const Kinematics& k, int body, const Vec3& x) {
  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(3, m.nv);
  for (int b = body; b > 0; b = m.bodies[b].parent) {
    const Body& bd = m.bodies[b];
    for (int d = bd.dof_begin; d < bd.dof_begin + bd.dof_count; ++d) {
      const Vec6& s = k.cdof[d];
      jac.col(d) = s.tail<3>() + s.head<3>().cross(x);
    }
  }
  return jac;
}

}  // namespace pliant::articulated
