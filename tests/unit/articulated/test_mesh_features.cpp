// Static features against moving meshes through the moving mesh's tree
// (contact.cpp: moving_mesh_trees; contact_mesh_features.cpp: mesh_feature_contacts): box corners and spheres,
// and a static mesh's vertices (the reverse of the moving mesh's samples).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>
#include <algorithm>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"

namespace pliant::articulated {
namespace {

std::string mf_temp(const std::string& stem) {
  return (std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()) + ".obj")).string();
}

// A 432-triangle moving grid box among static boxes and spheres, in random poses:
// through the tree the contacts equal the scan's to the bit (on a box mesh the
// pseudo-normal sign is the face normal's), and the root-box cull drops none.
TEST(MeshFeatures, TreeContactsEqualTheScanOnABoxMesh) {
  const std::string obj = test::write_grid_box_obj("pliant_mf_grid", 0.06, 0.04, 0.03, 6);
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"g\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"box\" size=\"0.03 0.02 0.04\" pos=\"0.02 0 0\" euler=\"20 30 40\"/>"
      "<geom type=\"sphere\" size=\"0.02\" pos=\"-0.05 0.02 0.01\"/>"
      "<geom type=\"sphere\" size=\"0.005\" pos=\"0.01 -0.03 -0.02\"/>"
      "<body><freejoint/><geom type=\"mesh\" mesh=\"g\" mass=\"0.2\"/></body></worldbody></mujoco>",
      "grid.xml");
  std::filesystem::remove(obj);
  const std::vector<MeshBvh> trees = moving_mesh_trees(m);
  ASSERT_EQ(trees.size(), m.geoms.size());
  ASSERT_EQ(trees.back().order.size(), 432u);
  const std::vector<int> obs = contact_obstacles(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int total = 0;
  for (int i = 0; i < 200; ++i) {
    VecX q = m.qpos0;
    q.head<3>() = 0.06 * Vec3(u(rng), u(rng), u(rng));
    const Quat r = Quat(Eigen::AngleAxisd(3 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
    Kinematics k;
    kinematics(m, q, &k);
    std::vector<Contact> tree, scan;
    mesh_feature_contacts(m, k, obs, {}, trees, &tree);
    mesh_feature_contacts(m, k, obs, {}, {}, &scan);
    ASSERT_EQ(tree.size(), scan.size()) << "pose " << i;
    for (size_t c = 0; c < tree.size(); ++c) {
      EXPECT_EQ(tree[c].depth, scan[c].depth);
      EXPECT_EQ(tree[c].normal, scan[c].normal);
      EXPECT_EQ(tree[c].point, scan[c].point);
    }
    total += static_cast<int>(tree.size());
  }
  EXPECT_GT(total, 100);
}

// A moving wedge (11.4 degree apex edge), no gravity, and a static 8 mm ball 2 mm
// outside its apex edge: nothing touches. The scan's face-normal sign reads one side as
// more than 1.5 cm deep; through the tree no contact is found and a PBAD step leaves
// the wedge at rest.
TEST(MeshFeatures, StaticBallJustOutsideAMovingSharpEdgeIsNotInContact) {
  const std::string obj = mf_temp("pliant_mf_wedge");
  {
    std::ofstream out(obj);
    for (double y : {-0.05, 0.05}) out << "v -0.01 " << y << " 0\nv 0.01 " << y << " 0\nv 0 " << y << " 0.1\n";
    out << "f 1 2 3\nf 4 6 5\nf 1 4 5\nf 1 5 2\nf 2 5 6\nf 2 6 3\nf 3 6 4\nf 3 4 1\n";
  }
  int scan_hits = 0;
  for (double side : {-1.0, 1.0}) {
    const std::string ball_pos = std::to_string(side * 0.0015) + " 0.01 0.11";
    const Model m = model_from_mjcf("<mujoco><option gravity=\"0 0 0\"/><asset><mesh name=\"w\" file=\"" + obj +
                                        "\"/></asset><worldbody><geom type=\"sphere\" size=\"0.008\" pos=\"" +
                                        ball_pos + "\"/><body><freejoint/><geom type=\"mesh\" mesh=\"w\" mass=\"0.1\"/>"
                                        "</body></worldbody></mujoco>",
                                    "wedge.xml");
    SimWorkspace ws;
    sim_prepare(m, ws);
    Kinematics k;
    kinematics(m, m.qpos0, &k);
    std::vector<Contact> tree, scan;
    mesh_feature_contacts(m, k, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &tree);
    mesh_feature_contacts(m, k, ws.obstacles, {}, {}, &scan);
    EXPECT_TRUE(tree.empty()) << "side " << side;
    scan_hits += static_cast<int>(scan.size());
    if (!scan.empty()) {
      EXPECT_GT(scan[0].depth, 0.015);  // the face normal's wrong sign
    }
    SimOptions o;
    o.dt = 0.01;
    State s = state_init(m);
    ASSERT_TRUE(sim_step(m, o, s, ws));
    EXPECT_TRUE(ws.contacts.empty());
    EXPECT_LT(s.qvel.norm(), 1e-12) << "side " << side;
  }
  EXPECT_EQ(scan_hits, 1);
  std::filesystem::remove(obj);
}

// A 0.5 kg mesh plate (20 x 20 x 2 cm box, 12 triangles) on a vertical slide joint over
// a static tetrahedral spike whose tip (off the plate's samples) is at z = 0: the tip
// (a static mesh vertex) against the plate's faces holds it at the penalty depth
// m g / k, one contact; the plate's samples alone (find_contacts' body points) touch
// nothing there, so without the vertex the plate would sink onto the spike's sides.
TEST(MeshFeatures, PlateRestsOnAStaticSpikeTip) {
  const std::string plate = test::write_box_obj("pliant_mf_plate", 0.1, 0.1, 0.01);
  const std::string spike = mf_temp("pliant_mf_spike");
  {
    std::ofstream out(spike);
    const double tx = 0.0123, ty = 0.0071, r = 0.03;
    for (int i = 0; i < 3; ++i)
      out << "v " << tx + r * std::cos(2.0944 * i) << " " << ty + r * std::sin(2.0944 * i) << " -0.1\n";
    out << "v " << tx << " " << ty << " 0\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  }
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"p\" file=\"" + plate + "\"/><mesh name=\"s\" file=\"" + spike +
          "\"/></asset><worldbody><geom type=\"mesh\" mesh=\"s\"/><body pos=\"0 0 0.011\">"
          "<joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"p\" mass=\"0.5\"/></body>"
          "</worldbody></mujoco>",
      "spike.xml");
  std::filesystem::remove(plate);
  std::filesystem::remove(spike);
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  State s = state_init(m);
  SimWorkspace ws;
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  const double k = o.contact.stiffness, depth = 0.5 * 9.81 / k;
  EXPECT_NEAR(s.qpos[0], -0.001 - depth, 1e-7);  // body at z 0.011 + q: bottom at -depth
  ASSERT_EQ(ws.contacts.size(), 1u);
  EXPECT_EQ(ws.contacts[0].slot, -1);  // the spike's tip, not a plate sample
  EXPECT_NEAR(ws.contacts[0].depth, depth, 1e-7);
  EXPECT_NEAR(ws.contacts[0].normal.z(), 1, 1e-9);
}

// A moving 432-triangle box mesh in random poses over a 1760-triangle static terrain:
// the terrain's vertices found by walking its tree (the moving mesh's bounding sphere)
// give the same contacts as testing every vertex (same set; the order differs).
TEST(MeshFeatures, StaticMeshVerticesThroughTheTreeEqualTheFullLoop) {
  const std::string terrain = mf_temp("pliant_mf_terrain");
  {
    const MeshShape t = test::terrain_mesh(20, [](double x, double y) { return 0.03 * std::sin(9 * x) * std::cos(7 * y); });
    std::ofstream out(terrain);
    out.precision(17);
    for (const Vec3& v : t.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& f : t.triangles) out << "f " << f[0] + 1 << " " << f[1] + 1 << " " << f[2] + 1 << "\n";
  }
  const std::string box = test::write_grid_box_obj("pliant_mf_tbox", 0.12, 0.08, 0.05, 6);
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"t\" file=\"" + terrain + "\"/><mesh name=\"b\" file=\"" +
                                      box + "\"/></asset><worldbody><geom type=\"mesh\" mesh=\"t\"/><body>"
                                      "<freejoint/><geom type=\"mesh\" mesh=\"b\" mass=\"0.2\"/></body></worldbody></mujoco>",
                                  "terrain.xml");
  std::filesystem::remove(terrain);
  std::filesystem::remove(box);
  SimWorkspace ws;
  sim_prepare(m, ws);
  ASSERT_EQ(ws.obstacle_trees.size(), 1u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int total = 0;
  const auto key = [](const Contact& c) { return std::make_tuple(c.point.x(), c.point.y(), c.point.z()); };
  for (int i = 0; i < 100; ++i) {
    VecX q = m.qpos0;
    q.head<3>() = Vec3(0.4 * u(rng), 0.4 * u(rng), 0.05 * u(rng));
    const Quat r = Quat(Eigen::AngleAxisd(u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
    Kinematics k;
    kinematics(m, q, &k);
    std::vector<Contact> walk, all;
    mesh_feature_contacts(m, k, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &walk);
    mesh_feature_contacts(m, k, ws.obstacles, {}, ws.mesh_trees, &all);
    ASSERT_EQ(walk.size(), all.size()) << "pose " << i;
    const auto less = [&](const Contact& a, const Contact& b) { return key(a) < key(b); };
    std::sort(walk.begin(), walk.end(), less);
    std::sort(all.begin(), all.end(), less);
    for (size_t c = 0; c < walk.size(); ++c) {
      EXPECT_EQ(walk[c].point, all[c].point);
      EXPECT_EQ(walk[c].depth, all[c].depth);
      EXPECT_EQ(walk[c].normal, all[c].normal);
    }
    total += static_cast<int>(walk.size());
  }
  EXPECT_GT(total, 200);
}

}  // namespace
}  // namespace pliant::articulated
