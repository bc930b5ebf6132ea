// Rotation-strain reconstruction: linear modes at first order, exact rigid rotation
// for a rotation field (where linear modes grow the body), Jacobian against central
// differences.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>
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

TEST(RotationStrain, AdjointProductMatchesTheJacobian) {
  const Lattice lat = beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 5);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  Eigen::VectorXd z(5), x, out;
  z << 0.7, -0.4, 0.5, 0.3, -0.6;
  z *= 0.2 / b.U.cwiseAbs().maxCoeff();
  Eigen::MatrixXd J;
  rotation_strain_positions(lat, rs, z, x, &J);
  const Eigen::VectorXd g = Eigen::VectorXd::Random(x.size());
  rotation_strain_vjp(lat, rs, z, g, out);
  const Eigen::VectorXd ref = J.transpose() * g;
  EXPECT_LT((out - ref).norm(), 1e-10 * ref.norm());
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

// Reduced reconstruction (POD of the remainder + cell cubature): on poses it was not
// trained on, shapes close to the full solve up to a rigid rotation (the reduced map
// leaves net rotation to the floating frame); dx/dz and the curvature term against
// central differences of the reduced map itself.
TEST(RotationStrain, ReducedReconstructionFollowsTheFullSolve) {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 3;
  const Lattice lat = build_lattice(repair_mesh(cube), 9, 1000);
  const int r = 6;
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), r);
  RotationStrain rs = rotation_strain_build(lat, b.U);
  const Eigen::VectorXd X = centred_rest(lat);
  // Random poses whose linear displacement reaches up to 30% of the beam length.
  auto poses = [&](int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> nd;
    std::vector<Eigen::VectorXd> out;
    for (int p = 0; p < count; ++p) {
      Eigen::VectorXd z(r);
      for (int k = 0; k < r; ++k) z[k] = nd(rng) * std::sqrt(b.omega2[0] / b.omega2[k]);
      const double amp = (b.U * z).reshaped(3, lat.nodes()).colwise().norm().maxCoeff();
      out.push_back(z * (0.3 * 3.0 / amp) * (0.3 + 0.7 * (p + 1.0) / count));
    }
    return out;
  };
  rs.reduced = rotation_strain_reduce(lat, rs, b.U, X, poses(24, 5), RsReductionSettings{});
  const RsReduced& red = *rs.reduced;
  Eigen::VectorXd x, y;
  double worst = 0;
  for (const auto& z : poses(6, 77)) {
    rotation_strain_positions(lat, rs, z, x);
    rotation_strain_reduced_positions(red, z, y);
    // Best rotation of y onto x (both centred), then the relative error.
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (int j = 0; j < lat.nodes(); ++j) C += x.segment<3>(3 * j) * y.segment<3>(3 * j).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d Q = svd.matrixU() * svd.matrixV().transpose();
    for (int j = 0; j < lat.nodes(); ++j) y.segment<3>(3 * j) = Q * y.segment<3>(3 * j);
    worst = std::max(worst, (y - x).norm() / (x - X).norm());
  }
  std::printf("reduced RS: m %d, %zu of %zu cells, basis error %.4f, cubature error %.4f; unseen poses: worst shape "
              "error %.4f of the deformation\n", red.m, red.cells.size(), lat.cells.size(), red.basis_error,
              red.cubature_error, worst);
  EXPECT_LT(worst, 0.08);
  EXPECT_LT(red.cells.size(), lat.cells.size() * 3 / 4);
  // dx/dz and the curvature against central differences of the reduced map.
  const Eigen::VectorXd z = poses(3, 4)[2];
  Eigen::MatrixXd J, Jp, Jm, Tc;
  rotation_strain_reduced_positions(red, z, y, &J);
  const Eigen::VectorXd g = Eigen::VectorXd::Random(y.size());
  rotation_strain_reduced_curvature(red, z, g, Tc);
  double jerr = 0, cerr = 0;
  Eigen::VectorXd xm;
  for (int k = 0; k < r; ++k) {
    const double h = 1e-6 * z.norm();
    Eigen::VectorXd zp = z, zm = z;
    zp[k] += h, zm[k] -= h;
    rotation_strain_reduced_positions(red, zp, x, &Jp);
    rotation_strain_reduced_positions(red, zm, xm, &Jm);
    jerr = std::max(jerr, ((x - xm) / (2 * h) - J.col(k)).norm() / J.col(k).norm());
    cerr = std::max(cerr, ((Jp.transpose() * g - Jm.transpose() * g) / (2 * h) - Tc.col(k)).norm() / Tc.norm());
  }
  EXPECT_LT(jerr, 1e-5);
  EXPECT_LT(cerr, 1e-4);
}
