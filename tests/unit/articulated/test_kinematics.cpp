#include <gtest/gtest.h>

#include <random>

#include "pliant/articulated/dynamics.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

VecX random_state(const Model& m, unsigned seed, VecX* v) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX q = m.qpos0;
  VecX dv(m.nv);
  for (int i = 0; i < m.nv; ++i) dv[i] = u(rng);
  qpos_integrate(m, q, dv, 1.0);
  v->resize(m.nv);
  for (int i = 0; i < m.nv; ++i) (*v)[i] = u(rng);
  return q;
}

TEST(Kinematics, IntegrateAndDifferenceAreInverse) {
  const Model m = test::mixed_model();
  VecX v;
  const VecX q0 = random_state(m, 1, &v);
  VecX q1 = q0;
  qpos_integrate(m, q1, v, 0.3);
  const VecX back = qpos_difference(m, q1, q0);
  EXPECT_LT((back - 0.3 * v).norm(), 1e-10);
}

TEST(Kinematics, PointJacobianMatchesFiniteDifferences) {
  const Model m = test::mixed_model();
  VecX v;
  const VecX q = random_state(m, 2, &v);
  Kinematics k;
  kinematics(m, q, &k);
  for (int b = 1; b < static_cast<int>(m.bodies.size()); ++b) {
    const Vec3 local(0.03, -0.02, 0.05);
    const Vec3 x = k.xpos[b] + k.xmat[b] * local;
    const Eigen::MatrixXd jac = point_jacobian(m, k, b, x);
    const double h = 1e-6;
    for (int d = 0; d < m.nv; ++d) {
      VecX e = VecX::Zero(m.nv);
      e[d] = 1;
      VecX qp = q, qm = q;
      qpos_integrate(m, qp, e, h);
      qpos_integrate(m, qm, e, -h);
      Kinematics kp, km;
      kinematics(m, qp, &kp);
      kinematics(m, qm, &km);
      const Vec3 fd = ((kp.xpos[b] + kp.xmat[b] * local) - (km.xpos[b] + km.xmat[b] * local)) / (2 * h);
      EXPECT_LT((fd - jac.col(d)).norm(), 1e-6) << "body " << b << " dof " << d;
    }
  }
}

TEST(Kinematics, TwistRotatesBodyFrames) {
  // Orientation change along a dof: dR/dt = [omega] R with omega the twist's angular part.
  const Model m = test::mixed_model();
  VecX v;
  const VecX q = random_state(m, 3, &v);
  Kinematics k, kp;
  kinematics(m, q, &k);
  VecX qp = q;
  const double h = 1e-7;
  qpos_integrate(m, qp, v, h);
  kinematics(m, qp, &kp);
  for (int b = 1; b < static_cast<int>(m.bodies.size()); ++b) {
    Vec3 w = Vec3::Zero();
    for (int bb = b; bb > 0; bb = m.bodies[bb].parent)
      for (int d = m.bodies[bb].dof_begin; d < m.bodies[bb].dof_begin + m.bodies[bb].dof_count; ++d)
        w += k.cdof[d].head<3>() * v[d];
    const Mat3 dr = (kp.xmat[b] - k.xmat[b]) / h;
    Mat3 wx;
    wx << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    EXPECT_LT((dr - wx * k.xmat[b]).norm(), 1e-5);
  }
}

TEST(Kinematics, HingeRotatesAboutItsAnchor) {
  const Model m = test::pendulum(0.5);
  VecX q = m.qpos0;
  q[0] = M_PI / 2;
  Kinematics k;
  kinematics(m, q, &k);
  // Rotation by +90 deg about +y takes (0,0,-0.5) to (-0.5,0,0).
  EXPECT_NEAR(k.xcom[1].x(), -0.5, 1e-12);
  EXPECT_NEAR(k.xcom[1].z(), 0.0, 1e-12);
}

}  // namespace
}  // namespace pliant::articulated
