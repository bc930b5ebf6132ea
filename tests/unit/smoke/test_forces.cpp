#include <gtest/gtest.h>

#include <cmath>

#include "forces.h"
#include "smoke_test_util.h"

namespace pliant::smoke {
namespace {
using test::make_grid;

TEST(Forces, BuoyancyIsDensityTimesCoefficientAlongY) {
  const MacGrid g = make_grid(2, {6, 5, 1}, false);
  test::Velocity vel(g);
  std::vector<float> rho(g.cells(), 0.0f);
  rho[g.cell(2, 2, 0)] = 1.0f;
  add_buoyancy(g, 3.0, rho.data(), 0.1, vel.mut());
  // Faces below and above the dense cell get 0.1 * 3 * 0.5 each; nothing else moves.
  EXPECT_FLOAT_EQ(vel.v[g.face_lo(1, 2, 2, 0)], 0.15f);
  EXPECT_FLOAT_EQ(vel.v[g.face_hi(1, 2, 2, 0)], 0.15f);
  EXPECT_NEAR(test::sum(vel.v), 0.3, 1e-7);
  EXPECT_EQ(test::sum(vel.u), 0.0);
}

TEST(Forces, UniformAccelerationSkipsClosedWalls) {
  const MacGrid g = make_grid(3, {4, 3, 2}, false);
  test::Velocity vel(g);
  add_uniform_acceleration(g, {0.0, -9.81, 1.0}, 0.01, vel.mut());
  EXPECT_FLOAT_EQ(vel.v[g.face_lo(1, 1, 1, 1)], float(-0.0981));
  EXPECT_EQ(vel.v[g.face_lo(1, 1, 0, 1)], 0.0f);  // bottom wall
  EXPECT_EQ(vel.v[g.face_hi(1, 1, 2, 1)], 0.0f);  // top wall
  EXPECT_FLOAT_EQ(vel.w[g.face_lo(2, 1, 1, 1)], 0.01f);
  EXPECT_EQ(test::sum(vel.u), 0.0);
}

// The vortex pushes tangentially: counter-clockwise about z in 2D (positive curl),
// no radial component, zero outside the radius.
TEST(Forces, VortexIsTangentialAndLocal) {
  const MacGrid g = make_grid(2, {40, 40, 1}, true, 0.025);
  test::Velocity vel(g);
  ForceField f;
  f.type = ForceField::Vortex;
  f.center_m = {0.5, 0.5, 0};
  f.radius_m = 0.3;
  f.strength_per_s = 2.0;
  add_vortex(g, f, 0.1, vel.mut());
  // Face u at x = 0.5 (i = 20), y = (j + 0.5) h: counter-clockwise rotation moves
  // points below the centre towards +x.
  const float below = vel.u[g.face_lo(0, 20, 14, 0)];  // y = 0.3625, d = 0.1375
  const double d = 0.5 - (14 + 0.5) * g.h;
  EXPECT_NEAR(below, 0.1 * 4.0 * d * (1 - d / 0.3), 1e-6);
  EXPECT_LT(vel.u[g.face_lo(0, 20, 26, 0)], 0.0f);  // above: -x
  EXPECT_EQ(vel.u[g.face_lo(0, 20, 38, 0)], 0.0f);  // outside the radius
  // Circulation around a square loop of faces inside the radius is positive.
  double circ = 0;
  for (int i = 15; i < 25; ++i) circ += vel.u[g.face_lo(0, i, 15, 0)] - vel.u[g.face_lo(0, i, 25, 0)];
  for (int j = 15; j < 25; ++j) circ += vel.v[g.face_lo(1, 25, j, 0)] - vel.v[g.face_lo(1, 15, j, 0)];
  EXPECT_GT(circ, 0.0);
}

TEST(Forces, SourceAddsDensityAndSetsVelocityInsideOnly) {
  const MacGrid g = make_grid(2, {20, 20, 1}, false, 0.1);
  test::Velocity vel(g);
  std::vector<float> rho(g.cells(), 0.0f);
  Source s;
  s.shape.type = Shape::Box;
  s.shape.center_m = {1.0, 1.0, 0};
  s.shape.half_size_m = {0.3, 0.2, 0};
  s.density_per_s = 2.0;
  s.velocity_m_per_s = {0.0, 0.5, 0.0};
  apply_source(g, s, 0.25, rho.data(), vel.mut());
  // Cell centres 0.75..1.25 in x (6 cells: 0.75,0.85,...,1.25) and 0.85..1.15 in y (4 cells).
  int inside = 0;
  for (float x : rho) inside += x > 0;
  EXPECT_EQ(inside, 6 * 4);
  EXPECT_NEAR(test::sum(rho), 6 * 4 * 0.5, 1e-5);
  EXPECT_FLOAT_EQ(vel.v[g.face_lo(1, 10, 10, 0)], 0.5f);
  EXPECT_EQ(vel.v[g.face_lo(1, 2, 2, 0)], 0.0f);
}

TEST(Forces, SphereIsACircleIn2D) {
  Shape s;
  s.center_m = {0, 0, 5};
  s.radius_m = 1;
  EXPECT_TRUE(shape_contains(s, 2, {0.6, 0.6, 0}));
  EXPECT_FALSE(shape_contains(s, 3, {0.6, 0.6, 0}));
  EXPECT_FALSE(shape_contains(s, 2, {0.8, 0.8, 0}));
}

}  // namespace
}  // namespace pliant::smoke
