// Linear modes: K phi = omega^2 M phi residual, M-orthonormality, rigid-mode
// deflation; dense and CHOLMOD subspace-iteration paths agree.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/modes.h"

using namespace pliant::soft;

namespace {
Lattice box_lattice(int res) {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 3;  // a 3 x 1 x 1 beam
  return build_lattice(repair_mesh(cube), res, 1000);
}

void check_modes(const Lattice& lat, const Lame& l, const ModalBasis& b) {
  Eigen::VectorXd x(3 * lat.nodes()), m(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j) {
    x.segment<3>(3 * j) = lat.rest[j];
    m.segment<3>(3 * j).setConstant(lat.node_mass_kg[j]);
  }
  Eigen::SparseMatrix<double> K;
  elastic_energy(lat, l, x, CellWeights{}, nullptr, &K);
  const Eigen::MatrixXd UtMU = b.U.transpose() * m.asDiagonal() * b.U;
  EXPECT_LT((UtMU - Eigen::MatrixXd::Identity(b.r(), b.r())).cwiseAbs().maxCoeff(), 1e-8);
  for (int k = 0; k < b.r(); ++k) {
    EXPECT_GT(b.omega2[k], 1e-3);  // no rigid mode left
    const Eigen::VectorXd res = K * b.U.col(k) - b.omega2[k] * m.asDiagonal() * b.U.col(k);
    EXPECT_LT(res.norm(), 1e-4 * b.omega2[k] * (m.asDiagonal() * b.U.col(k)).norm());
  }
  const Eigen::MatrixXd R = rigid_modes(lat);
  EXPECT_LT((R.transpose() * m.asDiagonal() * b.U).cwiseAbs().maxCoeff(), 1e-8);
}
}  // namespace

TEST(Modes, DenseModesSatisfyEigenproblem) {
  const Lattice lat = box_lattice(6);
  ASSERT_LE(3 * lat.nodes(), 900);
  const Lame l = lame_from(Material{});
  const ModalBasis b = linear_modes(lat, l, 10);
  ASSERT_EQ(b.r(), 10);
  check_modes(lat, l, b);
}

TEST(Modes, SubspaceIterationMatchesDense) {
  const Lattice lat = box_lattice(12);
  ASSERT_GT(3 * lat.nodes(), 900);
  const Lame l = lame_from(Material{});
  const ModalBasis b = linear_modes(lat, l, 6);
  check_modes(lat, l, b);
  // Bending of a 3:1 beam: the two lowest modes are a near-degenerate pair.
  EXPECT_NEAR(b.omega2[0], b.omega2[1], 0.05 * b.omega2[0]);
}

TEST(Modes, ModalDerivativesExtendTheBasis) {
  const Lattice lat = box_lattice(6);
  const Lame l = lame_from(Material{});
  const ModalBasis b = linear_modes(lat, l, 6);
  const ModalBasis d = with_modal_derivatives(lat, l, b, 3);
  EXPECT_EQ(d.r(), 6 + 6);  // 3 * 4 / 2 derivatives
  Eigen::VectorXd m(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j) m.segment<3>(3 * j).setConstant(lat.node_mass_kg[j]);
  const Eigen::MatrixXd UtMU = d.U.transpose() * m.asDiagonal() * d.U;
  EXPECT_LT((UtMU - Eigen::MatrixXd::Identity(d.r(), d.r())).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((rigid_modes(lat).transpose() * m.asDiagonal() * d.U).cwiseAbs().maxCoeff(), 1e-8);
  // The original modes stay in the span: projecting them loses nothing.
  const Eigen::MatrixXd P = d.U * (d.U.transpose() * m.asDiagonal() * b.U);
  EXPECT_LT((P - b.U).norm(), 1e-8 * b.U.norm());
  // U^T K U is diagonal (omega2) after the Rayleigh-Ritz rotation.
  Eigen::VectorXd x(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j) x.segment<3>(3 * j) = lat.rest[j];
  Eigen::SparseMatrix<double> K;
  elastic_energy(lat, l, x, CellWeights{}, nullptr, &K);
  const Eigen::MatrixXd Kr = d.U.transpose() * (K * d.U);
  EXPECT_LT((Kr - Eigen::MatrixXd(d.omega2.asDiagonal())).cwiseAbs().maxCoeff(), 1e-6 * d.omega2.maxCoeff());
}

TEST(Modes, PodRecoversTheSpanOfItsSnapshots) {
  // Snapshots mixing modes 1, 3, 4 plus rigid motion: the 3-vector POD spans exactly
  // those modes (rigid part removed), so Rayleigh-Ritz gives back their eigenvalues.
  const Lattice lat = box_lattice(6);
  const Lame l = lame_from(Material{});
  const ModalBasis b = linear_modes(lat, l, 6);
  const Eigen::MatrixXd R = rigid_modes(lat);
  std::vector<Eigen::VectorXd> snaps;
  for (int s = 0; s < 12; ++s) {
    const double a = std::sin(1.0 + s), c = std::cos(2.0 * s), d = 0.3 * std::sin(3.0 * s + 0.5);
    snaps.push_back(a * b.U.col(1) + c * b.U.col(3) + d * b.U.col(4) + (0.1 * s) * R.col(s % 6));
  }
  const ModalBasis p = pod_basis(lat, l, snaps, 3);
  ASSERT_EQ(p.r(), 3);
  EXPECT_NEAR(p.omega2[0], b.omega2[1], 1e-6 * b.omega2[1]);
  EXPECT_NEAR(p.omega2[1], b.omega2[3], 1e-6 * b.omega2[3]);
  EXPECT_NEAR(p.omega2[2], b.omega2[4], 1e-6 * b.omega2[4]);
  Eigen::VectorXd m(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j) m.segment<3>(3 * j).setConstant(lat.node_mass_kg[j]);
  const Eigen::MatrixXd UtMU = p.U.transpose() * m.asDiagonal() * p.U;
  EXPECT_LT((UtMU - Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((R.transpose() * m.asDiagonal() * p.U).cwiseAbs().maxCoeff(), 1e-8);
}
