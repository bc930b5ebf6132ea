// Static mesh obstacles through the triangle tree and the pseudo-normal sign
// (contact.cpp: obstacle_trees, obstacle_distance, find_contacts).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"

namespace pliant::articulated {
namespace {

double mo_height(double x, double y) { return 0.03 * std::sin(9 * x) * std::cos(7 * y) + 0.02 * x; }

// The terrain's top as the mesh has it: linear on each cell's two triangles (split
// along the (i, j)-(i+1, j+1) diagonal, as terrain_mesh).
double mo_linear_height(int n, double x, double y) {
  const double gx = (x + 0.5) * n, gy = (y + 0.5) * n;
  const int i = std::min(n - 1, static_cast<int>(gx)), j = std::min(n - 1, static_cast<int>(gy));
  const double u = gx - i, v = gy - j;
  const auto h = [n](int a, int b) { return mo_height(-0.5 + double(a) / n, -0.5 + double(b) / n); };
  return u >= v ? h(i, j) + u * (h(i + 1, j) - h(i, j)) + v * (h(i + 1, j + 1) - h(i + 1, j))
                : h(i, j) + v * (h(i, j + 1) - h(i, j)) + u * (h(i + 1, j + 1) - h(i, j + 1));
}

// A 1760-triangle static terrain, rotated and moved: through its tree the distance
// equals the scan's to the bit (the same nearest triangle), the sign matches the true
// inside (below the piecewise-linear top, inside the block) at every point, and where
// the scan's face-normal sign agrees the normal is the same to the bit.
TEST(MeshObstacle, TerrainDistanceThroughTheTreeEqualsTheScan) {
  const int n = 20;
  Model m;
  Geom g;
  g.type = GeomType::Mesh;
  g.body = 0;
  g.pos = Vec3(0.3, -0.2, 0.1);
  g.quat = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  g.mesh = std::make_shared<const MeshShape>(test::terrain_mesh(n, mo_height));
  m.geoms.push_back(g);
  ASSERT_EQ(g.mesh->triangles.size(), 4u * n * n + 8u * n);
  const std::vector<int> obs = contact_obstacles(m);
  ASSERT_EQ(obs.size(), 1u);
  const std::vector<MeshBvh> trees = obstacle_trees(m, obs);
  ASSERT_EQ(trees.size(), 1u);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.6, 0.6), w(-0.1, 0.1);
  int inside = 0, scan_differs = 0;
  for (int i = 0; i < 3000; ++i) {
    // Points in the terrain's frame, most within 3 cm of its top, some anywhere.
    Vec3 p(u(rng), u(rng), 0);
    p.z() = i % 5 ? mo_linear_height(n, std::clamp(p.x(), -0.5, 0.5), std::clamp(p.y(), -0.5, 0.5)) + 0.3 * w(rng)
                  : 2.5 * w(rng);
    const Vec3 x = g.pos + g.quat * p;
    Vec3 n0, n1;
    const double d_scan = obstacle_distance(g, x, &n0), d_tree = obstacle_distance(g, &trees[0], x, &n1);
    ASSERT_EQ(std::abs(d_scan), std::abs(d_tree)) << p.transpose();
    if ((d_scan < 0) == (d_tree < 0)) {
      ASSERT_EQ(d_scan, d_tree);
      ASSERT_EQ(n0, n1);
    } else {
      ++scan_differs;
    }
    if (std::abs(d_tree) < 1e-9) continue;
    const bool truly_inside = std::abs(p.x()) < 0.5 && std::abs(p.y()) < 0.5 && p.z() > -0.2 &&
                              p.z() < mo_linear_height(n, p.x(), p.y());
    ASSERT_EQ(d_tree < 0, truly_inside) << p.transpose() << " d " << d_tree;
    inside += truly_inside;
  }
  EXPECT_GT(inside, 800);
  std::printf("terrain: %d of 3000 points signed differently by the face-normal scan\n", scan_differs);
}

// A wedge (11.4 degree apex edge) standing on the world as a static mesh, a free ball
// (radius 8 mm) 2 mm outside its apex edge, no gravity: nothing touches. The scan's
// face-normal sign read one side as 2 cm deep (a contact that threw the ball); through
// the tree no contact is found and a PBAD step leaves the ball at rest.
TEST(MeshObstacle, BallJustOutsideASharpStaticEdgeIsNotInContact) {
  const auto obj = std::filesystem::temp_directory_path() / ("pliant_mo_wedge_" + std::to_string(::getpid()) + ".obj");
  {
    std::ofstream out(obj);
    for (double y : {-0.05, 0.05}) out << "v -0.01 " << y << " 0\nv 0.01 " << y << " 0\nv 0 " << y << " 0.1\n";
    out << "f 1 2 3\nf 4 6 5\nf 1 4 5\nf 1 5 2\nf 2 5 6\nf 2 6 3\nf 3 6 4\nf 3 4 1\n";
  }
  int scan_hits = 0;
  for (double side : {-1.0, 1.0}) {
    const std::string ball_pos = std::to_string(side * 0.0015) + " 0.01 0.11";
    const Model m = model_from_mjcf("<mujoco><option gravity=\"0 0 0\"/><asset><mesh name=\"w\" file=\"" + obj.string() +
                                        "\"/></asset><worldbody><geom type=\"mesh\" mesh=\"w\"/><body pos=\"" + ball_pos +
                                        "\"><freejoint/><geom type=\"sphere\" size=\"0.008\" mass=\"0.1\"/></body>"
                                        "</worldbody></mujoco>",
                                    "wedge.xml");
    SimWorkspace ws;
    sim_prepare(m, ws);
    ASSERT_EQ(ws.obstacle_trees.size(), 1u);
    Kinematics k;
    kinematics(m, m.qpos0, &k);
    std::vector<Contact> tree_contacts, scan_contacts;
    find_contacts(m, k, ws.points, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &tree_contacts);
    find_contacts(m, k, ws.points, ws.obstacles, {}, {}, &scan_contacts);
    EXPECT_TRUE(tree_contacts.empty()) << "side " << side;
    scan_hits += static_cast<int>(scan_contacts.size());
    if (!scan_contacts.empty()) {
      EXPECT_GT(scan_contacts[0].depth, 0.015);  // the scan's wrong sign
    }
    SimOptions o;
    o.dt = 0.01;
    State s = state_init(m);
    ASSERT_TRUE(sim_step(m, o, s, ws));
    EXPECT_TRUE(ws.contacts.empty());
    EXPECT_LT(s.qvel.norm(), 1e-12) << "side " << side;
    EXPECT_LT((s.qpos - m.qpos0).norm(), 1e-12);
  }
  EXPECT_EQ(scan_hits, 1);  // one side's nearest face is the far one: what the tree fixes
  std::filesystem::remove(obj);
}

// A box (1 kg, half size 0.1) resting on a 1200-triangle static slab whose top is a
// 10 x 10 grid of 0.1 m cells, its four bottom corners right above grid vertices (the
// nearest feature a vertex or an edge, whose pseudo-normals give the sign), and a ball
// on the slab over a cell's diagonal edge: each at the penalty depth m g / (contacts k).
TEST(MeshObstacle, BodiesRestOnASubdividedStaticSlabAtTheAnalyticDepth) {
  const std::string obj = test::write_grid_box_obj("pliant_mo_slab", 0.5, 0.5, 0.1, 10);
  const Model m = model_from_mjcf(
      "<mujoco><asset><mesh name=\"slab\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"mesh\" mesh=\"slab\" pos=\"0 0 -0.1\"/>"
      "<body pos=\"0 0 0.1005\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\" mass=\"1\"/></body>"
      "<body pos=\"0.25 0.25 0.0505\"><freejoint/><geom type=\"sphere\" size=\"0.05\" mass=\"0.5\"/></body>"
      "</worldbody></mujoco>",
      "slab.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.01;
  o.contact.friction = FrictionModel::None;
  State s = state_init(m);
  SimWorkspace ws;
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  ASSERT_EQ(ws.obstacle_trees.size(), 1u);
  EXPECT_EQ(ws.obstacle_trees[0].order.size(), 1200u);
  const double k = o.contact.stiffness, g = 9.81;
  int box_contacts = 0;
  for (const Contact& c : ws.contacts) box_contacts += c.body == 1;
  EXPECT_EQ(box_contacts, 4);
  EXPECT_NEAR(s.qpos[2], 0.1 - 1 * g / (4 * k), 1e-7);   // box centre
  EXPECT_NEAR(s.qpos[9], 0.05 - 0.5 * g / k, 1e-7);      // ball centre
  EXPECT_NEAR(s.qpos[0], 0, 1e-9);
  EXPECT_NEAR(s.qpos[7], 0.25, 1e-9);
}

}  // namespace
}  // namespace pliant::articulated
