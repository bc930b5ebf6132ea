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

TEST(Contact, MeshObstacleDistanceEqualsTheBoxOnFaces) {
  // A static box mesh against the analytic box: same signed distance and normal for
  // points outside (nearest a face, edge or corner) and inside near a face.
  const std::string obj = test::write_box_obj("pliant_mesh_obstacle", 0.5, 0.4, 0.3);
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"b\" file=\"" + obj +
                                      "\"/></asset><worldbody><geom type=\"mesh\" mesh=\"b\" euler=\"10 20 30\"/>"
                                      "<geom type=\"box\" size=\"0.5 0.4 0.3\" euler=\"10 20 30\"/></worldbody></mujoco>",
                                  "m.xml");
  std::filesystem::remove(obj);
  for (const Vec3& x : {Vec3(0.9, 0.1, 0), Vec3(0.7, 0.6, 0.5), Vec3(-0.1, 0.05, 0.28), Vec3(0, -0.35, 0.1)}) {
    Vec3 nm, nb;
    const Vec3 xw = m.geoms[1].quat * x;
    // (assimp reads vertices in single precision)
    EXPECT_NEAR(obstacle_distance(m.geoms[0], xw, &nm), obstacle_distance(m.geoms[1], xw, &nb), 1e-6) << x.transpose();
    EXPECT_NEAR((nm - nb).norm(), 0, 1e-6) << x.transpose();
  }
}

TEST(Contact, SphereRestsOnAStaticMeshAndAMeshBoxRestsOnAPlane) {
  // Penalty equilibrium depth m g / k for both: a sphere dropped on a mesh block, and a
  // mesh cube (8 vertex contact points) on the floor; PBAD3, 1 s.
  const std::string obj = test::write_box_obj("pliant_mesh_rest", 0.1, 0.1, 0.1);
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"cube\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"plane\"/><geom type=\"mesh\" mesh=\"cube\" pos=\"1 0 0.1\"/>"
      "<body pos=\"1 0 0.35\"><joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"sphere\" size=\"0.05\" mass=\"1\"/></body>"
      "<body pos=\"0 0 0.15\"><joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"cube\" mass=\"2\"/></body>"
      "</worldbody></mujoco>",
      "m.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  State s = state_init(m);
  SimWorkspace ws;
  for (int i = 0; i < 150; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  const double k = o.contact.stiffness;
  // The cube's bottom face carries its 4 corners plus edge and face samples.
  int bottom = 0;
  for (const ContactPoint& p : contact_points(m))
    if (p.body == 2 && std::abs(p.local.z() + 0.1) < 1e-6) ++bottom;
  EXPECT_GT(bottom, 4);
  EXPECT_NEAR(0.35 + s.qpos[0], 0.25 - 1 * 9.81 / k, 2e-4);           // sphere on the block top (z 0.2)
  EXPECT_NEAR(0.15 + s.qpos[1], 0.1 - 2 * 9.81 / (bottom * k), 2e-4);  // cube on the floor
}

TEST(Contact, MeshSamplesCoverEdgesAndFacesAtTheirSpacing) {
  const std::string obj = test::write_box_obj("pliant_mesh_samples", 0.3, 0.1, 0.02);
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"t\" file=\"" + obj +
                                      "\"/></asset><worldbody><body><freejoint/><geom type=\"mesh\" mesh=\"t\"/>"
                                      "</body></worldbody></mujoco>",
                                  "m.xml");
  std::filesystem::remove(obj);
  const std::vector<Vec3> pts = mesh_contact_samples(*m.geoms[0].mesh);
  const double spacing = 0.6 / kMeshSamplesPerExtent;
  // Every point of the surface has a sample within one spacing (checked on a fine
  // grid of the top face), and every sample lies on the surface.
  for (double x = -0.3; x <= 0.3; x += 0.01)
    for (double y = -0.1; y <= 0.1; y += 0.01) {
      double best = 1e9;
      for (const Vec3& p : pts) best = std::min(best, (p - Vec3(x, y, 0.02)).norm());
      EXPECT_LT(best, spacing) << x << " " << y;
    }
  for (const Vec3& p : pts) {
    const Vec3 q = p.cwiseAbs() - Vec3(0.3, 0.1, 0.02);
    EXPECT_NEAR(q.maxCoeff(), 0, 1e-6);
  }
  // No duplicates (shared edges sampled once).
  for (size_t i = 0; i < pts.size(); ++i)
    for (size_t j = i + 1; j < pts.size(); ++j) ASSERT_GT((pts[i] - pts[j]).norm(), 1e-9);
}

TEST(Contact, MeshTileIsHeldBySphereAndBoxCorner) {
  // A 20 x 20 x 2 cm mesh tile on a vertical slide, dropped onto a small sphere
  // (r 3 cm) and onto a box standing on its corner, both far from the tile's
  // vertices: with vertex contacts only, both tiles fell through. Held at the
  // penalty depth m g / k = 4.9e-5 m: the box's corners and the sphere are tested
  // against the mesh's faces (mesh_feature_contacts), the mesh's samples against them.
  const std::string obj = test::write_box_obj("pliant_mesh_tile", 0.1, 0.1, 0.01);
  const Quat corner_up = Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3::UnitZ());
  std::ostringstream box_quat;
  box_quat.precision(17);
  box_quat << corner_up.w() << " " << corner_up.x() << " " << corner_up.y() << " " << corner_up.z();
  const double tip = 0.04 * std::sqrt(3.0);
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"tile\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"sphere\" size=\"0.03\"/><geom type=\"box\" size=\"0.04 0.04 0.04\" pos=\"1 0 0\" quat=\"" +
          box_quat.str() + "\"/>"
      "<body pos=\"0 0 0.08\"><joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"tile\" mass=\"0.5\"/></body>"
      "<body pos=\"1 0 0.12\"><joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"tile\" mass=\"0.5\"/></body>"
      "</worldbody></mujoco>",
      "m.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  State s = state_init(m);
  SimWorkspace ws;
  for (int i = 0; i < 60; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  const double bottom_sphere = 0.08 + s.qpos[0] - 0.01, bottom_box = 0.12 + s.qpos[1] - 0.01;
  EXPECT_GT(bottom_sphere, 0.03 - 1e-4);
  EXPECT_LT(bottom_sphere, 0.03);
  EXPECT_GT(bottom_box, tip - 1e-4);
  EXPECT_LT(bottom_box, tip);
  EXPECT_NEAR(s.qvel[0], 0, 0.05);
  EXPECT_NEAR(s.qvel[1], 0, 0.05);
  std::printf("tile bottom below the sphere top %.3e m, below the box tip %.3e m\n", 0.03 - bottom_sphere,
              tip - bottom_box);
}

TEST(Contact, MeshFeatureContactGradientMatchesFiniteDifferences) {
  // A tiled mesh on slide z + two hinges pressed 5 mm onto an upturned box corner and a
  // sphere (feature contacts and samples both active): PBAD's gradient against central
  // differences of its energy.
  const std::string obj = test::write_box_obj("pliant_mesh_grad", 0.1, 0.1, 0.01);
  const Quat up = Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3::UnitZ());
  std::ostringstream bq;
  bq.precision(17);
  bq << up.w() << " " << up.x() << " " << up.y() << " " << up.z();
  const double tip = 0.04 * std::sqrt(3.0);
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"tile\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"box\" size=\"0.04 0.04 0.04\" pos=\"0.03 0.02 0\" quat=\"" + bq.str() + "\"/>"
      "<geom type=\"sphere\" size=\"0.02\" pos=\"-0.05 -0.04 " + std::to_string(tip - 0.02) + "\"/>"
      "<body pos=\"0 0 " + std::to_string(tip + 0.01 - 0.005) + "\"><joint type=\"slide\" axis=\"0 0 1\"/>"
      "<joint axis=\"1 0 0\"/><joint axis=\"0 1 0\"/><geom type=\"mesh\" mesh=\"tile\" mass=\"0.5\"/></body>"
      "</worldbody></mujoco>",
      "m.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  State s = state_init(m);
  SimWorkspace ws;
  sim_prepare(m, ws);
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  Kinematics k;
  kinematics(m, s.qpos, &k);
  std::vector<Contact> features;
  mesh_feature_contacts(m, k, contact_obstacles(m), {}, moving_mesh_trees(m), &features);
  ASSERT_EQ(features.size(), 2u);  // the corner and the sphere
  for (const Contact& c : features) EXPECT_NEAR(c.depth, 0.005, 1e-6);
  const VecX q = s.qpos + Vec3(0.001, 0.02, -0.03);
  pbad_evaluate(m, o, s, p, q, ws);
  const VecX g = ws.grad;
  const double eps = 1e-7;
  for (int i = 0; i < m.nv; ++i) {
    VecX qp = q, qm = q;
    qp[i] += eps;
    qm[i] -= eps;
    const double fd = (pbad_evaluate(m, o, s, p, qp, ws) - pbad_evaluate(m, o, s, p, qm, ws)) / (2 * eps);
    EXPECT_NEAR(g[i], fd, 1e-5 * (1 + g.norm())) << i;
  }
}

TEST(Contact, MeshSlidingOnABoxCornerStopsAtTheCoulombDistance) {
  // A mesh tile on two slides (x, z) resting on an upturned box corner, pushed at
  // 0.2 m/s: Coulomb friction at the corner's feature contact stops it after
  // v^2 / (2 mu g) = 4.08 mm; frictionless it keeps going.
  const std::string obj = test::write_box_obj("pliant_mesh_slide", 0.1, 0.1, 0.01);
  const Quat up = Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3::UnitZ());
  std::ostringstream bq;
  bq.precision(17);
  bq << up.w() << " " << up.x() << " " << up.y() << " " << up.z();
  const double tip = 0.04 * std::sqrt(3.0), k = 1e5, mass = 0.5;
  std::ostringstream z;
  z.precision(17);
  z << tip + 0.01 - mass * 9.81 / k;
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"tile\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"box\" size=\"0.04 0.04 0.04\" quat=\"" + bq.str() + "\"/>"
      "<body pos=\"0 0 " + z.str() + "\"><joint type=\"slide\" axis=\"1 0 0\"/><joint type=\"slide\" axis=\"0 0 1\"/>"
      "<geom type=\"mesh\" mesh=\"tile\" mass=\"0.5\"/></body></worldbody></mujoco>",
      "m.xml");
  std::filesystem::remove(obj);
  for (const FrictionModel f : {FrictionModel::Coulomb, FrictionModel::None}) {
    SimOptions o;
    o.dt = 0.005;
    o.contact.stiffness = k;
    o.contact.friction = f;
    o.contact.mu = 0.5;
    State s = state_init(m);
    s.qvel[0] = 0.2;
    SimWorkspace ws;
    for (int i = 0; i < 80; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
    std::printf("tile on a corner, %s: %.5f m after 0.4 s\n", f == FrictionModel::Coulomb ? "coulomb" : "none", s.qpos[0]);
    if (f == FrictionModel::Coulomb) {
      EXPECT_NEAR(s.qpos[0], 0.04 / (2 * 0.5 * 9.81), 0.1 * 0.00408);
      EXPECT_NEAR(s.qvel[0], 0, 1e-3);
    } else {
      EXPECT_NEAR(s.qpos[0], 0.2 * 0.4, 0.002);
    }
    EXPECT_NEAR(s.qpos[1], 0, 1e-4);  // still on the corner
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

// ---- Body-body contact ----

using namespace pair_test;

TEST(Contact, BodyPairGradientAndBlocksMatchFiniteDifferences) {
  const std::string sphere = "<geom type=\"sphere\" size=\"0.05\"/>";
  const std::string capsule = "<geom type=\"capsule\" size=\"0.03 0.08\" euler=\"20 35 10\"/>";
  const std::string capsule2 = "<geom type=\"capsule\" size=\"0.025 0.07\" euler=\"80 -10 40\"/>";
  const std::string box = "<geom type=\"box\" size=\"0.1 0.07 0.05\" euler=\"5 -8 12\"/>";
  const std::string cube = "<geom type=\"box\" size=\"0.04 0.04 0.04\" euler=\"30 40 20\"/>";
  EXPECT_EQ(expect_pair_derivatives(two_bodies("0 0 0", sphere, "0.05 0.04 0.05", "<geom type=\"sphere\" size=\"0.04\"/>")), 1u);
  EXPECT_EQ(expect_pair_derivatives(two_bodies("0 0 0", capsule, "0.06 -0.03 0.02", sphere)), 1u);
  // Axes crossing, closest points interior, one end sphere of capsule2 in reach too.
  EXPECT_EQ(expect_pair_derivatives(two_bodies("0 0 0", capsule, "0.03 0.04 0.01", capsule2)), 2u);
  EXPECT_EQ(expect_pair_derivatives(two_bodies("0 0 0", box, "0.02 0.01 0.09", sphere)), 1u);
  // Capsule end sphere dipping into the box's top face (corners far from the capsule).
  EXPECT_GE(expect_pair_derivatives(two_bodies("0 0 0", box, "0.01 0 0.12", capsule)), 1u);
  // A tilted cube's lowest corner in the box's top face.
  EXPECT_GE(expect_pair_derivatives(two_bodies("0 0 0", box, "0.01 0.005 0.11", cube)), 1u);
}

// Box edge across box edge (two boxes on their edges, crosswise): no corner of either
// is inside the other, the edge-edge contact pushes the upper box up.
TEST(Contact, EdgeAcrossEdgeGradientMatchesFiniteDifferences) {
  const std::string ridge_x = "<geom type=\"box\" size=\"0.1 0.03 0.03\" euler=\"45 2 3\"/>";
  const std::string ridge_y = "<geom type=\"box\" size=\"0.03 0.1 0.03\" euler=\"-4 43 1\"/>";
  const Model boxes = two_bodies("0 0 0", ridge_x, "0.004 -0.003 0.083", ridge_y);
  const std::vector<PairContact> c = pair_contacts_at(boxes, state_init(boxes).qpos);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_GT(c[0].normal.z(), 0.95);
  EXPECT_EQ(expect_pair_derivatives(boxes), 1u);
}

// The upper box rests on the fixed lower one's edge (symmetric, so it balances) at the
// penalty depth m g / k below the touching height 2 h; without the edge-edge contact
// it falls through.
TEST(Contact, CrosswiseBoxesOnEdgesRestAtThePenaltyDepth) {
  const double h = 0.03 * std::sqrt(2.0);  // a 45-degree box's edge height above its centre
  const Model m = model_from_mjcf(
      "<mujoco><worldbody><body name=\"a\"><geom type=\"box\" size=\"0.1 0.03 0.03\" euler=\"45 0 0\"/></body>"
      "<body name=\"b\" pos=\"0 0 " + std::to_string(2 * h + 0.001) + "\"><freejoint/>"
      "<geom type=\"box\" size=\"0.03 0.1 0.03\" euler=\"0 45 0\" mass=\"0.5\"/></body></worldbody></mujoco>",
      "crosswise.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  for (int i = 0; i < 60; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  EXPECT_LT(s.qvel.lpNorm<Eigen::Infinity>(), 1e-2);
  EXPECT_EQ(pair_contacts_at(m, s.qpos).size(), 1u);
  const double ratio = (2 * h - s.qpos[2]) / (m.bodies[2].mass * 9.81 / o.contact.stiffness);
  EXPECT_NEAR(ratio, 1.0, 0.05);
  std::printf("crosswise boxes: resting depth / (m g / k) = %.4f\n", ratio);
}

// Three bodies dropped on a free box that stands on the ground: each comes to rest at
// the penalty's static depth m g / (n k) (n contacts sharing its weight).
TEST(Contact, BodiesDroppedOnABoxRestAtThePenaltyDepth) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody><geom type="plane"/>
    <body name="base" pos="0 0 0.05"><freejoint/><geom type="box" size="0.3 0.3 0.05" mass="3"/></body>
    <body name="ball" pos="-0.15 0 0.16"><freejoint/><geom type="sphere" size="0.05" mass="0.5"/></body>
    <body name="cube" pos="0 0.1 0.16"><freejoint/><geom type="box" size="0.05 0.05 0.05" mass="0.5"/></body>
    <body name="rod" pos="0.15 0 0.14"><freejoint/><geom type="capsule" size="0.03 0.1" euler="90 0 0" mass="0.5"/></body>
    </worldbody></mujoco>)", "pile.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  double max_iterations = 0;
  for (int i = 0; i < 150; ++i) {
    StepInfo info;
    ASSERT_TRUE(sim_step(m, o, s, ws, &info));
    max_iterations = std::max<double>(max_iterations, info.iterations);
  }
  EXPECT_LT(s.qvel.lpNorm<Eigen::Infinity>(), 1e-2);
  Kinematics k;
  kinematics(m, s.qpos, &k);
  std::vector<PairContact> c;
  find_pair_contacts(m, k, contact_geom_pairs(m), &c);
  const double g = 9.81, kk = o.contact.stiffness;
  int count[5] = {0, 0, 0, 0, 0};
  double worst = 0;
  for (const PairContact& pc : c) {
    ASSERT_EQ(pc.body_a, 1);  // the base below, every top body pushed up
    EXPECT_NEAR(pc.normal.z(), 1.0, 1e-3);
    const int n = pc.body_b == 2 ? 1 : pc.body_b == 3 ? 4 : 2;
    EXPECT_NEAR(pc.depth / (0.5 * g / (n * kk)), 1.0, 0.2) << "body " << pc.body_b;
    worst = std::max(worst, std::abs(pc.depth / (0.5 * g / (n * kk)) - 1));
    ++count[pc.body_b];
  }
  EXPECT_EQ(count[2], 1);
  EXPECT_EQ(count[3], 4);
  EXPECT_EQ(count[4], 2);
  EXPECT_LT(max_iterations, 20);
  std::printf("on the box: %zu body-body contacts, depth within %.2g%% of m g / (n k), max LM iterations per step %g\n",
              c.size(), 100 * worst, max_iterations);
}

// Zero gravity, no friction: a box hits a capsule off-centre (both spin); the stencil's
// momentum sum(m v) is conserved through the collision.
TEST(Contact, CollidingFreeBodiesConserveMomentum) {
  const Model m = two_bodies("0 0 0", "<geom type=\"box\" size=\"0.05 0.04 0.03\" mass=\"1\" euler=\"10 20 0\"/>",
                             "0.2 0.03 0.01", "<geom type=\"capsule\" size=\"0.03 0.06\" mass=\"0.7\" euler=\"0 80 30\"/>",
                             "0 0 0");
  const pair_test::CollisionMomentum r = pair_test::collide_two_free_bodies(m);
  EXPECT_GT(r.most_contacts, 0u);
  EXPECT_LT(r.worst, 1e-6);
  EXPECT_TRUE(r.bounced);  // the relative velocity along x changed sign
  std::printf("momentum drift %.3g relative\n", r.worst);
}

// A chain of three capsules whose last link falls back onto the first (fixed) one:
// with self-collision the two stay apart (penalty depth), without it they pass.
double folding_chain_min_gap(bool self_collision) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody>
    <body name="l1"><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
      <body name="l2" pos="0.3 0 0" euler="0 -100 0"><joint type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.02"/>
        <body name="l3" pos="0.1 0 0" euler="0 -80 0"><joint type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.02"/></body></body></body>
    </worldbody></mujoco>)", "fold.xml");
  SimOptions o;
  o.dt = 0.005;
  o.contact.self_collision = self_collision;
  State s = state_init(m);
  SimWorkspace ws;
  Kinematics k;
  double gap = 1e9;
  const Geom &g1 = m.geoms[0], &g3 = m.geoms[2];
  for (int i = 0; i < 160; ++i) {
    if (!sim_step(m, o, s, ws)) return -1e9;
    kinematics(m, s.qpos, &k);
    // Distance of link 3's axis from link 1's capsule (sampled), minus link 3's radius.
    for (int j = 0; j <= 20; ++j) {
      const Vec3 x = k.xpos[3] + k.xmat[3] * (g3.pos + g3.quat * Vec3(0, 0, g3.size[1] * (j / 10.0 - 1)));
      Geom w = g1;
      w.pos = k.xpos[1] + k.xmat[1] * g1.pos;
      w.quat = Quat(k.xmat[1]) * g1.quat;
      Vec3 n;
      gap = std::min(gap, obstacle_distance(w, x, &n) - g3.size[0]);
    }
  }
  return gap;
}

TEST(Contact, FoldingChainStaysApartWithSelfCollision) {
  const double on = folding_chain_min_gap(true), off = folding_chain_min_gap(false);
  std::printf("folding chain: min gap %.3g m with self-collision, %.3g m without\n", on, off);
  EXPECT_GT(on, -2e-3);
  EXPECT_LT(off, -0.02);
}

TEST(Contact, BodyPairFiltersParentChildBitmaskAndExclude) {
  // Geoms 1..7 on bodies a, child, grandchild, t2, a2, t4, ex (geom 0: the plane).
  const Model m = model_from_mjcf(R"(<mujoco><worldbody><geom type="plane"/>
    <body name="a"><freejoint/><geom size="0.1"/>
      <body name="child"><joint/><geom size="0.1"/>
        <body name="grandchild"><joint/><geom size="0.1"/></body></body></body>
    <body name="t2"><freejoint/><geom size="0.1" contype="2" conaffinity="0"/></body>
    <body name="a2"><freejoint/><geom size="0.1" contype="0" conaffinity="2"/></body>
    <body name="t4"><freejoint/><geom size="0.1" contype="4" conaffinity="4"/></body>
    <body name="ex"><freejoint/><geom size="0.1"/></body>
    </worldbody><contact><exclude body1="ex" body2="a"/></contact></mujoco>)", "filters.xml");
  std::vector<std::pair<int, int>> pairs;
  for (const GeomPair& p : contact_geom_pairs(m)) pairs.emplace_back(p.a, p.b);
  // a-child, child-grandchild: parent and child; t2/a2/t4 by the bitmask rule (only
  // t2's type meets a2's affinity); ex-a excluded.
  const std::vector<std::pair<int, int>> expect = {{1, 3}, {2, 7}, {3, 7}, {4, 5}};
  EXPECT_EQ(pairs, expect);
  // Without the exclude, ex meets a too.
  Model open = m;
  open.contact_exclude.clear();
  EXPECT_EQ(contact_geom_pairs(open).size(), 5u);
}

// ---- Explicit pairs (Model::contact_pairs) ----

// A ball on a slide joint above a fixed box body, both contype = conaffinity = 0 and
// self_collision off: only the explicit pair makes them touch; it rests at m g / k.
TEST(Contact, ExplicitPairCollidesWithContypeZeroAndRestsAtThePenaltyDepth) {
  Model m = model_from_mjcf(R"(<mujoco><worldbody>
    <body name="base"><geom name="base" type="box" size="0.2 0.2 0.05" contype="0" conaffinity="0"/></body>
    <body name="ball" pos="0 0 0.101"><joint type="slide" axis="0 0 1"/>
      <geom name="ball" size="0.05" mass="1" contype="0" conaffinity="0"/></body>
    </worldbody><contact><pair geom1="ball" geom2="base"/></contact></mujoco>)", "pair.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  ASSERT_FALSE(o.contact.self_collision);
  const auto drop = [&](const Model& model, bool self_collision) {
    SimOptions oo = o;
    oo.contact.self_collision = self_collision;
    State s = state_init(model);
    SimWorkspace ws;
    for (int i = 0; i < 80; ++i) EXPECT_TRUE(sim_step(model, oo, s, ws));
    return 0.101 + s.qpos[0];
  };
  const double k = o.contact.stiffness;
  EXPECT_NEAR((0.1 - drop(m, false)) / (9.81 / k), 1.0, 0.02);
  EXPECT_EQ(contact_geom_pairs(m).size(), 1u);
  Model unpaired = m;
  unpaired.contact_pairs.clear();
  EXPECT_LT(drop(unpaired, true), 0);  // contype 0: falls through, self-collision or not
}

// A box sliding on a fixed box body stops after v0^2 / (2 mu g) with the explicit
// pair's friction (0.2), not the scene's (0.5).
TEST(Contact, ExplicitPairFrictionReplacesTheScenes) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody>
    <body name="base"><geom name="base" type="box" size="0.5 0.2 0.05"/></body>
    <body name="box"><freejoint/><geom name="box" type="box" size="0.05 0.05 0.05" mass="1"/></body>
    </worldbody><contact><pair geom1="base" geom2="box" friction="0.2 0.2"/></contact></mujoco>)", "slide.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.mu = 0.5;
  State s = state_init(m);
  s.qpos[0] = -0.3;
  s.qpos[2] = 0.1 - 9.81 / (4 * o.contact.stiffness);
  s.qvel[0] = 0.5;
  SimWorkspace ws;
  for (int i = 0; i < 40; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  const double analytic = 0.25 / (2 * 0.2 * 9.81);
  EXPECT_NEAR((s.qpos[0] + 0.3) / analytic, 1.0, 0.03);
  EXPECT_LT(std::abs(s.qvel[0]), 1e-3);
}

// ---- Mesh geoms in body-body contact ----

// Body a: a free box mesh (half sizes 0.1 0.07 0.05, tilted); body b: a free geom.
size_t expect_mesh_pair_derivatives(const std::string& pos_b, const std::string& geom_b,
                                    const std::string& mesh_euler = "5 -8 12") {
  const std::string obj = test::write_box_obj("pliant_mesh_pair", 0.1, 0.07, 0.05);
  const Model m = model_from_mjcf("<mujoco><option gravity=\"0 0 -9.81\"/><asset><mesh name=\"m\" file=\"" + obj +
                                      "\"/></asset><worldbody><body name=\"a\"><freejoint/>"
                                      "<geom type=\"mesh\" mesh=\"m\" euler=\"" + mesh_euler + "\"/></body><body name=\"b\" pos=\"" +
                                      pos_b + "\"><freejoint/>" + geom_b + "</body></worldbody></mujoco>",
                                  "mesh_pair.xml");
  std::filesystem::remove(obj);
  return expect_pair_derivatives(m);
}

TEST(Contact, MeshPairGradientMatchesFiniteDifferences) {
  // Sphere centre against the mesh (exact: one contact).
  EXPECT_EQ(expect_mesh_pair_derivatives("0.02 0.01 0.09", "<geom type=\"sphere\" size=\"0.05\"/>"), 1u);
  // A tilted cube's lowest corner in the mesh's top face, mesh samples inside the cube.
  EXPECT_GE(expect_mesh_pair_derivatives("0.01 0.005 0.11", "<geom type=\"box\" size=\"0.04 0.04 0.04\" euler=\"30 40 20\"/>"), 1u);
  // A capsule's end sphere dipping into the mesh's top face.
  EXPECT_GE(expect_mesh_pair_derivatives("0.01 0 0.12", "<geom type=\"capsule\" size=\"0.03 0.08\" euler=\"20 35 10\"/>"), 1u);
  // The mesh's bottom face lying on a larger box: its samples give more than
  // kMaxTermsPerBodyPair terms, merged per body pair in lm_solve (pbad_solver.cpp);
  // the LM matrix's body-body part still equals the finite-difference one.
  EXPECT_GT(expect_mesh_pair_derivatives("0.01 0.005 -0.097", "<geom type=\"box\" size=\"0.2 0.2 0.05\" euler=\"0.05 -0.03 0\"/>", "0 0 0"),
            static_cast<size_t>(kMaxTermsPerBodyPair));
}

// A mesh cube on a slide joint rests on a fixed box body (its bottom face's samples
// share the weight: each at m g / (n k)), a ball rests on a fixed mesh block (its
// centre against the mesh: m g / k).
TEST(Contact, MeshBodiesRestOnABoxAndUnderABallAtThePenaltyDepth) {
  const std::string obj = test::write_box_obj("pliant_mesh_pair_rest", 0.05, 0.05, 0.05);
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"cube\" file=\"" + obj + "\"/></asset><worldbody>"
      "<body name=\"base\"><geom type=\"box\" size=\"0.3 0.3 0.05\"/></body>"
      "<body name=\"cube\" pos=\"-0.15 0 0.101\"><joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"cube\" mass=\"1\"/></body>"
      "<body name=\"block\" pos=\"0.6 0 0\"><geom type=\"mesh\" mesh=\"cube\"/></body>"
      "<body name=\"ball\" pos=\"0.6 0 0.101\"><joint type=\"slide\" axis=\"0 0 1\"/><geom size=\"0.05\" mass=\"1\"/></body>"
      "</worldbody></mujoco>",
      "mesh_rest.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  for (int i = 0; i < 80; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  EXPECT_LT(s.qvel.lpNorm<Eigen::Infinity>(), 1e-2);
  const std::vector<PairContact> c = pair_contacts_at(m, s.qpos);
  const double kk = o.contact.stiffness;
  int on_base = 0, on_block = 0;
  for (const PairContact& pc : c) (pc.body_b == 4 ? on_block : on_base) += 1;
  EXPECT_GT(on_base, 4);  // corners plus edge and face samples
  EXPECT_EQ(on_block, 1);
  for (const PairContact& pc : c) {
    EXPECT_NEAR(pc.normal.z(), 1.0, 1e-6);  // pushes the upper body (b) up
    const int n = pc.body_b == 4 ? 1 : on_base;
    EXPECT_NEAR(pc.depth / (9.81 / (n * kk)), 1.0, 0.02) << pc.body_a << " " << pc.body_b;
  }
}

// ---- Parallel capsules ----

// A free capsule dropped slightly tilted (3 degrees) on a fixed one, axes parallel in
// plan, offset along them: the overlap's two end spheres (x = -0.06 and 0.1) carry its
// weight as a beam on two supports (3/8 and 5/8 of m g, centre at x = 0.04), so it
// rests at the penalty's static tilt (F2 - F1) / (k span). The one contact at the
// middle of the overlap held it on the kink of an energy V-shaped in the tilt (exactly
// level, 1.98 LM iterations per step here against 1.34).
TEST(Contact, CapsuleOnAParallelCapsuleRestsOnTwoContacts) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody>
    <body name="low"><geom type="capsule" size="0.02 0.1" euler="0 90 0"/></body>
    <body name="up" pos="0.04 0 0.0458" euler="0 87 0"><freejoint/><geom type="capsule" size="0.02 0.1" mass="0.5"/></body>
    </worldbody></mujoco>)", "capsules.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  double iterations = 0;
  for (int i = 0; i < 100; ++i) {
    StepInfo info;
    ASSERT_TRUE(sim_step(m, o, s, ws, &info));
    iterations += info.iterations;
  }
  Kinematics k;
  kinematics(m, s.qpos, &k);
  const double tilt = std::asin(std::abs(k.xmat[2].col(2).z()));  // axis against the horizontal
  const double expect = (0.625 - 0.375) * 0.5 * 9.81 / (o.contact.stiffness * 0.16);
  const std::vector<PairContact> c = pair_contacts_at(m, s.qpos);
  std::printf("capsule on a parallel capsule: %zu contacts, tilt %.4g rad (beam on two supports %.4g), %.2f LM iterations per step\n",
              c.size(), tilt, expect, iterations / 100);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(tilt / expect, 1.0, 0.05);
  EXPECT_NEAR((c[0].depth + c[1].depth) * o.contact.stiffness / (0.5 * 9.81), 1.0, 0.01);
  EXPECT_LT(s.qvel.lpNorm<Eigen::Infinity>(), 1e-2);
}

// Energy of two capsules continuous as the upper one turns through parallel and its
// crossing point slides off the lower one's end (the contact rule switches there), and
// the gradient still matches finite differences for a crossing with an end sphere in
// reach (closest-point contact plus end spheres but the deepest).
TEST(Contact, CapsuleCapsuleEnergyIsContinuousThroughParallel) {
  const auto energy_at = [](double yaw, double shift) {
    const Model m = model_from_mjcf("<mujoco><worldbody><body name=\"low\"><geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 0\"/></body>"
                                    "<body name=\"up\" pos=\"" + std::to_string(shift) + " 0 0.039\" euler=\"0 0 " +
                                        std::to_string(yaw) + "\"><freejoint/><geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 0\"/></body>"
                                    "</worldbody></mujoco>", "capsules.xml");
    double e = 0;
    for (const PairContact& c : pair_contacts_at(m, state_init(m).qpos)) e += c.depth * c.depth;
    return e;
  };
  double worst = 0;
  for (double shift : {0.04, 0.19}) {
    double prev = energy_at(-2, shift);
    for (int i = 1; i <= 400; ++i) {  // yaw -2 .. 2 degrees, 0.01 degree steps
      const double e = energy_at(-2 + 0.01 * i, shift);
      worst = std::max(worst, std::abs(e - prev) / std::max(e, prev));
      prev = e;
    }
  }
  std::printf("capsule pair energy: largest relative change per 0.01 degree %.3g\n", worst);
  EXPECT_LT(worst, 0.02);
  EXPECT_GE(expect_pair_derivatives(two_bodies("0 0 0", "<geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 0\"/>",
                                               "0.07 0.01 0.038", "<geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 90 40\"/>")),
            2u);
}

}  // namespace
}  // namespace pliant::articulated
