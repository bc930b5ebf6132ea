// Contact: body-body pairs of spheres, capsules and boxes; pair filters and explicit pairs.
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
// is inside the other; each edge's deepest point in the other box (at the kink between
// its two faces: mixed normal, gain < 1) pushes the upper box up.
TEST(Contact, EdgeAcrossEdgeGradientMatchesFiniteDifferences) {
  const std::string ridge_x = "<geom type=\"box\" size=\"0.1 0.03 0.03\" euler=\"45 2 3\"/>";
  const std::string ridge_y = "<geom type=\"box\" size=\"0.03 0.1 0.03\" euler=\"-4 43 1\"/>";
  const Model boxes = two_bodies("0 0 0", ridge_x, "0.004 -0.003 0.083", ridge_y);
  const std::vector<PairContact> c = pair_contacts_at(boxes, state_init(boxes).qpos);
  ASSERT_EQ(c.size(), 2u);
  for (const PairContact& p : c) EXPECT_GT(std::abs(p.normal.z()), 0.95);
  EXPECT_EQ(expect_pair_derivatives(boxes), 2u);
}

// The upper box rests on the fixed lower one's edge (symmetric, so it balances) at the
// penalty depth m g / k below the touching height 2 h: the two edges' contacts (each
// the other box's two faces mixed, gain 1/sqrt 2, at depth d / sqrt 2) carry half the
// weight each; without them it falls through.
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
  EXPECT_EQ(pair_contacts_at(m, s.qpos).size(), 2u);
  const double ratio = (2 * h - s.qpos[2]) / (m.bodies[2].mass * 9.81 / o.contact.stiffness);
  EXPECT_NEAR(ratio, 1.0, 0.05);
  std::printf("crosswise boxes: resting depth / (m g / k) = %.4f\n", ratio);
}

// A box lying flat across another box's edge (the pile's box_mid on box_low: three
// corners in the lower box's face, the fourth overhanging) touches on a polygon: its
// three corners and the two points where its edges cross the lower box's edge, each
// found from both edges (7 contacts). The former one contact at the pressed edge's
// deepest point (in place of a corner) jumped by the pressed length as the box tilted
// by 1e-6 rad either way: LM stopped on that kink every step, |gradient| 0.58 N.
TEST(Contact, BoxLyingAcrossAnEdgeRestsAtASmoothMinimum) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody><geom type="plane"/>
    <body name="low" pos="0 0 0.04998"><freejoint/><geom type="box" size="0.15 0.1 0.05" mass="2"/></body>
    <body name="top" pos="0.036 0.022 0.1405" quat="0.9659258 0 0 0.2588190"><freejoint/>
      <geom type="box" size="0.08 0.06 0.04" mass="1"/></body>
    </worldbody></mujoco>)", "across.xml");
  SimOptions o;
  o.dt = 0.01;
  o.contact.mu = 0.6;
  o.contact.self_collision = true;
  State s = state_init(m);
  SimWorkspace ws;
  double iterations = 0, worst_gradient = 0;
  for (int i = 0; i < 100; ++i) {
    StepInfo info;
    ASSERT_TRUE(sim_step(m, o, s, ws, &info));
    if (i < 50) continue;
    iterations += info.iterations;
    worst_gradient = std::max(worst_gradient, info.energy_residual);
  }
  EXPECT_EQ(pair_contacts_at(m, s.qpos).size(), 7u);
  EXPECT_NEAR(s.qpos[9], 0.14, 2e-4);  // on the lower box, not in it
  EXPECT_LT(worst_gradient, 1e-6);     // LM's grad_tol 2.9e-6 N (3 kg)
  EXPECT_LT(iterations / 50, 1.5);
  std::printf("box across an edge: %zu contacts, z %.5f, %.2f LM it/step at rest, |gradient| <= %.2g\n",
              pair_contacts_at(m, s.qpos).size(), s.qpos[9], iterations / 50, worst_gradient);
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

}  // namespace
}  // namespace pliant::articulated
