// The compact Picard stencil of the NSO (nso_advection_stencil.h) against dense
// matrices built from it column by column: A^T is the adjoint of A, the A^T A entries
// SCGS uses match the dense product, and the direct entry lookup matches the rows.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "nso_advection_stencil.h"

namespace pliant::smoke {
namespace {

struct Case {
  int dim, n;
  bool periodic;
};

class NsoAdvectionStencil : public ::testing::TestWithParam<Case> {};

TEST_P(NsoAdvectionStencil, TransposeAndSquareMatchTheDenseOperator) {
  const Case c = GetParam();
  MacGrid g;
  g.dim = c.dim;
  g.n = {c.n, c.n, c.dim == 3 ? c.n : 1};
  g.h = 1.0 / c.n;
  g.periodic = c.periodic;
  const SpacetimeGrid sg(g, 1);
  const size_t F = sg.faces();
  // A random velocity with Courant numbers up to ~1.5: backtraces cross cells, walls and
  // (periodic) the box edges.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.5, 1.5);
  std::vector<double> zbar(F);
  for (double& v : zbar) v = U(rng);
  SlStencil s;
  build_sl_stencil(sg, zbar.data(), g.h, s);  // dt = h: velocity in cells per frame
  // Dense A from columns: A e_j.
  std::vector<double> A(F * F), e(F, 0.0), col(F);
  for (size_t j = 0; j < F; ++j) {
    e[j] = 1.0;
    sl_apply(sg, s, e.data(), col.data());
    e[j] = 0.0;
    for (size_t i = 0; i < F; ++i) A[i * F + j] = col[i];
  }
  // Adjoint: y += alpha A^T x equals the dense transpose.
  std::vector<double> x(F), y(F, 0.0);
  for (double& v : x) v = U(rng);
  sl_apply_transpose_add(sg, s, 0.5, x.data(), y.data());
  double err = 0;
  for (size_t j = 0; j < F; ++j) {
    double ref = 0;
    for (size_t i = 0; i < F; ++i) ref += 0.5 * A[i * F + j] * x[i];
    err = std::max(err, std::abs(y[j] - ref));
  }
  EXPECT_LT(err, 1e-12);
  // A^T A: diagonal and (face, hi partner) entries; direct entry lookup.
  std::vector<double> diag(F), hi(F);
  sl_ata(sg, s, diag.data(), hi.data());
  double err_d = 0, err_h = 0, err_e = 0, nonzero_hi = 0;
  for (size_t p = 0; p < F; ++p) {
    double d = 0, h = 0;
    const int64_t q = face_hi_partner(sg, p);
    for (size_t i = 0; i < F; ++i) {
      d += A[i * F + p] * A[i * F + p];
      if (q >= 0) h += A[i * F + p] * A[i * F + size_t(q)];
    }
    err_d = std::max(err_d, std::abs(diag[p] - d));
    err_h = std::max(err_h, std::abs(hi[p] - h));
    nonzero_hi += std::abs(h);
    for (size_t j = 0; j < F; ++j) err_e = std::max(err_e, std::abs(sl_entry(sg, s, p, j) - A[p * F + j]));
  }
  EXPECT_LT(err_d, 1e-12);
  EXPECT_LT(err_h, 1e-12);
  EXPECT_GT(nonzero_hi, 1.0);  // the test exercises the hi coupling
  EXPECT_LT(err_e, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Grids, NsoAdvectionStencil,
                         ::testing::Values(Case{2, 6, false}, Case{2, 6, true}, Case{3, 4, false}, Case{3, 4, true}));

}  // namespace
}  // namespace pliant::smoke
