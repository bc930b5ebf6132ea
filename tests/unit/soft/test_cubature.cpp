// Cubature: NNLS against a known solution; the fitted cells reproduce the full
// reduced elastic force within 2% on test poses not used in training.
#include <gtest/gtest.h>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/cubature.h"
#include "pliant/soft/simulator.h"

using namespace pliant::soft;

TEST(Cubature, NnlsRecoversNonNegativeSolution) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(30, 8);
  Eigen::VectorXd w(8);
  w << 1, 0, 2, 0, 0.5, 0, 0, 3;
  const Eigen::VectorXd x = nnls(A, A * w);
  EXPECT_LT((x - w).norm(), 1e-8);
  // A target needing negative weights: the constrained optimum has x >= 0 and
  // satisfies the KKT conditions (gradient >= 0 where x = 0).
  const Eigen::VectorXd b = -A.col(0) + A.col(1);
  const Eigen::VectorXd y = nnls(A, b);
  EXPECT_GE(y.minCoeff(), 0);
  const Eigen::VectorXd grad = A.transpose() * (A * y - b);
  for (int i = 0; i < 8; ++i) {
    if (y[i] > 0) EXPECT_NEAR(grad[i], 0, 1e-8);
    else EXPECT_GT(grad[i], -1e-8);
  }
}

TEST(Cubature, ReproducesReducedForceOnTestPoses) {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 3;
  SurfaceMesh s = repair_mesh(cube);
  Lattice lat = build_lattice(s, 9, 1000);
  Character ch = make_character(std::move(s), std::move(lat), Material{}, 10);
  CubatureReport rep;
  const CellWeights w = fit_cubature(ch, training_poses(ch, 20, 0.05, 1), 0.005, 400, &rep);
  EXPECT_LT(rep.kept_fraction, 0.6);
  EXPECT_GT(rep.cells, 0);
  double worst = 0;
  for (const auto& q : training_poses(ch, 6, 0.05, 99)) {
    const Eigen::VectorXd full = reduced_force(ch, q, CellWeights{});
    const Eigen::VectorXd cub = reduced_force(ch, q, w);
    worst = std::max(worst, (full - cub).norm() / full.norm());
  }
  EXPECT_LT(worst, 0.02);
  std::printf("cubature: %d of %zu cells (%.1f%%), test error %.4f\n", rep.cells, ch.lattice.cells.size(),
              100 * rep.kept_fraction, worst);
}

// Rotation-strain coordinates: weights trained on rotation-strain poses (the map's
// shapes, J^T f) reproduce the full reduced force on unseen large poses; weights
// trained on linear poses (the same basis, x = X + U q) do worse there.
TEST(Cubature, RotationStrainForceOnUnseenLargePoses) {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 3;
  SurfaceMesh s = repair_mesh(cube);
  Lattice lat = build_lattice(s, 9, 1000);
  const Character lin = make_character(std::move(s), std::move(lat), Material{}, 8);
  Character rs = lin;
  enable_rotation_strain(rs);
  CubatureReport rep, rep_lin;
  const auto poses = training_poses(rs, 12, 0.05, 1);
  const CellWeights w = fit_cubature(rs, poses, 0.01, 400, &rep);
  const CellWeights w_lin = fit_cubature(lin, poses, 0.01, 400, &rep_lin);
  double worst = 0, worst_lin = 0;
  for (const auto& q : training_poses(rs, 6, rotation_strain_training_amplitude, 99)) {
    const Eigen::VectorXd full = reduced_force(rs, q, CellWeights{});
    worst = std::max(worst, (reduced_force(rs, q, w) - full).norm() / full.norm());
    worst_lin = std::max(worst_lin, (reduced_force(rs, q, w_lin) - full).norm() / full.norm());
  }
  std::printf("rotation-strain cubature: %d cells (linear-trained %d) of %zu; unseen large poses: force error %.4f "
              "(linear-trained weights %.4f)\n", rep.cells, rep_lin.cells, rs.lattice.cells.size(), worst, worst_lin);
  EXPECT_LT(worst, 0.03);
  EXPECT_LT(worst, worst_lin);
  EXPECT_LT(rep.kept_fraction, 0.8);
}
