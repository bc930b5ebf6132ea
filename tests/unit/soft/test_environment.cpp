// Environment forces: drag is C1 at tangential relative velocity (the original
// formulation is not); contact and friction gradients match finite differences.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "pliant/soft/environment.h"

using namespace pliant::soft;

TEST(Environment, DragIsC1AtTangentialVelocity) {
  Environment env;
  const Eigen::Vector3d a(0, 0.02, 0);  // patch facing +y, 0.02 m^2
  const Eigen::Vector3d Ut(0.7, 0, 0.2);  // tangential
  const Eigen::Vector3d dn(0, 1, 0);
  const double h = 1e-6;
  // Value continuous, and the one-sided derivatives along the normal agree.
  const Eigen::Vector3d f0 = drag_force(env, a, Ut);
  const Eigen::Vector3d fp = drag_force(env, a, Ut + h * dn), fm = drag_force(env, a, Ut - h * dn);
  const Eigen::Vector3d dplus = (fp - f0) / h, dminus = (f0 - fm) / h;
  EXPECT_LT((dplus - dminus).norm(), 1e-4 * std::max(1.0, dplus.norm()));
  // The original form -rho A |U| max(n.U, 0) n jumps in derivative by rho A |U|.
  auto original = [&](const Eigen::Vector3d& U) {
    const Eigen::Vector3d n = a.normalized();
    return Eigen::Vector3d(-env.fluid_density_kg_per_m3 * a.norm() * U.norm() * std::max(0.0, n.dot(U)) * n);
  };
  const Eigen::Vector3d op = (original(Ut + h * dn) - original(Ut)) / h, om = (original(Ut) - original(Ut - h * dn)) / h;
  EXPECT_GT((op - om).norm(), 0.1 * env.fluid_density_kg_per_m3 * a.norm() * Ut.norm());
  // Pushing fluid with the face costs a force against the motion; moving away does not.
  EXPECT_LT(drag_force(env, a, Eigen::Vector3d(0, 1, 0))[1], 0);
  EXPECT_NEAR(drag_force(env, a, Eigen::Vector3d(0, -1, 0))[1], 0.5 * 1000 * 0.02 * env.skin_coefficient, 1e-9);
}

TEST(Environment, ContactAndFrictionGradientsMatchFiniteDifferences) {
  Environment env;
  env.obstacles.push_back({Obstacle::Plane, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 0});
  env.obstacles.push_back({Obstacle::Sphere, Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitY(), 0.1});
  const Eigen::Vector3d x(0.22, -0.01, 0.02);
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  contact_potential(env, 2.0, x, &g, nullptr);
  const double h = 1e-7;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d xp = x, xm = x;
    xp[a] += h, xm[a] -= h;
    const double fd = (contact_potential(env, 2.0, xp, nullptr, nullptr) - contact_potential(env, 2.0, xm, nullptr, nullptr)) / (2 * h);
    EXPECT_NEAR(g[a], fd, 1e-5 * std::max(1.0, std::abs(fd)));
  }
  // Friction in both regimes (slip below and above eps).
  const Eigen::Vector3d n = Eigen::Vector3d(0.1, 1, 0).normalized();
  for (double scale : {0.3e-5, 3e-5}) {
    const Eigen::Vector3d u = scale * Eigen::Vector3d(1, 0.5, -0.7);
    Eigen::Vector3d gf = Eigen::Vector3d::Zero();
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    friction_potential(4.0, n, u, 1e-5, &gf, &H);
    const double hh = 1e-10;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d up = u, um = u;
      up[a] += hh, um[a] -= hh;
      const double fd = (friction_potential(4.0, n, up, 1e-5, nullptr, nullptr) -
                         friction_potential(4.0, n, um, 1e-5, nullptr, nullptr)) / (2 * hh);
      EXPECT_NEAR(gf[a], fd, 1e-4 * std::max(1.0, gf.norm()));
    }
    // The Hessian used by Newton is symmetric positive semi-definite.
    EXPECT_LT((H - H.transpose()).norm(), 1e-9 * H.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(H).eigenvalues().minCoeff(), -1e-9 * H.norm());
  }
}
