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

namespace {

// Explicit inverse of a joint's pivot block d (n x n, n <= 6, symmetric) into the
// top-left corner of dinv. Unpivoted LDL^T: its pivots are positive exactly when d is
// positive definite (Sylvester), the case of every forward-dynamics and accepted LM
// solve; otherwise (indefinite Newton model) Eigen's pivoted LDLT still solves.
template <int N>
bool invert_pivot_block(const Eigen::Matrix<double, N, N>& d, Mat6* dinv) {
  Eigen::Matrix<double, N, N> l = Eigen::Matrix<double, N, N>::Identity();
  Eigen::Matrix<double, N, 1> piv;
  bool positive = true;
  for (int j = 0; j < N && positive; ++j) {
    double dj = d(j, j);
    for (int k = 0; k < j; ++k) dj -= l(j, k) * l(j, k) * piv[k];
    piv[j] = dj;
    positive = dj > 0;
    for (int i = j + 1; i < N && positive; ++i) {
      double lij = d(i, j);
      for (int k = 0; k < j; ++k) lij -= l(i, k) * l(j, k) * piv[k];
      l(i, j) = lij / dj;
    }
  }
  if (positive) {
    // d^-1 = L^-T D^-1 L^-1 with the unit lower triangle inverted in place.
    const Eigen::Matrix<double, N, N> linv =
        l.template triangularView<Eigen::UnitLower>().solve(Eigen::Matrix<double, N, N>::Identity());
    dinv->template topLeftCorner<N, N>().noalias() = linv.transpose() * piv.cwiseInverse().asDiagonal() * linv;
    return true;
  }
  dinv->template topLeftCorner<N, N>() = d.ldlt().solve(Eigen::Matrix<double, N, N>::Identity());
  return false;
}

// One body of the leaves-to-root pass with its joint block of fixed size N (the
// subspace S is 6 x N): u = ia^T S, D = sym(S^T u) + armature, ia_p += ia - u D^-1 u^T,
// pa_p += pa + u D^-1 (r - S^T pa). Fixed sizes: no dynamic loops, no allocation.
template <int N>
bool eliminate_body(const Kinematics& k, const Body& body, const VecX& armature, const VecX& rhs,
                    const Mat6& ia, const Vec6& pa, Mat6* u, Mat6* dinv, Vec6* ures, Mat6* ia_p,
                    Vec6* pa_p) {
  Eigen::Matrix<double, 6, N> s;
  for (int i = 0; i < N; ++i) s.col(i) = k.cdof[body.dof_begin + i];
  const Eigen::Matrix<double, 6, N> ub = ia.transpose() * s;
  Eigen::Matrix<double, N, N> d = s.transpose() * ub;
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < i; ++j) d(i, j) = d(j, i);
    d(i, i) += armature[body.dof_begin + i];
  }
  const bool positive = invert_pivot_block<N>(d, dinv);
  const Eigen::Matrix<double, N, 1> r = rhs.segment<N>(body.dof_begin) - s.transpose() * pa;
  const Eigen::Matrix<double, 6, N> w = ub * dinv->template topLeftCorner<N, N>();
  ia_p->noalias() += ia;
  ia_p->noalias() -= w * ub.transpose();
  pa_p->noalias() += pa + w * r;
  u->template leftCols<N>() = ub;
  ures->template head<N>() = r;
  return positive;
}

template <int N>
void back_substitute(const Kinematics& k, const Body& body, const Mat6& u, const Mat6& dinv,
                     const Vec6& ures, const Vec6& ap, Eigen::Ref<VecX> x, Vec6* acc) {
  const Eigen::Matrix<double, N, 1> r = ures.head<N>() - u.leftCols<N>().transpose() * ap;
  const Eigen::Matrix<double, N, 1> xb = dinv.topLeftCorner<N, N>() * r;
  x.segment<N>(body.dof_begin) = xb;
  *acc = ap;
  for (int i = 0; i < N; ++i) *acc += k.cdof[body.dof_begin + i] * xb[i];
}

// One body of the root-to-leaves pass: its joint solution from the stored elimination
// and its accumulated acceleration (the parent's must be done).
void back_substitute_body(const Model& m, const Kinematics& k, int b, Eigen::Ref<VecX> x, TreeWorkspace* ws) {
  const Body& body = m.bodies[b];
  const Vec6& ap = ws->acc[body.parent];
  switch (body.dof_count) {
    case 0: ws->acc[b] = ap; break;
    case 1: back_substitute<1>(k, body, ws->u[b], ws->dinv[b], ws->ures[b], ap, x, &ws->acc[b]); break;
    case 2: back_substitute<2>(k, body, ws->u[b], ws->dinv[b], ws->ures[b], ap, x, &ws->acc[b]); break;
    case 3: back_substitute<3>(k, body, ws->u[b], ws->dinv[b], ws->ures[b], ap, x, &ws->acc[b]); break;
    case 4: back_substitute<4>(k, body, ws->u[b], ws->dinv[b], ws->ures[b], ap, x, &ws->acc[b]); break;
    case 5: back_substitute<5>(k, body, ws->u[b], ws->dinv[b], ws->ures[b], ap, x, &ws->acc[b]); break;
    default: back_substitute<6>(k, body, ws->u[b], ws->dinv[b], ws->ures[b], ap, x, &ws->acc[b]); break;
  }
}

// Root to leaves, shared by tree_solve and tree_resolve: joint solutions from the
// stored elimination (u, D^-1, reduced right-hand sides) and accumulated accelerations.
void back_substitute_tree(const Model& m, const Kinematics& k, VecX* x, TreeWorkspace* ws) {
  const int nb = static_cast<int>(m.bodies.size());
  x->resize(m.nv);
  ws->acc[0].setZero();
  for (int b = 1; b < nb; ++b) back_substitute_body(m, k, b, *x, ws);
}

}  // namespace

namespace {

// tree_resolve's leaves-to-root pass for one body: only the right-hand side moves,
// pa_p += pa + u D^-1 (r - S^T pa) with the stored u and D^-1.
template <int N>
void resolve_body(const Kinematics& k, const Body& body, const Eigen::Ref<const VecX>& rhs, const Mat6& u, const Mat6& dinv,
                  const Vec6& pa, Vec6* ures, Vec6* pa_p) {
  Eigen::Matrix<double, N, 1> r = rhs.segment<N>(body.dof_begin);
  for (int i = 0; i < N; ++i) r[i] -= k.cdof[body.dof_begin + i].dot(pa);
  pa_p->noalias() += pa + u.leftCols<N>() * (dinv.topLeftCorner<N, N>() * r);
  ures->template head<N>() = r;
}

void resolve_up(const Model& m, const Kinematics& k, int b, const Eigen::Ref<const VecX>& rhs, TreeWorkspace* ws) {
  const Body& body = m.bodies[b];
  Vec6* pa_p = &ws->pa[body.parent];
  switch (body.dof_count) {
    case 0: *pa_p += ws->pa[b]; break;
    case 1: resolve_body<1>(k, body, rhs, ws->u[b], ws->dinv[b], ws->pa[b], &ws->ures[b], pa_p); break;
    case 2: resolve_body<2>(k, body, rhs, ws->u[b], ws->dinv[b], ws->pa[b], &ws->ures[b], pa_p); break;
    case 3: resolve_body<3>(k, body, rhs, ws->u[b], ws->dinv[b], ws->pa[b], &ws->ures[b], pa_p); break;
    case 4: resolve_body<4>(k, body, rhs, ws->u[b], ws->dinv[b], ws->pa[b], &ws->ures[b], pa_p); break;
    case 5: resolve_body<5>(k, body, rhs, ws->u[b], ws->dinv[b], ws->pa[b], &ws->ures[b], pa_p); break;
    default: resolve_body<6>(k, body, rhs, ws->u[b], ws->dinv[b], ws->pa[b], &ws->ures[b], pa_p); break;
  }
}

}  // namespace

void tree_resolve(const Model& m, const Kinematics& k, const VecX& rhs, VecX* x, TreeWorkspace* ws) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int b = 0; b < nb; ++b) ws->pa[b].setZero();
  for (int b = nb - 1; b >= 1; --b) resolve_up(m, k, b, rhs, ws);
  back_substitute_tree(m, k, x, ws);
}

void tree_resolve_in(const Model& m, const Kinematics& k, const Forest& f, const int* trees, int count,
                     const Eigen::Ref<const VecX>& rhs, Eigen::Ref<VecX> x, TreeWorkspace* ws) {
  // A tree's bodies only exchange pa and acc with each other (and the world's, whose
  // pa is never read and whose acc is zero), so each tree runs on its own.
  ws->acc[0].setZero();
  for (int t = 0; t < count; ++t) {
    const std::vector<int>& bodies = f.bodies[trees[t]];
    for (int b : bodies) ws->pa[b].setZero();
    for (auto b = bodies.rbegin(); b != bodies.rend(); ++b) resolve_up(m, k, *b, rhs, ws);
    for (int b : bodies) back_substitute_body(m, k, b, x, ws);
  }
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
  // Leaves to root: articulated inertia seen through each body's joints. For a
  // non-symmetric composite block (exact PBAD Hessian, see tree_solve's header) entry
  // (j, a) of the matrix is S_j^T ia_j S_a for a an ancestor dof, so the coupling
  // column towards the ancestors is u = ia^T S; the joint's own block is the symmetric
  // matrix whose upper triangle is S^T ia^T S. The elimination is a block LDL^T:
  // positive pivots <=> positive definite.
  for (int b = nb - 1; b >= 1; --b) {
    const Body& body = m.bodies[b];
    const int p = body.parent;
    bool pos = true;
#define PLIANT_ELIMINATE(N)                                                                      \
  pos = eliminate_body<N>(k, body, armature, rhs, ws->ia[b], ws->pa[b], &ws->u[b], &ws->dinv[b], \
                          &ws->ures[b], &ws->ia[p], &ws->pa[p])
    switch (body.dof_count) {
      case 0:
        ws->ia[p] += ws->ia[b];
        ws->pa[p] += ws->pa[b];
        break;
      case 1: PLIANT_ELIMINATE(1); break;
      case 2: PLIANT_ELIMINATE(2); break;
      case 3: PLIANT_ELIMINATE(3); break;
      case 4: PLIANT_ELIMINATE(4); break;
      case 5: PLIANT_ELIMINATE(5); break;
      default: PLIANT_ELIMINATE(6); break;  // model_finalize: at most 6 dofs per body
    }
#undef PLIANT_ELIMINATE
    positive = positive && pos;
  }
  // Root to leaves: joint solutions and accumulated body "accelerations".
  back_substitute_tree(m, k, x, ws);
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
