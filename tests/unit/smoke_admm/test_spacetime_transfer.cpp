// Restriction is the transpose of prolongation up to the factor 2^dim, and both
// reproduce constants (cells) / linear fields away from clamped boundaries.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "spacetime_multigrid_transfer.h"

namespace pliant::smoke {
namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

void check_transpose(int dim, bool periodic) {
  MacGrid g;
  g.dim = dim;
  g.n = {16, 8, dim == 3 ? 8 : 1};
  g.periodic = periodic;
  const SpacetimeGrid fine(g, 1), coarse = fine.coarsened();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const double scale = dim == 3 ? 8.0 : 4.0;
  for (int cells = 0; cells < 2; ++cells) {
    const size_t nf = cells ? fine.cells() : fine.faces(), nc = cells ? coarse.cells() : coarse.faces();
    std::vector<double> xc(nc), yf(nf), Px(nf), Ry(nc);
    for (auto& v : xc) v = U(rng);
    for (auto& v : yf) v = U(rng);
    if (cells) {
      prolong_cells(fine, coarse, xc.data(), Px.data());
      restrict_cells(fine, coarse, yf.data(), Ry.data());
    } else {
      prolong_faces(fine, coarse, xc.data(), Px.data());
      restrict_faces(fine, coarse, yf.data(), Ry.data());
    }
    const double lhs = dot(Px, yf), rhs = scale * dot(xc, Ry);
    EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(lhs) + 1e-12) << "dim " << dim << " periodic " << periodic
                                                          << " cells " << cells;
    // Rows of R sum to one: constants restrict exactly.
    std::vector<double> one(nf, 1.0), r1(nc);
    if (cells) restrict_cells(fine, coarse, one.data(), r1.data());
    else restrict_faces(fine, coarse, one.data(), r1.data());
    if (cells || periodic) {
      for (double v : r1) ASSERT_NEAR(v, 1.0, 1e-12);
    }
  }
}

TEST(SpacetimeTransfer, RestrictionIsScaledTransposeOfProlongation2D) {
  check_transpose(2, false);
  check_transpose(2, true);
}
TEST(SpacetimeTransfer, RestrictionIsScaledTransposeOfProlongation3D) {
  check_transpose(3, false);
  check_transpose(3, true);
}

TEST(SpacetimeTransfer, ProlongationIsExactForLinearFaceFields) {
  MacGrid g;
  g.dim = 2;
  g.n = {16, 16, 1};
  const SpacetimeGrid fine(g, 1), coarse = fine.coarsened();
  // u(x, y) = x (grid units of the fine grid) sampled on coarse u faces: x = 2 i.
  std::vector<double> xc(coarse.faces(), 0.0), xf(fine.faces());
  const FieldLayout lc = coarse.g.face_layout(0), lf = fine.g.face_layout(0);
  for (int j = 0; j < lc.size[1]; ++j)
    for (int i = 0; i < lc.size[0]; ++i) xc[lc.index(i, j, 0)] = 2.0 * i;
  prolong_faces(fine, coarse, xc.data(), xf.data());
  for (int j = 0; j < lf.size[1]; ++j)
    for (int i = 0; i < lf.size[0]; ++i) ASSERT_NEAR(xf[lf.index(i, j, 0)], double(i), 1e-12);
}

}  // namespace
}  // namespace pliant::smoke
