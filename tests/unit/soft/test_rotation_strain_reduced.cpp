// Reduced rotation-strain reconstruction (POD of the remainder + cell cubature)
// against the full solve and against differences of itself.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"
#include "rotation_strain_test_lattices.h"

using namespace pliant::soft;
using pliant::soft::test::centred_rest;

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
