// Rotation-strain adjoint products: (dx/dz)^T g against the explicit Jacobian, the
// curvature term against central differences of the Jacobian.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"
#include "rotation_strain_test_lattices.h"

using namespace pliant::soft;
using pliant::soft::test::beam_lattice;

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
