#include <gtest/gtest.h>

#include <cmath>

#include "liquid_test_util.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {
namespace {

double mean_height(const LiquidState& s) {
  double y = 0;
  for (size_t p = 0; p < s.count(); ++p) y += s.x[3 * p + 1];
  return y / double(s.count());
}

double max_speed(const LiquidState& s) {
  double v = 0;
  for (size_t p = 0; p < s.count(); ++p)
    v = std::max(v, double(std::hypot(s.v[3 * p], s.v[3 * p + 1], s.v[3 * p + 2])));
  return v;
}

TEST(FlipStep, LiquidAtRestStaysAtRest) {
  const LiquidModel m = test::still_container_2d();
  LiquidState s = liquid_init(m);
  ASSERT_GT(s.count(), 300u);
  const size_t n0 = s.count();
  // Volume of a flat column: floor area x height, height = 2 (mean y - floor y).
  const double floor_y = m.source.pose.position_m[1];
  const double v0 = 2 * (mean_height(s) - floor_y);
  for (int f = 0; f < 50; ++f) liquid_step(m, s);  // 1 s
  EXPECT_LT(max_speed(s), 0.03);  // m/s; a drop from the rim would reach 0.5
  const double v1 = 2 * (mean_height(s) - floor_y);
  EXPECT_NEAR(v1 / v0, 1.0, 0.01);
  EXPECT_EQ(s.count(), n0);  // a full column needs no reseeding
  const auto fr = liquid_fractions(m, s);
  EXPECT_DOUBLE_EQ(fr[2], 1.0);
}

TEST(FlipStep, FreeFlightFollowsTheParabola) {
  LiquidModel m;
  m.dim = 2;
  m.domain_min_m = {0, 0, 0};
  m.domain_max_m = {2, 2, 0};
  m.cell_size_m = 0.05;
  m.n = {40, 40, 1};
  m.has_source = m.has_target = false;
  LiquidState s;
  s.x = {0.3f, 0.5f, 0.f};
  s.v = {1.0f, 2.0f, 0.f};
  const double dt = 0.002, T = 0.4, g = 9.81;
  for (int i = 0; i < int(T / dt + 0.5); ++i) liquid_substep(m, s, dt);
  const double x = 0.3 + 1.0 * T, y = 0.5 + 2.0 * T - 0.5 * g * T * T;
  // Symplectic Euler in time: |error| <= g dt T / 2 (+ float rounding).
  const double bound = 0.5 * g * dt * T + 1e-4;
  EXPECT_NEAR(s.x[0], x, 1e-4);
  EXPECT_NEAR(s.x[1], y, bound);
  EXPECT_NEAR(s.v[1], 2.0 - g * T, 1e-3);
  EXPECT_GT(std::abs(s.x[1] - (0.5 + 2.0 * T)), 0.5);  // gravity did act
}

TEST(FlipStep, DamBreakKeepsParticlesInsideAndConservesCount) {
  LiquidModel m;
  m.dim = 2;
  m.domain_min_m = {0, 0, 0};
  m.domain_max_m = {0.5, 0.5, 0};
  m.cell_size_m = 0.0125;
  m.n = {40, 40, 1};
  m.has_source = m.has_target = false;
  m.reseed = false;
  m.liquid_boxes.push_back({{0, 0, 0}, {0.2, 0.25, 0}});
  LiquidState s = liquid_init(m);
  const size_t n0 = s.count();
  const double y0 = mean_height(s);
  for (int f = 0; f < 25; ++f) liquid_step(m, s);
  EXPECT_EQ(s.count(), n0);
  double xmax = 0;
  for (size_t p = 0; p < s.count(); ++p) {
    ASSERT_GE(s.x[3 * p], 0.f);
    ASSERT_LE(s.x[3 * p], 0.5f);
    ASSERT_GE(s.x[3 * p + 1], 0.f);
    xmax = std::max(xmax, double(s.x[3 * p]));
  }
  EXPECT_GT(xmax, 0.45);          // the front reached the far wall within 0.5 s
  EXPECT_LT(mean_height(s), y0);  // potential energy released
}

TEST(FlipStep, ViscousLiquidFollowsTiltedContainer) {
  // A container that moves sideways carries its liquid along (wall velocity BC).
  LiquidModel m = test::still_container_2d();
  m.viscosity_pa_s = 0.5;
  m.source_path.keys = {{0.0, m.source.pose}, {0.4, m.source.pose}};
  m.source_path.keys[1].pose.position_m[0] += 0.03;
  LiquidState s = liquid_init(m);
  for (int f = 0; f < 25; ++f) liquid_step(m, s);
  const auto fr = liquid_fractions(m, s);
  EXPECT_GT(fr[2], 0.97);
  double mx = 0;
  for (size_t p = 0; p < s.count(); ++p) mx += s.x[3 * p];
  EXPECT_NEAR(mx / s.count(), 0.03, 0.01);
}

}  // namespace
}  // namespace pliant::liquid
