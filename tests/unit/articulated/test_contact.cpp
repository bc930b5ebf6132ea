// Contact: body points against world obstacles (plane, box), sliding and creeping boxes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"
#include "pair_fixture.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// A 1 kg box (half size 0.1) with a free joint on a plane tilted by `slope` about y.
Model box_on_plane(double slope) {
  const Quat q(Eigen::AngleAxisd(slope, Vec3::UnitY()));
  const std::string quat = std::to_string(q.w()) + " " + std::to_string(q.x()) + " " +
                           std::to_string(q.y()) + " " + std::to_string(q.z());
  const std::string xml = "<mujoco><worldbody><geom type=\"plane\" quat=\"" + quat +
                          "\"/><body name=\"box\" pos=\"0 0 0.1\"><freejoint/>"
                          "<geom type=\"box\" size=\"0.1 0.1 0.1\" mass=\"1\"/></body></worldbody></mujoco>";
  return model_from_mjcf(xml, "box.xml");
}

State resting_box(const Model& m, double slope, double stiffness) {
  const Quat q(Eigen::AngleAxisd(slope, Vec3::UnitY()));
  const Vec3 n = q * Vec3::UnitZ();
  const double depth = 1.0 * 9.81 * std::cos(slope) / (4 * stiffness);
  State s = state_init(m);
  s.qpos.head<3>() = n * (0.1 - depth);
  s.qpos.segment<4>(3) << q.w(), q.x(), q.y(), q.z();
  return s;
}

// find_contacts skips a geom's points for an obstacle its bounding sphere cannot
// reach: the contacts must be exactly those of testing every point against every
// obstacle (the reference below), for every geom type, margins included, with many
// geoms near and far from a plane, a box, a sphere and a capsule.
TEST(Contact, BoundingSphereCullKeepsEveryContactOfTheFullTest) {
  std::ostringstream x;
  x << "<mujoco><worldbody><geom type=\"plane\"/><geom type=\"box\" size=\"0.3 0.2 0.1\" pos=\"1 0 0.1\" euler=\"0 0 20\"/>"
       "<geom type=\"sphere\" size=\"0.2\" pos=\"-1 0 0.2\"/><geom type=\"capsule\" size=\"0.05 0.5\" pos=\"0 1 0.05\" euler=\"90 0 0\"/>";
  const char* shapes[] = {R"(type="sphere" size="0.06")", R"(type="capsule" size="0.04 0.1")",
                          R"(type="box" size="0.05 0.08 0.03")", R"(type="cylinder" size="0.05 0.07")",
                          R"(type="ellipsoid" size="0.04 0.07 0.05")"};
  for (int b = 0; b < 60; ++b) {
    const double px = -1.4 + 0.05 * b, py = 0.9 * std::sin(1.3 * b), pz = 0.02 + 0.25 * (0.5 + 0.5 * std::cos(0.7 * b));
    x << "<body pos=\"" << px << " " << py << " " << pz << "\" euler=\"" << 37 * b << " " << 23 * b << " " << 11 * b
      << "\"><freejoint/><geom " << shapes[b % 5] << (b % 4 == 0 ? " margin=\"0.02\"" : "") << "/></body>";
  }
  x << "</worldbody></mujoco>";
  const Model m = model_from_mjcf(x.str(), "cull.xml");
  Kinematics k;
  kinematics(m, state_init(m).qpos, &k);
  const auto pts = contact_points(m);
  const auto obs = contact_obstacles(m);
  std::vector<Contact> found;
  find_contacts(m, k, pts, obs, {}, {}, &found);
  std::vector<Contact> full;  // every point against every obstacle
  for (size_t i = 0; i < pts.size(); ++i)
    for (size_t o = 0; o < obs.size(); ++o) {
      if (!point_meets(m, pts[i], obs[o])) continue;  // cylinders' / ellipsoids' plane points
      const Vec3 c = k.xpos[pts[i].body] + k.xmat[pts[i].body] * contact_point_local(m, pts[i], k.xmat[pts[i].body]);
      Vec3 n;
      const double reach = pts[i].radius + point_contact_mix(m, pts[i], obs[o]).margin;
      const double d = obstacle_distance(m.geoms[obs[o]], nullptr, c, &n) - reach;
      if (d < 0) full.push_back({static_cast<int>(i * obs.size() + o), pts[i].body, c - reach * n, n, -d, Vec3::Zero(), ContactMix{}});
    }
  ASSERT_EQ(found.size(), full.size());
  EXPECT_GT(found.size(), 30u);
  for (size_t i = 0; i < full.size(); ++i) {
    EXPECT_EQ(found[i].slot, full[i].slot) << i;
    EXPECT_EQ(found[i].depth, full[i].depth) << i;
    EXPECT_EQ(found[i].point, full[i].point) << i;
  }
}

TEST(Contact, ObstacleDistances) {
  Geom box;
  box.type = GeomType::Box;
  box.size = Vec3(1, 2, 3);
  Vec3 n;
  EXPECT_NEAR(obstacle_distance(box, Vec3(2, 0, 0), &n), 1.0, 1e-12);
  EXPECT_NEAR(n.x(), 1.0, 1e-12);
  EXPECT_NEAR(obstacle_distance(box, Vec3(0, 0, 2.5), &n), -0.5, 1e-12);
  EXPECT_NEAR(n.z(), 1.0, 1e-12);
  EXPECT_NEAR(obstacle_distance(box, Vec3(2, 3, 0), &n), std::sqrt(2.0), 1e-12);
  Geom sphere;
  sphere.type = GeomType::Sphere;
  sphere.size[0] = 0.5;
  EXPECT_NEAR(obstacle_distance(sphere, Vec3(0, 2, 0), &n), 1.5, 1e-12);
  EXPECT_NEAR(n.y(), 1.0, 1e-12);
}

TEST(Contact, BoxCornersAreContactPoints) {
  const Model m = box_on_plane(0);
  EXPECT_EQ(contact_points(m).size(), 8u);
  EXPECT_EQ(contact_obstacles(m).size(), 1u);
}

TEST(Contact, SlidingBoxStopsAtAnalyticDistance) {
  // v0 = 2 m/s, mu = 0.5: d = v0^2 / (2 mu g) = 0.4077 m.
  const Model m = box_on_plane(0);
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.5;
  State s = resting_box(m, 0, o.contact.stiffness);
  s.qvel[0] = 2.0;
  SimWorkspace ws;
  const double x0 = s.qpos[0];
  for (int i = 0; i < 150; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  const double analytic = 4.0 / (2 * 0.5 * 9.81);
  EXPECT_NEAR((s.qpos[0] - x0) / analytic, 1.0, 0.02);
  EXPECT_LT(std::abs(s.qvel[0]), 1e-3);
}

TEST(Contact, BoxBelowFrictionAngleCreepsLessThanAMillimetre) {
  const double slope = 20 * M_PI / 180;  // tan 20 deg = 0.36 < mu = 0.5
  const Model m = box_on_plane(slope);
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.5;
  State s = resting_box(m, slope, o.contact.stiffness);
  SimWorkspace ws;
  const Vec3 p0 = s.qpos.head<3>();
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  EXPECT_LT((s.qpos.head<3>() - p0).norm(), 1e-3);
}

TEST(Contact, BoxAboveFrictionAngleSlides) {
  const double slope = 35 * M_PI / 180;  // tan 35 deg = 0.70 > mu = 0.5
  const Model m = box_on_plane(slope);
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.5;
  State s = resting_box(m, slope, o.contact.stiffness);
  SimWorkspace ws;
  const Vec3 p0 = s.qpos.head<3>();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  // s = 1/2 g (sin a - mu cos a) t^2 along the slope after 1 s.
  const double expect = 0.5 * 9.81 * (std::sin(slope) - 0.5 * std::cos(slope));
  EXPECT_NEAR((s.qpos.head<3>() - p0).norm() / expect, 1.0, 0.05);
}

}  // namespace
}  // namespace pliant::articulated
