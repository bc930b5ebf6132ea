// Contact: body-body pairs with a mesh geom (mesh against sphere, capsule, box, mesh).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"
#include "pair_fixture.h"
#include "sim_internal.h"
#include "contact_internal.h"

namespace pliant::articulated {
namespace {

using namespace pair_test;

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
  // kMaxTermsPerBodyPair terms, merged per body pair in lm_solve (lm_solve.cpp);
  // the LM matrix's body-body part still equals the finite-difference one.
  EXPECT_GT(expect_mesh_pair_derivatives("0.01 0.005 -0.097", "<geom type=\"box\" size=\"0.2 0.2 0.05\" euler=\"0.05 -0.03 0\"/>", "0 0 0"),
            static_cast<size_t>(kMaxTermsPerBodyPair));
}

// mesh_against's pre-test of the mesh's samples against a box's / capsule's bounding
// box (grown by the margin) keeps every contact of the plain loop over all samples, in
// its order, over random poses with the two shapes overlapping or near.
TEST(Contact, MeshSamplePreTestKeepsEveryContactOfTheFullLoop) {
  const std::string obj = test::write_box_obj("pliant_mesh_pretest", 0.1, 0.07, 0.05);
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"m\" file=\"" + obj +
                                      "\"/></asset><worldbody><body name=\"a\"><freejoint/><geom type=\"mesh\" mesh=\"m\"/></body>"
                                      "<body name=\"b\" pos=\"1 0 0\"><freejoint/><geom type=\"box\" size=\"0.06 0.03 0.02\"/></body>"
                                      "<body name=\"c\" pos=\"2 0 0\"><freejoint/><geom type=\"capsule\" size=\"0.02 0.07\"/></body>"
                                      "</worldbody></mujoco>",
                                  "pretest.xml");
  std::filesystem::remove(obj);
  const std::vector<GeomPair> pairs = contact_geom_pairs(m);
  const MeshCollider* mc = nullptr;
  for (const GeomPair& p : pairs) mc = p.mesh_a ? p.mesh_a.get() : p.mesh_b ? p.mesh_b.get() : mc;
  ASSERT_NE(mc, nullptr);
  using contact_internal::Placed;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto rotation = [&] { return Quat(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix(); };
  size_t kept = 0;
  for (int shape = 1; shape <= 2; ++shape)
    for (int trial = 0; trial < 300; ++trial) {
      const Placed mesh{&m.geoms[0], Vec3(u(rng), u(rng), u(rng)), rotation()};
      const Placed s{&m.geoms[shape], mesh.c + 0.12 * Vec3(u(rng), u(rng), u(rng)), rotation()};
      const double margin = trial % 3 == 0 ? 0.01 : 0.0;
      std::vector<PairContact> out, full;
      contact_internal::mesh_against(mesh, *mc, s, margin, &out);
      for (const Vec3& v : mc->samples)
        contact_internal::point_against(s, mesh.g->body, mesh.c + mesh.r * v, margin, &full);
      std::vector<PairContact> samples;
      for (const PairContact& c : out)
        if (c.body_a == s.g->body) samples.push_back(c);
      ASSERT_EQ(samples.size(), full.size()) << shape << " " << trial;
      for (size_t i = 0; i < full.size(); ++i) {
        EXPECT_EQ(samples[i].depth, full[i].depth);
        EXPECT_EQ(samples[i].point, full[i].point);
      }
      kept += full.size();
    }
  EXPECT_GT(kept, 500u);
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

}  // namespace
}  // namespace pliant::articulated
