#include <gtest/gtest.h>

#include <cmath>

#include "advection.h"
#include "smoke_test_util.h"

namespace pliant::smoke {
namespace {
using test::make_grid;

struct Case {
  int dim;
  bool periodic;
};

class UpwindConservation : public ::testing::TestWithParam<Case> {};

// Eq. 3.2 flux form: every interior flux leaves one cell and enters its neighbour,
// walls carry none, so sum(rho) is constant; sub-stepping keeps rho >= 0.
TEST_P(UpwindConservation, TotalDensityConstantAndNonNegative) {
  const Case c = GetParam();
  const MacGrid g = c.dim == 2 ? make_grid(2, {40, 24, 1}, c.periodic) : make_grid(3, {12, 10, 8}, c.periodic);
  const test::Velocity vel = test::random_divergence_free(g, 7, 0.5f);
  std::vector<float> rho(g.cells()), scratch(g.cells());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> d(0.0f, 1.0f);
  for (float& x : rho) x = d(rng) < 0.3f ? d(rng) : 0.0f;
  const double total0 = test::sum(rho);
  const double dt = 0.05;  // Courant number well above 1: sub-steps required
  int substeps = 0;
  for (int step = 0; step < 40; ++step) substeps = std::max(substeps, advect_upwind_cells(g, vel.view(), dt, rho.data(), scratch.data()));
  EXPECT_GT(substeps, 1);
  EXPECT_NEAR(test::sum(rho) / total0, 1.0, 1e-6);
  float lo = 0;
  for (float x : rho) lo = std::min(lo, x);
  EXPECT_GE(lo, 0.0f);
}

INSTANTIATE_TEST_SUITE_P(Boundaries, UpwindConservation,
                         ::testing::Values(Case{2, false}, Case{2, true}, Case{3, false}, Case{3, true}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name = std::to_string(info.param.dim);
                           name += info.param.periodic ? "d_periodic" : "d_closed";
                           return name;
                         });

// Without sub-stepping, a Courant number > 1 makes the explicit update negative:
// this is what upwind_substeps guards against (and shows the test can fail).
TEST(Upwind, SingleStepBeyondCflGoesNegative) {
  const MacGrid g = make_grid(2, {16, 8, 1}, true);
  test::Velocity vel(g);
  std::fill(vel.u.begin(), vel.u.end(), 1.0f);
  std::vector<float> rho(g.cells(), 0.0f), scratch(g.cells());
  rho[g.cell(5, 3, 0)] = 1.0f;
  upwind_step(g, g.cell_layout(), vel.view(), 2.0 * g.h, rho.data(), scratch.data());
  EXPECT_LT(rho[g.cell(5, 3, 0)], 0.0f);
  EXPECT_EQ(upwind_substeps(g, vel.view(), 2.0 * g.h), 2);
}

// Uniform flow at Courant number exactly 1 shifts the field by one cell exactly.
TEST(Upwind, CourantOneShiftsByOneCell) {
  const MacGrid g = make_grid(2, {10, 4, 1}, true);
  test::Velocity vel(g);
  std::fill(vel.u.begin(), vel.u.end(), 1.0f);
  std::vector<float> rho(g.cells()), scratch(g.cells());
  for (int i = 0; i < 10; ++i) rho[g.cell(i, 2, 0)] = float(i + 1);
  advect_upwind_cells(g, vel.view(), g.h, rho.data(), scratch.data());
  for (int i = 0; i < 10; ++i) EXPECT_FLOAT_EQ(rho[g.cell(i, 2, 0)], float((i + 9) % 10 + 1));
}

TEST(SemiLagrangian, ConstantFieldStaysConstant) {
  for (bool periodic : {false, true})
    for (int dim : {2, 3}) {
      const MacGrid g = dim == 2 ? make_grid(2, {20, 16, 1}, periodic) : make_grid(3, {10, 8, 6}, periodic);
      const test::Velocity vel = test::random_velocity(g, 11, 2.0f);  // large, not div-free
      std::vector<float> q(g.cells(), 0.7f), out(g.cells());
      advect_semi_lagrangian_cells(g, vel.view(), 0.05, q.data(), out.data());
      for (float x : out) ASSERT_NEAR(x, 0.7f, 1e-6f);
    }
}

// A smooth blob in uniform periodic flow: its centroid moves by u t within a cell.
TEST(SemiLagrangian, BlobCentroidMovesWithTheFlow) {
  const MacGrid g = make_grid(2, {64, 32, 1}, true, 1.0 / 64);
  test::Velocity vel(g);
  const double ux = 0.3, uy = 0.1;
  std::fill(vel.u.begin(), vel.u.end(), float(ux));
  std::fill(vel.v.begin(), vel.v.end(), float(uy));
  std::vector<float> q(g.cells()), out(g.cells());
  const double cx = 0.2, cy = 0.15, s = 0.05;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 64; ++i) {
      const double x = (i + 0.5) * g.h - cx, y = (j + 0.5) * g.h - cy;
      q[g.cell(i, j, 0)] = float(std::exp(-(x * x + y * y) / (2 * s * s)));
    }
  const double dt = 0.02;
  const int steps = 50;
  for (int n = 0; n < steps; ++n) {
    advect_semi_lagrangian_cells(g, vel.view(), dt, q.data(), out.data());
    q.swap(out);
  }
  double m = 0, mx = 0, my = 0;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 64; ++i) {
      const double w = q[g.cell(i, j, 0)];
      m += w;
      mx += w * (i + 0.5) * g.h;
      my += w * (j + 0.5) * g.h;
    }
  const double t = dt * steps;
  EXPECT_NEAR(mx / m, cx + ux * t, g.h);
  EXPECT_NEAR(my / m, cy + uy * t, g.h);
}

// Velocity self-advection: uniform flow is a fixed point; closed walls stay zero.
TEST(SemiLagrangian, UniformVelocityIsSteadyAndWallsStayZero) {
  const MacGrid g = make_grid(3, {8, 6, 5}, true);
  test::Velocity vel(g), out(g);
  std::fill(vel.u.begin(), vel.u.end(), 0.4f);
  std::fill(vel.v.begin(), vel.v.end(), -0.2f);
  std::fill(vel.w.begin(), vel.w.end(), 0.1f);
  advect_semi_lagrangian_velocity(g, vel.view(), 0.1, out.mut());
  for (float x : out.u) ASSERT_NEAR(x, 0.4f, 1e-6f);
  for (float x : out.w) ASSERT_NEAR(x, 0.1f, 1e-6f);
  const MacGrid c = make_grid(2, {8, 6, 1}, false);
  test::Velocity r = test::random_velocity(c, 5), ro(c);
  advect_semi_lagrangian_velocity(c, r.view(), 0.1, ro.mut());
  for (int j = 0; j < 6; ++j) {
    EXPECT_EQ(ro.u[c.face_lo(0, 0, j, 0)], 0.0f);
    EXPECT_EQ(ro.u[c.face_lo(0, 8, j, 0)], 0.0f);
  }
}

// Upwind momentum advection conserves each periodic velocity component's sum.
TEST(Upwind, PeriodicMomentumIsConserved) {
  const MacGrid g = make_grid(2, {24, 20, 1}, true);
  const test::Velocity vel = test::random_divergence_free(g, 21, 0.5f);
  test::Velocity out = vel;
  std::vector<float> scratch(g.face_count(0));
  advect_upwind_velocity(g, vel.view(), 0.03, out.mut(), scratch.data());
  EXPECT_NEAR(test::sum(out.u), test::sum(vel.u), 1e-4);
  EXPECT_NEAR(test::sum(out.v), test::sum(vel.v), 1e-4);
  double diff = 0;
  for (size_t i = 0; i < vel.u.size(); ++i) diff = std::max(diff, double(std::abs(out.u[i] - vel.u[i])));
  EXPECT_GT(diff, 1e-3);  // it did move something
}

}  // namespace
}  // namespace pliant::smoke
