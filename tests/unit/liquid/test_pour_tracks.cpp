#include "pliant/liquid/pour_tracks.h"

#include <gtest/gtest.h>

#include <cmath>

#include "liquid_test_util.h"

namespace pliant::liquid {
namespace {

// One particle in free flight: it leaves the source at t = dt and follows
// x = x0 + vx t, y = y0 + vy t - g t^2 / 2 (frames every dt).
constexpr double x0 = 0.0, y0 = 0.2, vx = 1.0, vy = 0.5, g = 9.81, dt = 0.01;

LiquidState flight_start() {
  LiquidState s;
  s.x = {0.0f, 0.05f, 0.f};  // inside the source cavity (floor at y = 0.03)
  s.v = {0, 0, 0};
  return s;
}

void record_flight(PourTracks& tracks) {
  LiquidState s = flight_start();
  for (int f = 1; f <= 40; ++f) {
    const double t = f * dt;
    s.time_s = t;
    s.x = {float(x0 + vx * t), float(y0 + vy * t - 0.5 * g * t * t), 0.f};
    tracks.record(s);
  }
}

// The still source and a target (rim at y = 0.05, opening centred at x = 0.3).
LiquidModel model_with_target() {
  LiquidModel m = test::still_container_2d();
  m.has_target = true;
  m.target.shape.radius_m = 0.05, m.target.shape.height_m = 0.05;
  m.target.pose.position_m = {0.3, 0, 0};
  return m;
}

// Analytic time at which the flight crosses y = 0.05 (the rim) on its way down.
double rim_crossing_time() {
  const double a = -0.5 * g, b = vy, c = y0 - 0.05;
  return (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

// One particle leaves the source and flies a known parabola: the recorded
// landing point and C_OBJ (Eq. 2.6) match the analytic crossing of the rim.
TEST(PourTracks, ParabolaCrossingAndObjective) {
  LiquidModel m = model_with_target();
  PourTracks tracks(m, flight_start());
  record_flight(tracks);
  const auto& tr = tracks.tracks()[0];
  ASSERT_TRUE(tr.landed);
  const double tc = rim_crossing_time();
  const double xc = x0 + vx * tc;
  EXPECT_NEAR(tr.landing[0], xc, 0.01);  // linear between frames
  int useful = 0;
  const double cobj = tracks.objective(1e-4, &useful);
  EXPECT_EQ(useful, 1);
  EXPECT_NEAR(cobj, std::abs(xc - 0.3), 1e-4);  // the fitted parabola is exact
}

// A moving (FOLLOW) target: the landing offset and C_OBJ are measured against
// where the opening is when the particle crosses the rim, not where it started.
TEST(PourTracks, MovingTargetOffsetAtLandingTime) {
  LiquidModel m = model_with_target();
  m.target_velocity_mps = {-0.2, 0, 0};
  PourTracks tracks(m, flight_start());
  record_flight(tracks);
  const auto& tr = tracks.tracks()[0];
  ASSERT_TRUE(tr.landed);
  const double tc = rim_crossing_time();
  const double xc = x0 + vx * tc, centre = 0.3 - 0.2 * tc;
  EXPECT_NEAR(tr.landing_time, tc, 0.005);
  EXPECT_NEAR(tr.landing_offset[0], xc - centre, 0.01);
  EXPECT_NEAR(tracks.opening_centre(tc)[0], centre, 1e-9);
  int useful = 0;
  EXPECT_NEAR(tracks.objective(1e-4, &useful), std::abs(xc - centre), 1e-4);
  EXPECT_EQ(useful, 1);
}

}  // namespace
}  // namespace pliant::liquid
