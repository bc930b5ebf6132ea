#include <gtest/gtest.h>

#include "pressure_projection.h"
#include "smoke_test_util.h"

namespace pliant::smoke {
namespace {
using test::make_grid;

struct GridCase {
  int dim;
  std::array<int, 3> n;
  bool periodic;
};

class ProjectionGrid : public ::testing::TestWithParam<GridCase> {};

// After projection the divergence is gone (to the solver tolerance, limited by the
// float face storage), and both solvers give the same velocity (second method).
TEST_P(ProjectionGrid, DivergenceFreeAndSolversAgree) {
  const GridCase c = GetParam();
  const MacGrid g = make_grid(c.dim, c.n, c.periodic);
  const test::Velocity v0 = test::random_velocity(g, 17);
  test::Velocity vm = v0, vj = v0;
  PoissonSolver solver(g);
  std::vector<double> phi(g.cells(), 0.0), rhs(g.cells());
  const ProjectionStats sm = project(g, solver, PoissonMethod::MultigridPCG, 1e-9, 500, vm.mut(), phi.data(), rhs.data());
  std::fill(phi.begin(), phi.end(), 0.0);
  const ProjectionStats sj = project(g, solver, PoissonMethod::JacobiPCG, 1e-9, 5000, vj.mut(), phi.data(), rhs.data());
  EXPECT_LE(sm.relative_residual, 1e-9);
  EXPECT_LE(sj.relative_residual, 1e-9);
  EXPECT_GT(sm.max_divergence_before, 10.0);
  EXPECT_LT(sm.max_divergence_after, 1e-6 * sm.max_divergence_before);
  EXPECT_LT(sj.max_divergence_after, 1e-6 * sj.max_divergence_before);
  EXPECT_LT(sm.iterations, sj.iterations);
  double diff = 0;
  for (size_t i = 0; i < vm.u.size(); ++i) diff = std::max(diff, double(std::abs(vm.u[i] - vj.u[i])));
  for (size_t i = 0; i < vm.v.size(); ++i) diff = std::max(diff, double(std::abs(vm.v[i] - vj.v[i])));
  for (size_t i = 0; i < vm.w.size(); ++i) diff = std::max(diff, double(std::abs(vm.w[i] - vj.w[i])));
  EXPECT_LT(diff, 1e-5 * v0.max_abs());
  // Projection is idempotent: projecting again changes (almost) nothing.
  test::Velocity again = vm;
  project(g, solver, PoissonMethod::MultigridPCG, 1e-9, 500, again.mut(), phi.data(), rhs.data());
  double d2 = 0;
  for (size_t i = 0; i < vm.u.size(); ++i) d2 = std::max(d2, double(std::abs(vm.u[i] - again.u[i])));
  EXPECT_LT(d2, 1e-5 * v0.max_abs());
}

std::string case_name(const ::testing::TestParamInfo<GridCase>& info) {
  const GridCase& c = info.param;
  std::string s = std::to_string(c.n[0]);
  for (int a = 1; a < c.dim; ++a) {
    s += 'x';
    s += std::to_string(c.n[a]);
  }
  s += c.periodic ? "_periodic" : "_closed";
  return s;
}

INSTANTIATE_TEST_SUITE_P(Sizes, ProjectionGrid,
                         ::testing::Values(GridCase{2, {96, 64, 1}, false}, GridCase{2, {48, 40, 1}, true},
                                           GridCase{3, {24, 16, 20}, false}, GridCase{3, {16, 12, 8}, true},
                                           GridCase{2, {37, 21, 1}, false}),
                         case_name);

// A gradient field is removed completely; a divergence-free field is untouched.
TEST(Projection, RemovesGradientKeepsSolenoidal) {
  const MacGrid g = make_grid(2, {32, 24, 1}, false);
  const test::Velocity sol = test::random_divergence_free(g, 4);
  test::Velocity grad(g);
  std::vector<double> pot(g.cells());
  for (size_t c = 0; c < pot.size(); ++c) pot[c] = 0.01 * std::cos(0.37 * double(c));
  subtract_gradient(g, pot.data(), -1.0, grad.mut());
  test::Velocity mix = sol;
  for (size_t i = 0; i < mix.u.size(); ++i) mix.u[i] += grad.u[i];
  for (size_t i = 0; i < mix.v.size(); ++i) mix.v[i] += grad.v[i];
  PoissonSolver solver(g);
  std::vector<double> phi(g.cells(), 0.0), rhs(g.cells());
  project(g, solver, PoissonMethod::MultigridPCG, 1e-10, 200, mix.mut(), phi.data(), rhs.data());
  for (size_t i = 0; i < mix.u.size(); ++i) ASSERT_NEAR(mix.u[i], sol.u[i], 1e-5);
  for (size_t i = 0; i < mix.v.size(); ++i) ASSERT_NEAR(mix.v[i], sol.v[i], 1e-5);
}

// MGPCG needs far fewer iterations than Jacobi-PCG at 128^2 (smooth right-hand side).
TEST(Projection, MultigridBeatsJacobiAt128) {
  const MacGrid g = make_grid(2, {128, 128, 1}, false, 1.0 / 128);
  test::Velocity v(g);
  for (int j = 0; j < 128; ++j)
    for (int i = 1; i < 128; ++i) v.u[g.face_lo(0, i, j, 0)] = float(std::sin(0.05 * i) + 0.3 * std::cos(0.11 * j));
  PoissonSolver solver(g);
  std::vector<double> phi(g.cells(), 0.0), rhs(g.cells());
  test::Velocity a = v, b = v;
  const auto sm = project(g, solver, PoissonMethod::MultigridPCG, 1e-6, 1000, a.mut(), phi.data(), rhs.data());
  std::fill(phi.begin(), phi.end(), 0.0);
  const auto sj = project(g, solver, PoissonMethod::JacobiPCG, 1e-6, 5000, b.mut(), phi.data(), rhs.data());
  EXPECT_LT(3 * sm.iterations, sj.iterations) << sm.iterations << " vs " << sj.iterations;
  EXPECT_LE(sm.iterations, 15);
}

}  // namespace
}  // namespace pliant::smoke
