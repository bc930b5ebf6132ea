// Rotation-strain reconstruction: linear modes at first order, exact rigid rotation
// for a rotation field (where linear modes grow the body), Jacobian against central
// differences.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <thread>
#include <vector>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"

using namespace pliant::soft;

namespace {
Lattice beam_lattice() {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 3;  // a 3 x 1 x 1 beam
  return build_lattice(repair_mesh(cube), 6, 1000);
}

// Rest positions with the mass-weighted centroid at 0.
Eigen::VectorXd centred_rest(const Lattice& lat) {
  Eigen::VectorXd x(3 * lat.nodes());
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double m = 0;
  for (int j = 0; j < lat.nodes(); ++j) c += lat.node_mass_kg[j] * lat.rest[j], m += lat.node_mass_kg[j];
  c /= m;
  for (int j = 0; j < lat.nodes(); ++j) x.segment<3>(3 * j) = lat.rest[j] - c;
  return x;
}

}  // namespace

TEST(RotationStrain, SmallCoordinatesReproduceLinearModes) {
  const Lattice lat = beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 6);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  const Eigen::VectorXd X = centred_rest(lat);
  Eigen::VectorXd x;
  rotation_strain_positions(lat, rs, Eigen::VectorXd::Zero(6), x);
  EXPECT_LT((x - X).cwiseAbs().maxCoeff(), 1e-10);
  // Unit z moves nodes by about |U| ~ 1 / sqrt(mass); scale to ~1% of the beam length.
  Eigen::VectorXd dir(6);
  dir << 0.8, -0.5, 0.3, 0.6, -0.2, 0.4;
  dir *= 0.03 / b.U.cwiseAbs().maxCoeff();
  double err[2];
  for (int t = 0; t < 2; ++t) {
    const Eigen::VectorXd z = (t + 1) * dir;
    rotation_strain_positions(lat, rs, z, x);
    err[t] = (x - X - b.U * z).norm();
  }
  const double lin = (b.U * dir).norm();
  EXPECT_LT(err[0], 0.05 * lin);  // second order: small against the first-order term
  EXPECT_GT(err[0], 0);
  EXPECT_NEAR(err[1] / err[0], 4.0, 0.4);  // O(|z|^2)
}

TEST(RotationStrain, RotationFieldReconstructsRigidRotation) {
  const Lattice lat = beam_lattice();
  const Eigen::VectorXd X = centred_rest(lat);
  Eigen::MatrixXd U(3 * lat.nodes(), 1);  // infinitesimal rotation about z
  for (int j = 0; j < lat.nodes(); ++j) U.block<3, 1>(3 * j, 0) = Eigen::Vector3d::UnitZ().cross(X.segment<3>(3 * j));
  const RotationStrain rs = rotation_strain_build(lat, U);
  const double angle = 1.0;
  Eigen::VectorXd x;
  rotation_strain_positions(lat, rs, Eigen::VectorXd::Constant(1, angle), x);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double err = 0;
  for (int j = 0; j < lat.nodes(); ++j) err = std::max(err, (x.segment<3>(3 * j) - R * X.segment<3>(3 * j)).norm());
  EXPECT_LT(err, 1e-9);
  const double v0 = lattice_volume(lat, X);
  EXPECT_NEAR(lattice_volume(lat, x) / v0, 1.0, 1e-9);
  // The linear map X + U z stretches by sqrt(1 + z^2) across the axis: volume x 2.
  const Eigen::VectorXd x_lin = X + U * angle;
  EXPECT_NEAR(lattice_volume(lat, x_lin) / v0, 1 + angle * angle, 1e-9);
}

TEST(RotationStrain, JacobianMatchesFiniteDifferences) {
  const Lattice lat = beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 5);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  Eigen::VectorXd z(5);
  z << 1.0, -0.7, 0.5, 0.8, -0.4;
  z *= 0.3 / b.U.cwiseAbs().maxCoeff();  // large: nodes move ~30% of the beam's width
  Eigen::VectorXd x, xp, xm;
  Eigen::MatrixXd J;
  rotation_strain_positions(lat, rs, z, x, &J);
  ASSERT_EQ(J.rows(), 3 * lat.nodes());
  ASSERT_EQ(J.cols(), 5);
  const double h = 1e-5 / b.U.cwiseAbs().maxCoeff();
  for (int k = 0; k < 5; ++k) {
    Eigen::VectorXd zp = z, zm = z;
    zp[k] += h, zm[k] -= h;
    rotation_strain_positions(lat, rs, zp, xp);
    rotation_strain_positions(lat, rs, zm, xm);
    const Eigen::VectorXd fd = (xp - xm) / (2 * h);
    EXPECT_LT((fd - J.col(k)).norm(), 1e-6 * J.col(k).norm()) << "mode " << k;
    // Nonlinear: the Jacobian differs from the linear mode at this amplitude.
    EXPECT_GT((J.col(k) - b.U.col(k)).norm(), 1e-3 * b.U.col(k).norm()) << "mode " << k;
  }
}

TEST(RotationStrain, CurvatureMatchesDifferencesOfTheJacobian) {
  const Lattice lat = beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 4);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  Eigen::VectorXd z(4);
  z << 0.9, -0.6, 0.4, 0.7;
  z *= 0.3 / b.U.cwiseAbs().maxCoeff();
  Eigen::VectorXd g(3 * lat.nodes()), x;
  for (int i = 0; i < g.size(); ++i) g[i] = std::sin(1.7 * i + 0.3);
  Eigen::MatrixXd C, Jp, Jm;
  rotation_strain_curvature(lat, rs, z, g, C);
  const double h = 1e-5 / b.U.cwiseAbs().maxCoeff();
  Eigen::MatrixXd fd(4, 4);
  for (int a = 0; a < 4; ++a) {
    Eigen::VectorXd zp = z, zm = z;
    zp[a] += h, zm[a] -= h;
    rotation_strain_positions(lat, rs, zp, x, &Jp);
    rotation_strain_positions(lat, rs, zm, x, &Jm);
    fd.col(a) = (Jp - Jm).transpose() * g / (2 * h);
  }
  EXPECT_LT((C - fd).norm(), 1e-5 * fd.norm());
  EXPECT_LT((C - C.transpose()).norm(), 1e-12 * C.norm());
}

// Parallel rollouts (navigation's candidates) reconstruct from one shared factor, each
// thread with its own CHOLMOD buffers.
TEST(RotationStrain, ConcurrentReconstructionsMatchSerial) {
  const Lattice lat = beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 4);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  const double s = 0.2 / b.U.cwiseAbs().maxCoeff();
  std::vector<Eigen::VectorXd> serial(4), parallel(4);
  for (int t = 0; t < 4; ++t) rotation_strain_positions(lat, rs, Eigen::VectorXd::Constant(4, s * (t + 1) / 4), serial[t]);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      Eigen::MatrixXd J;
      for (int rep = 0; rep < 20; ++rep)
        rotation_strain_positions(lat, rs, Eigen::VectorXd::Constant(4, s * (t + 1) / 4), parallel[t], &J);
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ((parallel[t] - serial[t]).cwiseAbs().maxCoeff(), 0.0) << "thread " << t;
}
