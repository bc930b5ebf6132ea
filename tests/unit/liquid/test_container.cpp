#include <gtest/gtest.h>

#include <cmath>

#include "pliant/liquid/liquid.h"

namespace pliant::liquid {
namespace {

TEST(Container, WallSdfSigns) {
  for (auto type : {ContainerShape::Cylinder, ContainerShape::Oval, ContainerShape::Box, ContainerShape::Cup,
                    ContainerShape::Bottle}) {
    ContainerShape c;
    c.type = type;
    c.radius_m = 0.05, c.depth_m = 0.04, c.height_m = 0.12, c.wall_m = 0.01;
    c.neck_radius_m = 0.02, c.body_height_m = 0.08;
    for (int dim : {2, 3}) {
      EXPECT_GT(c.wall_sdf({0, 0.02, 0}, dim), 0) << type;           // cavity
      EXPECT_LT(c.wall_sdf({0, -0.005, 0}, dim), 0) << type;         // floor
      EXPECT_NEAR(c.wall_sdf({0, -0.01, 0}, dim), 0, 1e-12) << type; // floor's underside
      EXPECT_GT(c.wall_sdf({0, 0.3, 0}, dim), 0) << type;            // above the opening
      EXPECT_TRUE(c.in_cavity({0, 0.02, 0}, dim));
      EXPECT_FALSE(c.in_cavity({0, 0.2, 0}, dim));
      EXPECT_TRUE(c.in_extended_cavity({0, 0.2, 0}, dim));
    }
    EXPECT_LT(c.wall_sdf({-0.055, 0.05, 0}, 3), 0) << type;          // side wall (-x: no handle)
  }
}

TEST(Container, CavityVolumeOfCylinder) {
  ContainerShape c;
  c.radius_m = 0.05, c.height_m = 0.1;
  EXPECT_NEAR(c.cavity_volume(3), 3.14159265358979 * 0.05 * 0.05 * 0.1, 1e-12);
  EXPECT_NEAR(c.cavity_volume(2), 2 * 0.05 * 0.1, 1e-12);
}

TEST(Container, PoseRoundTripAndPouringDirection) {
  Pose p;
  p.position_m = {0.1, 0.2, 0.3};
  p.tilt_rad = 0.7;
  const Vec3 x{0.15, -0.05, 0.31};
  const Vec3 y = p.to_world(p.to_local(x));
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(x[a], y[a], 1e-12);
  // Positive tilt moves the opening toward +x.
  EXPECT_GT(p.to_world({0, 1, 0})[0], p.position_m[0]);
  const auto q = p.as_array();
  EXPECT_NEAR(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6], 1.0, 1e-6);
}

TEST(Container, TrajectoryInterpolatesKeysAndVelocityIsItsDerivative) {
  Trajectory t;
  for (int k = 0; k < 4; ++k) {
    KeyPose kp;
    kp.time_s = 0.5 * k;
    kp.pose.position_m = {0.1 * k, 0.05 * k * k, 0};
    kp.pose.tilt_rad = 0.3 * k;
    t.keys.push_back(kp);
  }
  for (const KeyPose& k : t.keys) {
    EXPECT_NEAR(t.at(k.time_s).position_m[0], k.pose.position_m[0], 1e-12);
    EXPECT_NEAR(t.at(k.time_s).tilt_rad, k.pose.tilt_rad, 1e-12);
  }
  for (double s : {0.1, 0.6, 1.2}) {
    Vec3 v;
    double rate;
    t.velocity(s, &v, &rate);
    const double e = 1e-6;
    EXPECT_NEAR(v[1], (t.at(s + e).position_m[1] - t.at(s - e).position_m[1]) / (2 * e), 1e-5);
    EXPECT_NEAR(rate, (t.at(s + e).tilt_rad - t.at(s - e).tilt_rad) / (2 * e), 1e-5);
  }
  Vec3 v0;
  double r0;
  t.velocity(0.0, &v0, &r0);
  EXPECT_EQ(r0, 0.0);  // a pour starts at rest
}

}  // namespace
}  // namespace pliant::liquid
