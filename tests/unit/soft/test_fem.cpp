// Stable neo-Hookean FEM: stress and Hessian against finite differences, rest state
// stress-free, linearization equals linear elasticity.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "pliant/soft/body.h"
#include "pliant/soft/fem.h"

using namespace pliant::soft;

namespace {
Lame test_lame() { return lame_from(Material{1000, 1e5, 0.35}); }

Eigen::Matrix3d random_F(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
  return F;
}

// The lattice of a 2x1x1 box at `resolution` cells along its longest side.
Lattice fem_box_lattice(int resolution) {
  SurfaceMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back({(i & 1) * 2.0, double((i >> 1) & 1), double((i >> 2) & 1)});
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return build_lattice(m, resolution, 1000);
}

Lattice two_cells() { return fem_box_lattice(2); }
}  // namespace

TEST(Fem, RestIsStressFree) {
  const Lame l = test_lame();
  EXPECT_NEAR(snh_stress(l, Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
}

TEST(Fem, StressMatchesFiniteDifferences) {
  std::mt19937 rng(1);
  const Lame l = test_lame();
  for (int trial = 0; trial < 5; ++trial) {
    // Include inverted configurations (J < 0): the stable form stays smooth there.
    Eigen::Matrix3d F = random_F(rng, 0.4);
    if (trial == 4) F.col(0) *= -1;
    const Eigen::Matrix3d P = snh_stress(l, F);
    const double h = 1e-6;
    for (int i = 0; i < 9; ++i) {
      Eigen::Matrix3d Fp = F, Fm = F;
      Fp.data()[i] += h;
      Fm.data()[i] -= h;
      const double fd = (snh_energy(l, Fp) - snh_energy(l, Fm)) / (2 * h);
      EXPECT_NEAR(P.data()[i], fd, 1e-5 * std::max(1.0, std::abs(fd)));
    }
  }
}

TEST(Fem, StressDerivativeMatchesFiniteDifferences) {
  std::mt19937 rng(2);
  const Lame l = test_lame();
  const Eigen::Matrix3d F = random_F(rng, 0.3);
  const auto A = snh_stress_derivative(l, F);
  const double h = 1e-6;
  for (int j = 0; j < 9; ++j) {
    Eigen::Matrix3d Fp = F, Fm = F;
    Fp.data()[j] += h;
    Fm.data()[j] -= h;
    const Eigen::Matrix3d dP = (snh_stress(l, Fp) - snh_stress(l, Fm)) / (2 * h);
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(A(i, j), dP.data()[i], 1e-4 * std::max(1.0, std::abs(dP.data()[i])));
  }
}

TEST(Fem, LinearizationIsLinearElasticity) {
  const Material mat{1000, 2e5, 0.3};
  const Lame l = lame_from(mat);
  const double mu = mat.young_pa / (2 * 1.3), lambda = mat.young_pa * 0.3 / (1.3 * 0.4);
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 1e-7;  // uniaxial strain
  const Eigen::Matrix3d P = snh_stress(l, Eigen::Matrix3d::Identity() + E);
  EXPECT_NEAR(P(0, 0), (2 * mu + lambda) * 1e-7, 1e-6 * (2 * mu + lambda) * 1e-7 + 1e-9);
  EXPECT_NEAR(P(1, 1), lambda * 1e-7, 1e-3 * lambda * 1e-7 + 1e-9);
}

TEST(Fem, LatticeGradientAndHessianMatchFiniteDifferences) {
  const Lattice lat = two_cells();
  ASSERT_EQ(lat.cells.size(), 2u);
  const Lame l = test_lame();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Eigen::VectorXd x(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j) x.segment<3>(3 * j) = lat.rest[j];
  for (int i = 0; i < x.size(); ++i) x[i] += u(rng);
  Eigen::VectorXd g;
  Eigen::SparseMatrix<double> H;
  elastic_energy(lat, l, x, CellWeights{}, &g, &H);
  const Eigen::MatrixXd Hd(H);
  const double h = 1e-6;
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x, gp, gm;
    xp[i] += h;
    xm[i] -= h;
    const double ep = elastic_energy(lat, l, xp, CellWeights{}, &gp, nullptr);
    const double em = elastic_energy(lat, l, xm, CellWeights{}, &gm, nullptr);
    EXPECT_NEAR(g[i], (ep - em) / (2 * h), 1e-5 * std::max(1.0, g.cwiseAbs().maxCoeff()));
    const Eigen::VectorXd col = (gp - gm) / (2 * h);
    EXPECT_LT((Hd.col(i) - col).cwiseAbs().maxCoeff(), 1e-4 * std::max(1.0, Hd.cwiseAbs().maxCoeff()));
  }
  // cell_force is minus the per-cell gradient.
  double f[24];
  cell_force(lat, l, x, 0, f);
  Eigen::VectorXd g0;
  CellWeights only0;
  only0.cells = {0};
  only0.weights = {1.0};
  elastic_energy(lat, l, x, only0, &g0, nullptr);
  for (int a = 0; a < 8; ++a)
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(f[3 * a + d], -g0[3 * lat.cells[0][a] + d], 1e-9 * g0.norm());
}

namespace {
// A 4 x 2 x 2 box lattice (16 cells) for the reduced-Hessian checks.
Lattice fem_reduced_box() { return fem_box_lattice(4); }

double fem_reduced_rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}
}  // namespace

// elastic_reduced keeps D_q = B_q U_e per cell between calls (constant bases) and
// computes one triangle of D^T A D: it must equal U^T (dE/dx, K) U of the nodal
// assembly on the first call, reuse bit for bit on the second, and notice a changed U.
TEST(Fem, ReducedHessianMatchesProjectedAssemblyAndCacheFollowsBasis) {
  const Lattice lat = fem_reduced_box();
  ASSERT_EQ(lat.cells.size(), 16u);
  const Lame l = test_lame();
  const int n = lat.nodes(), r = 5;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Eigen::MatrixXd U(3 * n, r);
  for (int i = 0; i < U.size(); ++i) U.data()[i] = u(rng);
  Eigen::VectorXd x(3 * n);
  for (int j = 0; j < n; ++j) x.segment<3>(3 * j) = lat.rest[j];
  for (int i = 0; i < x.size(); ++i) x[i] += u(rng);
  CellWeights cw;
  cw.cells = {1, 4, 6, 9, 15};
  cw.weights = {0.5, 2.0, 1.25, 3.0, 0.75};
  auto direct = [&](const Eigen::MatrixXd& B, Eigen::VectorXd& g, Eigen::MatrixXd& H) {
    Eigen::VectorXd gx;
    Eigen::SparseMatrix<double> K;
    const double e = elastic_energy(lat, l, x, cw, &gx, &K);
    g = B.transpose() * gx;
    H = B.transpose() * (K * B);
    return e;
  };
  Eigen::VectorXd g_ref, g1, g2;
  Eigen::MatrixXd H_ref, H1, H2;
  const double e_ref = direct(U, g_ref, H_ref);
  const double e1 = elastic_reduced(lat, l, x, cw, U, &g1, &H1);
  EXPECT_NEAR(e1, e_ref, 1e-13 * std::abs(e_ref));
  EXPECT_LT(fem_reduced_rel(g1, g_ref), 1e-12);
  EXPECT_LT(fem_reduced_rel(H1, H_ref), 1e-12);
  EXPECT_EQ((H1 - H1.transpose()).cwiseAbs().maxCoeff(), 0.0);  // symmetric by construction
  elastic_reduced(lat, l, x, cw, U, &g2, &H2);  // cached D
  EXPECT_EQ((H2 - H1).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((g2 - g1).cwiseAbs().maxCoeff(), 0.0);
  // Change U on one node of a kept cell only: the cache must rebuild that cell.
  Eigen::MatrixXd U2 = U;
  U2.row(3 * lat.cells[6][3] + 1) *= 3.0;
  direct(U2, g_ref, H_ref);
  elastic_reduced(lat, l, x, cw, U2, &g2, &H2);
  EXPECT_GT(fem_reduced_rel(H2, H1), 1e-6);
  EXPECT_LT(fem_reduced_rel(g2, g_ref), 1e-12);
  EXPECT_LT(fem_reduced_rel(H2, H_ref), 1e-12);
  // Above the cache limit D is rebuilt per call in one scratch cell: same bits.
  elastic_reduced(lat, l, x, cw, U, &g1, &H1);
  const size_t old_limit = set_reduced_cache_limit(0);
  elastic_reduced(lat, l, x, cw, U, &g2, &H2);
  set_reduced_cache_limit(old_limit);
  EXPECT_EQ((H2 - H1).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((g2 - g1).cwiseAbs().maxCoeff(), 0.0);
  // Every cell (no cubature) also agrees.
  cw = CellWeights{};
  direct(U, g_ref, H_ref);
  elastic_reduced(lat, l, x, cw, U, &g1, &H1);
  EXPECT_LT(fem_reduced_rel(H1, H_ref), 1e-12);
  EXPECT_LT(fem_reduced_rel(g1, g_ref), 1e-12);
}
