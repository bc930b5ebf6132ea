// Rotation-strain map internals: the left Jacobian built from stored coefficients
// (exp_coefficients + so3_left_jacobian) against the direct definition, and the map's
// lazily filled per-sample Jacobians (line-search evaluations skip them) against an
// evaluation that builds them at once.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>

#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"
#include "rotation_strain_test_lattices.h"
#include "rotation_strain_workspace.h"

using namespace pliant::soft;

namespace {

Eigen::Matrix3d rs_cache_exp(const Eigen::Vector3d& v) {
  const double t = v.norm();
  if (t == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(t, v / t).toRotationMatrix();
}

}  // namespace

// exp([v]x) against Eigen's angle-axis rotation; J against central differences of
// d/dh exp([v + h d]x) exp([v]x)^T = [J d]x, from tiny to large angles.
TEST(RotationStrain, ExpAndLeftJacobianFromCoefficientsMatchTheDefinition) {
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, -0.8, 0.5).normalized();
  for (double t : {0.0, 3e-5, 2e-3, 0.3, 1.2, 2.9}) {
    const Eigen::Vector3d v = t * dir + (t > 0 ? 0.1 * t : 0.0) * Eigen::Vector3d(0.2, 0.1, -0.3);
    Eigen::Matrix3d E, J, Jlazy;
    exp_and_jacobian(v, &E, &J);
    EXPECT_LT((E - rs_cache_exp(v)).cwiseAbs().maxCoeff(), 1e-14) << "t " << t;
    double s, c, b;
    exp_coefficients(v, &s, &c, &b);
    so3_left_jacobian(v, c, b, &Jlazy);
    EXPECT_EQ((J - Jlazy).cwiseAbs().maxCoeff(), 0.0) << "t " << t;  // the same arithmetic
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k);
      const double h = 1e-6;
      const Eigen::Matrix3d D = (rs_cache_exp(v + h * d) - rs_cache_exp(v - h * d)) / (2 * h) * E.transpose();
      const Eigen::Vector3d Jd = J * d;
      EXPECT_LT((D - cross_matrix(Jd)).cwiseAbs().maxCoeff(), 1e-8) << "t " << t << " direction " << k;
    }
  }
}

// A positions-only evaluation stores no per-sample J; a later Jacobian, vjp or
// curvature at the same z (a cache hit) fills it. Its results must be the bits of an
// evaluation that built J at once (both slots evicted in between).
TEST(RotationStrain, LazyPerSampleJacobiansGiveTheFreshEvaluationsBits) {
  const Lattice lat = pliant::soft::test::beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 4);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  Eigen::VectorXd z(4), x, x2, out1, out2;
  z << 0.9, -0.5, 0.6, 0.4;
  z *= 0.25 / b.U.cwiseAbs().maxCoeff();
  const Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(3 * lat.nodes(), -1, 1);
  Eigen::MatrixXd J1, J2, C1, C2;
  auto evict = [&] {
    rotation_strain_positions(lat, rs, 0.5 * z, x2);
    rotation_strain_positions(lat, rs, -0.7 * z, x2);
  };
  // Lazy: positions first, then each consumer of J.
  rotation_strain_positions(lat, rs, z, x);
  rotation_strain_positions(lat, rs, z, x, &J1);
  evict();
  rotation_strain_positions(lat, rs, z, x);
  rotation_strain_vjp(lat, rs, z, g, out1);
  evict();
  rotation_strain_positions(lat, rs, z, x);
  rotation_strain_curvature(lat, rs, z, g, C1);
  // Fresh: each consumer evaluates the map itself.
  evict();
  rotation_strain_positions(lat, rs, z, x, &J2);
  evict();
  rotation_strain_vjp(lat, rs, z, g, out2);
  evict();
  rotation_strain_curvature(lat, rs, z, g, C2);
  EXPECT_EQ((J1 - J2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((out1 - out2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((C1 - C2).cwiseAbs().maxCoeff(), 0.0);
  // And the Jacobian is the map's: a central difference along z.
  const double h = 1e-5 / b.U.cwiseAbs().maxCoeff();
  Eigen::VectorXd xp, xm;
  rotation_strain_positions(lat, rs, z + h * Eigen::VectorXd::Ones(4), xp);
  rotation_strain_positions(lat, rs, z - h * Eigen::VectorXd::Ones(4), xm);
  const Eigen::VectorXd fd = (xp - xm) / (2 * h), jd = J1.rowwise().sum();
  EXPECT_LT((fd - jd).norm(), 1e-6 * jd.norm());
}
