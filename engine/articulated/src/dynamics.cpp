// O(N) recursions in world coordinates: the articulated-body solve shared by
// forward dynamics and PBAD's Levenberg-Marquardt steps (Featherstone, "Rigid Body
// Dynamics Algorithms", ch. 7), recursive Newton-Euler for the bias force (ch. 5).
#include "pliant/articulated/dynamics.h"

namespace pliant::articulated {
namespace {

Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

using DofMat = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;

DofMat body_subspace(const Model& m, const Kinematics& k, int b) {
  const Body& body = m.bodies[b];
  DofMat s(6, body.dof_count);
  for (int i = 0; i < body.dof_count; ++i) s.col(i) = k.cdof[body.dof_begin + i];
  return s;
}

}  // namespace

Vec6 cross_motion(const Vec6& v, const Vec6& u) {
  Vec6 r;
  const Vec3 w = v.head<3>(), vl = v.tail<3>();
  r << w.cross(u.head<3>()), w.cross(u.tail<3>()) + vl.cross(u.head<3>());
  return r;
}

Vec6 cross_force(const Vec6& v, const Vec6& f) {
  Vec6 r;
  const Vec3 w = v.head<3>(), vl = v.tail<3>();
  r << w.cross(f.head<3>()) + vl.cross(f.tail<3>()), w.cross(f.tail<3>());
  return r;
}

Mat6 spatial_inertia(double mass, const Vec3& c, const Mat3& ic) {
  const Mat3 cx = skew(c);
  Mat6 h;
  h.topLeftCorner<3, 3>() = ic + mass * cx.transpose() * cx;
  h.topRightCorner<3, 3>() = mass * cx;
  h.bottomLeftCorner<3, 3>() = -mass * cx;
  h.bottomRightCorner<3, 3>() = mass * Mat3::Identity();
  return h;
}

Mat6 point_hessian(const Vec3& x, const Mat3& kk) {
  Eigen::Matrix<double, 3, 6> jx;
  jx << -skew(x), Mat3::Identity();
  return jx.transpose() * kk * jx;
}

Mat6 geometric_block_transposed(const Mat3& moment, const Vec3& force) {
  Mat6 q = Mat6::Zero();
  q.topLeftCorner<3, 3>() = moment.transpose() - moment.trace() * Mat3::Identity();
  q.bottomLeftCorner<3, 3>() = skew(force);
  return q;
}

bool tree_solve(const Model& m, const Kinematics& k, const std::vector<Mat6>& h,
                const VecX& armature, const VecX& rhs, VecX* x, TreeWorkspace* ws) {
  bool positive = true;
  const int nb = static_cast<int>(m.bodies.size());
  ws->ia.resize(nb);
  ws->pa.resize(nb);
  ws->acc.resize(nb);
  ws->u.resize(nb);
  ws->dinv.resize(nb);
  ws->ures.resize(nb);
  for (int b = 0; b < nb; ++b) {
    ws->ia[b] = h[b];
    ws->pa[b].setZero();
  }
  // Leaves to root: articulated inertia seen through each body's joints.
  for (int b = nb - 1; b >= 1; --b) {
    const Body& body = m.bodies[b];
    const int p = body.parent;
    if (body.dof_count == 0) {
      ws->ia[p] += ws->ia[b];
      ws->pa[p] += ws->pa[b];
      continue;
    }
    const DofMat s = body_subspace(m, k, b);
    // u = ia^T S: for a non-symmetric composite block (exact PBAD Hessian, see
    // tree_solve's header) entry (j, a) of the matrix is S_j^T ia_j S_a for a an
    // ancestor dof, so the coupling column towards the ancestors is ia^T S; the
    // joint's own block is the symmetric matrix whose upper triangle is S^T ia^T S.
    ws->u[b].noalias() = ws->ia[b].transpose() * s;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> d = s.transpose() * ws->u[b];
    for (int i = 0; i < body.dof_count; ++i)
      for (int j = 0; j < i; ++j) d(i, j) = d(j, i);
    for (int i = 0; i < body.dof_count; ++i) d(i, i) += armature[body.dof_begin + i];
    ws->dinv[b].compute(d);
    // The tree elimination is a block LDL^T: positive pivots <=> positive definite.
    positive = positive && (ws->dinv[b].vectorD().array() > 0).all();
    ws->ures[b] = rhs.segment(body.dof_begin, body.dof_count) - s.transpose() * ws->pa[b];
    const Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 6, 6> ut = ws->u[b].transpose();
    const Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 6, 6> dinv_ut = ws->dinv[b].solve(ut);
    ws->ia[p] += ws->ia[b] - ws->u[b] * dinv_ut;
    ws->pa[p] += ws->pa[b] + ws->u[b] * ws->dinv[b].solve(ws->ures[b]);
  }
  // Root to leaves: joint solutions and accumulated body "accelerations".
  x->resize(m.nv);
  ws->acc[0].setZero();
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    const Vec6& ap = ws->acc[body.parent];
    if (body.dof_count == 0) {
      ws->acc[b] = ap;
      continue;
    }
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> r = ws->ures[b] - ws->u[b].transpose() * ap;
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> xb = ws->dinv[b].solve(r);
    x->segment(body.dof_begin, body.dof_count) = xb;
    ws->acc[b] = ap + body_subspace(m, k, b) * xb;
  }
  return positive;
}

void tree_diagonal(const Model& m, const Kinematics& k, const std::vector<Mat6>& h, VecX* diag,
                   TreeWorkspace* ws) {
  const int nb = static_cast<int>(m.bodies.size());
  std::vector<Mat6>& c = ws->ia;  // scratch, overwritten by tree_solve
  c.assign(h.begin(), h.end());
  for (int b = nb - 1; b >= 1; --b) c[m.bodies[b].parent] += c[b];
  diag->resize(m.nv);
  for (int i = 0; i < m.nv; ++i) (*diag)[i] = k.cdof[i].dot(c[m.dof_body[i]] * k.cdof[i]);
}

void wrenches_to_generalized(const Model& m, const Kinematics& k, std::vector<Vec6>& w, VecX* tau) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int b = nb - 1; b >= 1; --b) w[m.bodies[b].parent] += w[b];
  tau->resize(m.nv);
  for (int i = 0; i < m.nv; ++i) (*tau)[i] = k.cdof[i].dot(w[m.dof_body[i]]);
}

VecX bias_force(const Model& m, const Kinematics& k, const VecX& qvel) {
  const int nb = static_cast<int>(m.bodies.size());
  std::vector<Vec6> v(nb), a(nb), f(nb);
  v[0].setZero();
  a[0].setZero();
  f[0].setZero();
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    Vec6 vb = v[body.parent], ab = a[body.parent];
    // d/dt of each dof's subspace: cross product with the twist of the frame it is
    // fixed in (the sum over a ball's own dofs of its self-term vanishes).
    for (int ji : body.joints) {
      const Joint& j = m.joints[ji];
      const int nvj = joint_nv(j.type);
      if (j.type == JointType::Free) {
        for (int i = 0; i < 3; ++i) vb += k.cdof[j.vadr + i] * qvel[j.vadr + i];
        for (int i = 3; i < 6; ++i) ab += cross_motion(vb, k.cdof[j.vadr + i]) * qvel[j.vadr + i];
        for (int i = 3; i < 6; ++i) vb += k.cdof[j.vadr + i] * qvel[j.vadr + i];
      } else {
        for (int i = 0; i < nvj; ++i) ab += cross_motion(vb, k.cdof[j.vadr + i]) * qvel[j.vadr + i];
        for (int i = 0; i < nvj; ++i) vb += k.cdof[j.vadr + i] * qvel[j.vadr + i];
      }
    }
    v[b] = vb;
    a[b] = ab;
    const Mat6& hb = k.cinert[b];
    f[b] = hb * ab + cross_force(vb, hb * vb) -
           point_wrench(k.xcom[b], m.bodies[b].mass * m.gravity);
  }
  VecX tau;
  wrenches_to_generalized(m, k, f, &tau);
  for (const Joint& j : m.joints)
    if (j.damping > 0)
      for (int i = 0; i < joint_nv(j.type); ++i) tau[j.vadr + i] += j.damping * qvel[j.vadr + i];
  return tau;
}

Eigen::MatrixXd mass_matrix(const Model& m, const Kinematics& k) {
  Eigen::MatrixXd mm = Eigen::MatrixXd::Zero(m.nv, m.nv);
  const int nb = static_cast<int>(m.bodies.size());
  std::vector<Mat6> c(k.cinert.begin(), k.cinert.end());
  for (int b = nb - 1; b >= 1; --b) c[m.bodies[b].parent] += c[b];
  for (int i = 0; i < m.nv; ++i)
    for (int j = 0; j <= i; ++j) {
      // Entry (i, j): the deeper dof's composite inertia (j's body is an ancestor of i's).
      const int bi = m.dof_body[i];
      int bj = m.dof_body[j];
      bool ancestor = false;
      for (int b = bi; b > 0; b = m.bodies[b].parent)
        if (b == bj) ancestor = true;
      if (!ancestor) continue;
      mm(i, j) = mm(j, i) = k.cdof[j].dot(c[bi] * k.cdof[i]);
    }
  for (const Joint& j : m.joints)
    for (int i = 0; i < joint_nv(j.type); ++i) mm(j.vadr + i, j.vadr + i) += j.armature;
  return mm;
}

void forward_dynamics(const Model& m, const Kinematics& k, const VecX& qvel, const VecX& tau,
                      VecX* qacc, TreeWorkspace* ws) {
  VecX arm = VecX::Zero(m.nv);
  for (const Joint& j : m.joints)
    for (int i = 0; i < joint_nv(j.type); ++i) arm[j.vadr + i] = j.armature;
  const VecX rhs = tau - bias_force(m, k, qvel);
  tree_solve(m, k, k.cinert, arm, rhs, qacc, ws);
}

double kinetic_energy(const Model& m, const Kinematics& k, const VecX& qvel) {
  const int nb = static_cast<int>(m.bodies.size());
  std::vector<Vec6> v(nb);
  v[0].setZero();
  double t = 0;
  for (int b = 1; b < nb; ++b) {
    const Body& body = m.bodies[b];
    v[b] = v[body.parent];
    for (int d = body.dof_begin; d < body.dof_begin + body.dof_count; ++d) v[b] += k.cdof[d] * qvel[d];
    t += 0.5 * v[b].dot(k.cinert[b] * v[b]);
  }
  for (const Joint& j : m.joints)
    for (int i = 0; i < joint_nv(j.type); ++i) t += 0.5 * j.armature * qvel[j.vadr + i] * qvel[j.vadr + i];
  return t;
}

double potential_energy(const Model& m, const Kinematics& k) {
  double v = 0;
  for (size_t b = 1; b < m.bodies.size(); ++b) v -= m.bodies[b].mass * m.gravity.dot(k.xcom[b]);
  return v;
}

}  // namespace pliant::articulated
