// Rotation-strain reconstruction: linear modes at first order, exact rigid rotation
// for a rotation field (where linear modes grow the body), Jacobian against central
// differences, per-thread buffers.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <thread>
#include <vector>

#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"
#include "rotation_strain_test_lattices.h"

using namespace pliant::soft;
using pliant::soft::test::beam_lattice;
using pliant::soft::test::centred_rest;

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
  // The reduced reconstruction (thread-local buffers, shared operators) likewise.
  RotationStrain rr = rs;
  std::vector<Eigen::VectorXd> train;
  for (int p = 0; p < 6; ++p) train.push_back(Eigen::VectorXd::Constant(4, s * (p + 1) / 6) + 0.3 * s * Eigen::VectorXd::Unit(4, p % 4));
  rr.reduced = rotation_strain_reduce(lat, rr, b.U, centred_rest(lat), train, RsReductionSettings{});
  std::vector<Eigen::MatrixXd> Js(4), Jp(4);
  for (int t = 0; t < 4; ++t)
    rotation_strain_reduced_positions(*rr.reduced, Eigen::VectorXd::Constant(4, s * (t + 1) / 4), serial[t], &Js[t]);
  threads.clear();
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int rep = 0; rep < 20; ++rep)
        rotation_strain_reduced_positions(*rr.reduced, Eigen::VectorXd::Constant(4, s * (t + 1) / 4), parallel[t], &Jp[t]);
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < 4; ++t) {
    EXPECT_EQ((parallel[t] - serial[t]).cwiseAbs().maxCoeff(), 0.0) << "reduced, thread " << t;
    EXPECT_EQ((Jp[t] - Js[t]).cwiseAbs().maxCoeff(), 0.0) << "reduced, thread " << t;
  }
}
