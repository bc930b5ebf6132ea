// Block Thomas solve of one SCGS block against a dense LU of the assembled matrix.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "scgs_block_tridiagonal.h"

namespace pliant::smoke {
namespace {

// Max error of the block Thomas solve against a dense LU; `coupled_cols` columns of the
// L/U blocks are non-zero (4: SCGS's pattern, no dual coupling in time; 5: dense blocks,
// so the solver's zero-column shortcut is checked in both cases).
double block_solve_error(int coupled_cols) {
  const int T = 7, m = 5, mm = m * m;  // 2D: 4 faces + 1 dual per frame
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<double> B(T * mm, 0.0), L(T * mm, 0.0), Up(T * mm, 0.0), rhs(T * m);
  for (int t = 0; t < T; ++t) {
    double* b = &B[t * mm];
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j <= i; ++j) b[i * m + j] = b[j * m + i] = (i == j ? 6.0 : 0.5 * U(rng));
    for (int i = 0; i < 4; ++i) b[i * m + 4] = b[4 * m + i] = (i % 2 ? 1.0 : -1.0) * 50.0;  // 1/h
    b[4 * m + 4] = 0.0;                                                                   // saddle
    if (t > 0)
      for (int i = 0; i < coupled_cols; ++i)
        for (int j = 0; j < coupled_cols; ++j) {
          L[t * mm + i * m + j] = -2.0 * std::abs(U(rng));
          Up[(t - 1) * mm + j * m + i] = L[t * mm + i * m + j];
        }
    for (int i = 0; i < m; ++i) rhs[t * m + i] = U(rng);
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(T * m, T * m);
  Eigen::VectorXd b(T * m);
  for (int t = 0; t < T; ++t)
    for (int i = 0; i < m; ++i) {
      b(t * m + i) = rhs[t * m + i];
      for (int j = 0; j < m; ++j) {
        A(t * m + i, t * m + j) = B[t * mm + i * m + j];
        if (t > 0) A(t * m + i, (t - 1) * m + j) = L[t * mm + i * m + j];
        if (t + 1 < T) A(t * m + i, (t + 1) * m + j) = Up[t * mm + i * m + j];
      }
    }
  const Eigen::VectorXd ref = A.fullPivLu().solve(b);
  std::vector<double> schur(T * mm), sinv(T * mm);
  std::vector<int> piv(T * m);
  if (!block_tridiagonal_solve(T, m, B.data(), L.data(), Up.data(), rhs.data(), {schur.data(), sinv.data(), piv.data()}))
    return 1e300;
  double err = 0, nrm = 0;
  for (int e = 0; e < T * m; ++e) err = std::max(err, std::abs(rhs[e] - ref(e))), nrm = std::max(nrm, std::abs(ref(e)));
  return err / nrm;
}

TEST(ScgsBlockTridiagonal, MatchesDenseSolveOnSaddlePointBlocks) { EXPECT_LT(block_solve_error(4), 1e-10); }

TEST(ScgsBlockTridiagonal, MatchesDenseSolveWithDualCoupledInTime) { EXPECT_LT(block_solve_error(5), 1e-10); }

TEST(ScgsBlockTridiagonal, ReportsSingularBlock) {
  const int T = 2, m = 2;
  std::vector<double> B(T * 4, 0.0), L(T * 4, 0.0), U(T * 4, 0.0), rhs(T * 2, 1.0), s1(8), s2(8);
  std::vector<int> piv(4);
  EXPECT_FALSE(block_tridiagonal_solve(T, m, B.data(), L.data(), U.data(), rhs.data(), {s1.data(), s2.data(), piv.data()}));
}

}  // namespace
}  // namespace pliant::smoke
