// Contact: meshes against world obstacles (static meshes, box corners and spheres on moving meshes).
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

}  // namespace
}  // namespace pliant::articulated
