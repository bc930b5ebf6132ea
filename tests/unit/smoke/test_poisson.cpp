#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "poisson.h"
#include "pressure_projection.h"
#include "smoke_test_util.h"

namespace pliant::smoke {
namespace {
using test::make_grid;

// Periodic manufactured solution phi = sin(2 pi x) cos(4 pi y) on [0,1]^2:
// -lap phi = 20 pi^2 phi, so A phi = h^2 * 20 pi^2 phi; the discrete solution's
// error must fall by ~4x per halving of h (second order).
double manufactured_error(int n, PoissonMethod method) {
  const MacGrid g = make_grid(2, {n, n, 1}, true, 1.0 / n);
  PoissonSolver solver(g);
  std::vector<double> b(g.cells()), x(g.cells(), 0.0), exact(g.cells());
  const double pi = std::numbers::pi;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double px = (i + 0.5) * g.h, py = (j + 0.5) * g.h;
      exact[g.cell(i, j, 0)] = std::sin(2 * pi * px) * std::cos(4 * pi * py);
      b[g.cell(i, j, 0)] = g.h * g.h * 20 * pi * pi * exact[g.cell(i, j, 0)];
    }
  const PoissonStats st = solver.solve(method, b.data(), x.data(), 1e-12, 2000);
  EXPECT_LE(st.relative_residual, 1e-12);
  double err = 0;
  for (size_t c = 0; c < x.size(); ++c) err = std::max(err, std::abs(x[c] - exact[c]));
  return err;
}

TEST(Poisson, ManufacturedSolutionConvergesAtSecondOrder) {
  for (PoissonMethod m : {PoissonMethod::MultigridPCG, PoissonMethod::JacobiPCG}) {
    const double e16 = manufactured_error(16, m), e32 = manufactured_error(32, m),
                 e64 = manufactured_error(64, m);
    EXPECT_LT(e64, 4e-3);  // ~ (k h)^2 / 12 relative truncation error
    EXPECT_NEAR(std::log2(e16 / e32), 2.0, 0.15);
    EXPECT_NEAR(std::log2(e32 / e64), 2.0, 0.1);
  }
}

// CG needs a symmetric preconditioner: <r1, M r2> == <r2, M r1>.
TEST(Poisson, MultigridPreconditionerIsSymmetricAndPositive) {
  struct Shape {
    int dim;
    std::array<int, 3> n;
    bool periodic;
  };
  for (const Shape& s : {Shape{2, {24, 40, 1}, false}, Shape{2, {32, 12, 1}, true},
                         Shape{3, {12, 8, 16}, false}, Shape{3, {8, 8, 8}, true}, Shape{2, {15, 9, 1}, true}}) {
    const MacGrid g = make_grid(s.dim, s.n, s.periodic);
    PoissonSolver solver(g);
    std::mt19937 rng(9);
    std::normal_distribution<double> d;
    std::vector<double> r1(g.cells()), r2(g.cells()), z1(g.cells()), z2(g.cells());
    for (auto& x : r1) x = d(rng);
    for (auto& x : r2) x = d(rng);
    remove_mean(r1.data(), r1.size());
    remove_mean(r2.data(), r2.size());
    solver.precondition(PoissonMethod::MultigridPCG, r1.data(), z1.data());
    solver.precondition(PoissonMethod::MultigridPCG, r2.data(), z2.data());
    double a = 0, b = 0, p = 0, rr = 0;
    for (size_t c = 0; c < r1.size(); ++c) {
      a += r1[c] * z2[c];
      b += r2[c] * z1[c];
      p += r1[c] * z1[c];
      rr += r1[c] * r1[c];
    }
    EXPECT_NEAR(a, b, 1e-10 * std::sqrt(rr) * std::sqrt(p)) << s.n[0] << "x" << s.n[1] << "x" << s.n[2];
    EXPECT_GT(p, 0.0);
  }
}

// Levels halve while every axis is even and >= 4 (96x128 -> ... -> 3x4).
TEST(Poisson, LevelsOfNonPowerOfTwoGrid) {
  PoissonSolver s(make_grid(2, {96, 128, 1}, false));
  ASSERT_EQ(s.levels(), 6);
  EXPECT_EQ(s.level(5).n[0], 3);
  EXPECT_EQ(s.level(5).n[1], 4);
  PoissonSolver odd(make_grid(3, {9, 8, 8}, false));
  EXPECT_EQ(odd.levels(), 1);
}

}  // namespace
}  // namespace pliant::smoke
