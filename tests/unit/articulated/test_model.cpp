#include <gtest/gtest.h>

#include "pliant/articulated/model.h"

namespace pliant::articulated {
namespace {

TEST(Model, GeomMassPropertiesAreAnalytic) {
  Geom sphere;
  sphere.type = GeomType::Sphere;
  sphere.size[0] = 0.1;
  double m;
  Mat3 i;
  geom_mass_properties(sphere, &m, &i);
  EXPECT_NEAR(m, 1000 * 4.0 / 3.0 * M_PI * 1e-3, 1e-12);
  EXPECT_NEAR(i(0, 0), 0.4 * m * 0.01, 1e-12);
  Geom box;
  box.type = GeomType::Box;
  box.size = Vec3(0.1, 0.2, 0.3);
  box.mass = 2;
  geom_mass_properties(box, &m, &i);
  EXPECT_EQ(m, 2);
  EXPECT_NEAR(i(2, 2), 2.0 / 12 * (0.04 + 0.16), 1e-12);
  // A capsule tends to a cylinder as the radius shrinks against the length.
  Geom cap;
  cap.type = GeomType::Capsule;
  cap.size = Vec3(1e-4, 0.5, 0);
  geom_mass_properties(cap, &m, &i);
  EXPECT_NEAR(i(0, 0) / (m * 1.0 / 12), 1.0, 1e-3);
}

TEST(Model, FinalizeAssignsAddressesAndCombinesGeoms) {
  Model m;
  m.bodies.resize(3);
  m.bodies[1].parent = 0;
  m.bodies[2].parent = 1;
  Joint ball;
  ball.type = JointType::Ball;
  ball.body = 2;
  Joint hinge;
  hinge.body = 1;
  m.joints = {ball, hinge};  // out of body order on purpose
  Geom a, b;
  a.body = b.body = 1;
  a.mass = b.mass = 1;
  a.pos = Vec3(1, 0, 0);
  b.pos = Vec3(-1, 0, 0);
  Geom c;
  c.body = 2;
  m.geoms = {a, b, c};
  model_finalize(m, {});
  EXPECT_EQ(m.nq, 5);
  EXPECT_EQ(m.nv, 4);
  EXPECT_EQ(m.joints[0].type, JointType::Hinge);
  EXPECT_EQ(m.joints[1].qadr, 1);
  EXPECT_EQ(m.qpos0[1], 1.0);  // identity quaternion
  EXPECT_EQ(m.bodies[1].mass, 2);
  EXPECT_NEAR(m.bodies[1].com.norm(), 0, 1e-15);
  EXPECT_NEAR(m.bodies[1].inertia(1, 1), 2 * (0.4 * 1.0 * 0.05 * 0.05) + 2, 1e-12);  // parallel axis
}

}  // namespace
}  // namespace pliant::articulated
