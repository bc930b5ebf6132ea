// Mesh-mesh body-body contact, the mesh distance tree, and explicit pairs' margin and
// condim (contact.cpp, mesh_distance.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"
#include "pair_fixture.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// A mesh written by `write` loaded as a MeshShape (through a one-geom MJCF model).
MeshShape mm_load_mesh(const std::string& obj) {
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"m\" file=\"" + obj +
                                      "\"/></asset><worldbody><body><freejoint/><geom type=\"mesh\" mesh=\"m\"/></body>"
                                      "</worldbody></mujoco>",
                                  "mesh.xml");
  std::filesystem::remove(obj);
  return *m.geoms[0].mesh;
}

// A closed box mesh: the tree finds the scan's triangle (same distance to the bit) and,
// all dihedral angles being 90 degrees, the same sign from its pseudo-normals.
TEST(MeshContact, TreeDistanceEqualsTheScanToTheBit) {
  const MeshShape mesh = mm_load_mesh(test::write_grid_box_obj("pliant_mm_tree", 0.2, 0.1, 0.05, 5));
  ASSERT_EQ(mesh.triangles.size(), 300u);
  const MeshBvh bvh = mesh_bvh(mesh);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    // Random points, and points on the lattice's planes (ties between triangles).
    Vec3 p(u(rng), u(rng) * 0.5, u(rng) * 0.3);
    if (i % 4 == 0) p.x() = -0.2 + 0.08 * std::round((p.x() + 0.2) / 0.08);
    if (i % 8 == 0) p.z() = 0.05;
    Vec3 n0, n1;
    const double d0 = mesh_signed_distance(mesh, p, &n0), d1 = mesh_signed_distance(mesh, bvh, p, &n1);
    ASSERT_EQ(d0, d1) << p.transpose();
    ASSERT_EQ(n0, n1) << p.transpose();
    inside += d0 < 0;
  }
  EXPECT_GT(inside, 100);
}

// A wedge (triangular prism, 11.4 degree apex edge): just outside the apex, the
// nearest triangle's face normal can read "inside" (the scan), the edge's pseudo-normal
// does not (the tree); inside points read inside, with the same distance both ways.
TEST(MeshContact, TreeSignIsRightNearASharpEdge) {
  const double w = 0.01, h = 0.1, l = 0.05;
  MeshShape wedge;
  for (double y : {-l, l}) {
    wedge.vertices.push_back(Vec3(-w, y, 0));
    wedge.vertices.push_back(Vec3(w, y, 0));
    wedge.vertices.push_back(Vec3(0, y, h));
  }
  wedge.triangles = {{0, 1, 2}, {3, 5, 4}, {0, 3, 4}, {0, 4, 1}, {1, 4, 5}, {1, 5, 2}, {2, 5, 3}, {2, 3, 0}};
  const MeshBvh bvh = mesh_bvh(wedge);
  int scan_wrong = 0;
  for (int i = 0; i < 40; ++i) {
    const double y = -0.04 + 0.002 * i, side = i % 2 ? 1 : -1;
    Vec3 n0, n1;
    // Outside, 1 cm above the apex and 2 mm to one side (the apex edge is nearest).
    const Vec3 out(side * (0.0015 + 0.00003 * i), y, h + 0.01);
    const double d0 = mesh_signed_distance(wedge, out, &n0), d1 = mesh_signed_distance(wedge, bvh, out, &n1);
    EXPECT_EQ(std::abs(d0), std::abs(d1));
    EXPECT_GT(d1, 0) << out.transpose();
    EXPECT_GT(n1.dot(out - Vec3(0, y, h)), 0);  // the normal points out, away from the edge
    scan_wrong += d0 < 0;
    // Inside, below the apex.
    const Vec3 in(side * 0.001, y, 0.05);
    EXPECT_LT(mesh_signed_distance(wedge, bvh, in, &n1), 0);
    EXPECT_EQ(mesh_signed_distance(wedge, in, &n0), mesh_signed_distance(wedge, bvh, in, &n1));
  }
  EXPECT_GT(scan_wrong, 0);  // what the pseudo-normals fix
  std::printf("wedge apex: %d of 40 outside points read inside by the face-normal scan, 0 by the tree\n", scan_wrong);
}

// Two free mesh bodies: a box mesh (300 triangles) and a tilted cube mesh (48) whose
// lowest corner dips into its top face. PBAD's gradient (Coulomb on) and the LM
// matrix's body-body part against finite differences.
TEST(MeshContact, MeshMeshPairGradientMatchesFiniteDifferences) {
  const std::string big = test::write_grid_box_obj("pliant_mm_grad_a", 0.1, 0.07, 0.05, 5);
  const std::string cube = test::write_grid_box_obj("pliant_mm_grad_b", 0.04, 0.04, 0.04, 2);
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"a\" file=\"" + big + "\"/><mesh name=\"b\" file=\"" + cube +
                                      "\"/></asset><worldbody><body name=\"a\"><freejoint/><geom type=\"mesh\" mesh=\"a\" "
                                      "euler=\"5 -8 12\"/></body><body name=\"b\" pos=\"0.01 0.005 0.11\"><freejoint/>"
                                      "<geom type=\"mesh\" mesh=\"b\" euler=\"30 40 20\"/></body></worldbody></mujoco>",
                                  "mm_grad.xml");
  std::filesystem::remove(big);
  std::filesystem::remove(cube);
  ASSERT_EQ(contact_geom_pairs(m).size(), 1u);  // mesh-mesh now listed
  EXPECT_GE(pair_test::expect_pair_derivatives(m), 1u);
}

// A mesh cube (half size 0.05, 1 kg) on a vertical slide joint on a fixed mesh block.
// Every contact has the same depth d (the cube's bottom-face samples inside the block,
// the block's top-face samples inside the cube's footprint), so n k d = m g. Once with
// automatic pairs (self_collision), once through an explicit MJCF <pair> with
// contype = conaffinity = 0 and self_collision off: the same contacts.
std::string mm_cube_on_block_xml(const std::string& cube, const std::string& block, bool explicit_pair) {
  const std::string mask = explicit_pair ? " contype=\"0\" conaffinity=\"0\"" : "";
  return "<mujoco><asset><mesh name=\"cube\" file=\"" + cube + "\"/><mesh name=\"block\" file=\"" + block +
         "\"/></asset><worldbody><body name=\"block\"><geom name=\"block\" type=\"mesh\" mesh=\"block\"" + mask +
         "/></body><body name=\"cube\" pos=\"-0.02 0.013 0.101\"><joint type=\"slide\" axis=\"0 0 1\"/>"
         "<geom name=\"cube\" type=\"mesh\" mesh=\"cube\" mass=\"1\"" + mask + "/></body></worldbody>" +
         (explicit_pair ? "<contact><pair geom1=\"block\" geom2=\"cube\"/></contact>" : "") + "</mujoco>";
}

TEST(MeshContact, MeshCubeRestsOnAMeshBlockAtThePenaltyDepth) {
  const std::string cube = test::write_grid_box_obj("pliant_mm_rest_cube", 0.05, 0.05, 0.05, 2);
  const std::string block = test::write_grid_box_obj("pliant_mm_rest_block", 0.3, 0.3, 0.05, 4);
  double height[2];
  for (int e = 0; e < 2; ++e) {
    const Model m = model_from_mjcf(mm_cube_on_block_xml(cube, block, e == 1), "mm_rest.xml");
    SimOptions o;
    o.dt = 0.01;
    o.contact.friction = FrictionModel::None;
    o.contact.self_collision = e == 0;
    State s = state_init(m);
    SimWorkspace ws;
    int iterations = 0;
    for (int i = 0; i < 80; ++i) {
      StepInfo info;
      ASSERT_TRUE(sim_step(m, o, s, ws, &info));
      iterations += info.iterations;
    }
    EXPECT_LT(std::abs(s.qvel[0]), 1e-3);
    Kinematics k;
    kinematics(m, s.qpos, &k);
    std::vector<PairContact> c;
    find_pair_contacts(m, k, contact_geom_pairs(m), &c, o.contact.self_collision);
    const double n = static_cast<double>(c.size()), kk = o.contact.stiffness, d = 9.81 / (n * kk);
    EXPECT_GT(c.size(), 9u);  // samples of both meshes
    int from_cube = 0;
    for (const PairContact& pc : c) {
      EXPECT_NEAR(std::abs(pc.normal.z()), 1.0, 1e-9);
      EXPECT_NEAR(pc.depth / d, 1.0, 0.02);
      // The force k d n acts on b: up on the cube, down on the block.
      EXPECT_GT(pc.normal.z() * (pc.body_b == 2 ? 1 : -1), 0);
      from_cube += pc.body_b == 2;
    }
    EXPECT_GT(from_cube, 0);
    EXPECT_LT(from_cube, static_cast<int>(c.size()));  // both directions contribute
    height[e] = 0.101 + s.qpos[0];
    EXPECT_NEAR((0.1 - height[e]) / d, 1.0, 0.02);
    std::printf("%s: %zu contacts (%d cube samples, %zu block samples), depth %.4g m = m g / (n k) x %.4f, %.2f LM "
                "iterations per step\n",
                e ? "explicit pair" : "self_collision", c.size(), from_cube, c.size() - from_cube, 0.1 - height[e],
                (0.1 - height[e]) / d, iterations / 80.0);
  }
  EXPECT_NEAR(height[0], height[1], 1e-12);
  std::filesystem::remove(cube);
  std::filesystem::remove(block);
}

// The explicit baselines use the same mesh-mesh contacts (spring-damper normal force):
// semi-implicit Euler and RK4 bring the cube to rest on the block at the same depth.
TEST(MeshContact, ExplicitIntegratorsRestAMeshCubeOnAMeshBlock) {
  const std::string cube = test::write_grid_box_obj("pliant_mm_euler_cube", 0.05, 0.05, 0.05, 2);
  const std::string block = test::write_grid_box_obj("pliant_mm_euler_block", 0.3, 0.3, 0.05, 4);
  const Model m = model_from_mjcf(mm_cube_on_block_xml(cube, block, false), "mm_euler.xml");
  std::filesystem::remove(cube);
  std::filesystem::remove(block);
  for (Integrator in : {Integrator::Euler, Integrator::Rk4}) {
    SimOptions o;
    o.integrator = in;
    o.dt = 2e-4;
    o.contact.self_collision = true;
    o.contact.friction = FrictionModel::None;
    o.contact.damping = 20;  // N s/m per contact: 0.3 of critical on 83 springs, c dt / m = 0.33 (stable)
    State s = state_init(m);
    SimWorkspace ws;
    for (int i = 0; i < 500; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));  // 0.1 s: falls 1 mm, settles
    const double sink = 0.1 - (0.101 + s.qpos[0]);
    EXPECT_EQ(pair_test::pair_contacts_at(m, s.qpos).size(), 83u) << integrator_name(in);
    EXPECT_NEAR(sink / (9.81 / (83 * o.contact.stiffness)), 1.0, 0.02) << integrator_name(in);
    EXPECT_LT(std::abs(s.qvel[0]), 1e-3);
  }
}

// A tilted mesh cube dropped from 0.2 m on a fixed mesh block at dt 0.01 (2 m/s at
// impact, 2 cm per step, the block 10 cm thick) stops on it: its lowest vertex never
// goes more than a few millimetres into the block, and it comes to rest on its face.
TEST(MeshContact, DroppedMeshCubeStopsOnAMeshBlock) {
  const std::string cube = test::write_grid_box_obj("pliant_mm_drop_cube", 0.05, 0.05, 0.05, 2);
  const std::string block = test::write_grid_box_obj("pliant_mm_drop_block", 0.3, 0.3, 0.05, 4);
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"cube\" file=\"" + cube + "\"/><mesh name=\"block\" file=\"" +
                                      block + "\"/></asset><worldbody><body name=\"block\"><geom type=\"mesh\" "
                                      "mesh=\"block\"/></body><body name=\"cube\" pos=\"0.01 0.02 0.3\" euler=\"12 7 3\">"
                                      "<freejoint/><geom type=\"mesh\" mesh=\"cube\" mass=\"1\"/></body></worldbody></mujoco>",
                                  "mm_drop.xml");
  std::filesystem::remove(cube);
  std::filesystem::remove(block);
  SimOptions o;
  o.dt = 0.01;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  double lowest = 1, max_iterations = 0, iterations = 0;
  const int steps = 120;
  for (int i = 0; i < steps; ++i) {
    StepInfo info;
    ASSERT_TRUE(sim_step(m, o, s, ws, &info));
    max_iterations = std::max<double>(max_iterations, info.iterations);
    iterations += info.iterations;
    Kinematics k;
    kinematics(m, s.qpos, &k);
    for (const Vec3& v : m.geoms[1].mesh->vertices) lowest = std::min(lowest, (k.xpos[2] + k.xmat[2] * v).z());
  }
  EXPECT_GT(lowest, 0.05 - 0.005);
  EXPECT_LT(s.qvel.lpNorm<Eigen::Infinity>(), 2e-2);
  EXPECT_NEAR(s.qpos[2], 0.1, 0.002);  // resting on a face
  std::printf("drop: lowest vertex %.3g mm into the block, %.2f LM iterations per step (max %g), final height %.5f\n",
              1e3 * (0.05 - lowest), iterations / steps, max_iterations, s.qpos[2]);
}

// Zero gravity, no friction: two mesh cubes collide off-centre; the stencil's
// momentum sum(m v) is conserved through the collision (only the solver's residual).
TEST(MeshContact, CollidingMeshCubesConserveMomentum) {
  const std::string a = test::write_grid_box_obj("pliant_mm_mom_a", 0.05, 0.04, 0.03, 2);
  const std::string b = test::write_grid_box_obj("pliant_mm_mom_b", 0.04, 0.04, 0.04, 2);
  const Model m = model_from_mjcf("<mujoco><option gravity=\"0 0 0\"/><asset><mesh name=\"a\" file=\"" + a +
                                      "\"/><mesh name=\"b\" file=\"" + b + "\"/></asset><worldbody><body name=\"a\">"
                                      "<freejoint/><geom type=\"mesh\" mesh=\"a\" mass=\"1\" euler=\"10 20 0\"/></body>"
                                      "<body name=\"b\" pos=\"0.2 0.03 0.01\"><freejoint/><geom type=\"mesh\" mesh=\"b\" "
                                      "mass=\"0.7\" euler=\"0 35 30\"/></body></worldbody></mujoco>",
                                  "mm_momentum.xml");
  std::filesystem::remove(a);
  std::filesystem::remove(b);
  const pair_test::CollisionMomentum r = pair_test::collide_two_free_bodies(m);
  EXPECT_GT(r.most_contacts, 0u);
  EXPECT_LT(r.worst, 1e-6);
  EXPECT_TRUE(r.bounced);
  std::printf("mesh-mesh momentum drift %.3g relative, up to %zu contacts\n", r.worst, r.most_contacts);
}

// ---- Explicit pairs: margin and condim ----

// A 1 kg ball on a slide joint over a fixed box body, through an explicit pair with
// margin 0.01: the penalty acts on margin - distance, so it rests margin higher than
// without (0.1 + margin - m g / k).
TEST(MeshContact, PairMarginRaisesTheRestingBallByTheMargin) {
  const auto rest = [](const std::string& margin) {
    const Model m = model_from_mjcf(
        "<mujoco><worldbody><body name=\"base\"><geom name=\"base\" type=\"box\" size=\"0.2 0.2 0.05\" contype=\"0\" "
        "conaffinity=\"0\"/></body><body name=\"ball\" pos=\"0 0 0.11\"><joint type=\"slide\" axis=\"0 0 1\"/>"
        "<geom name=\"ball\" size=\"0.05\" mass=\"1\" contype=\"0\" conaffinity=\"0\"/></body></worldbody><contact>"
        "<pair geom1=\"ball\" geom2=\"base\" " + margin + "/></contact></mujoco>",
        "margin.xml");
    SimOptions o;
    o.dt = 0.01;
    o.contact.friction = FrictionModel::None;
    State s = state_init(m);
    SimWorkspace ws;
    for (int i = 0; i < 80; ++i) EXPECT_TRUE(sim_step(m, o, s, ws));
    return 0.11 + s.qpos[0];
  };
  const double g_k = 9.81 / ContactOptions().stiffness;
  const double with = rest("margin=\"0.01\""), without = rest("");
  EXPECT_NEAR((0.1 + 0.01 - with) / g_k, 1.0, 0.02);
  EXPECT_NEAR((0.1 - without) / g_k, 1.0, 0.02);
  EXPECT_NEAR(with - without, 0.01, 0.02 * g_k);
}

// A box sliding at 0.5 m/s on a fixed box body through a condim="1" pair keeps its
// velocity (no friction, whatever the scene's model), and stops with condim="3".
TEST(MeshContact, CondimOnePairSlidesWithoutFriction) {
  const auto slide = [](const std::string& condim, FrictionModel f, Integrator in) {
    const Model m = model_from_mjcf("<mujoco><worldbody><body name=\"base\"><geom name=\"base\" type=\"box\" size=\"0.5 0.2 "
                                    "0.05\"/></body><body name=\"box\"><freejoint/><geom name=\"box\" type=\"box\" "
                                    "size=\"0.05 0.05 0.05\" mass=\"1\"/></body></worldbody><contact><pair geom1=\"base\" "
                                    "geom2=\"box\" condim=\"" + condim + "\"/></contact></mujoco>",
                                    "condim.xml");
    SimOptions o;
    o.dt = in == Integrator::Euler ? 0.001 : 0.01;
    o.integrator = in;
    o.contact.friction = f;
    o.contact.mu = 0.5;
    o.contact.damping = in == Integrator::Euler ? 50 : 0;
    State s = state_init(m);
    s.qpos[0] = -0.3;
    s.qpos[2] = 0.1 - 9.81 / (4 * o.contact.stiffness);
    s.qvel[0] = 0.5;
    SimWorkspace ws;
    const int steps = static_cast<int>(std::lround(0.4 / o.dt));
    for (int i = 0; i < steps; ++i) EXPECT_TRUE(sim_step(m, o, s, ws));
    return s.qvel[0];
  };
  EXPECT_NEAR(slide("1", FrictionModel::Coulomb, Integrator::Pbad3), 0.5, 1e-3);
  EXPECT_NEAR(slide("1", FrictionModel::Ck, Integrator::Pbad3), 0.5, 1e-3);
  EXPECT_NEAR(slide("1", FrictionModel::Coulomb, Integrator::Euler), 0.5, 1e-3);
  EXPECT_LT(std::abs(slide("3", FrictionModel::Coulomb, Integrator::Pbad3)), 1e-3);  // v0^2 / (2 mu g) = 2.5 cm
  EXPECT_LT(std::abs(slide("3", FrictionModel::Coulomb, Integrator::Euler)), 2e-2);
}

}  // namespace
}  // namespace pliant::articulated
