// Contact: a capsule's side against a box (across an edge, across a face), measured
// geometrically; gradient and energy continuity of the segment's deepest-point contact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "pair_fixture.h"

namespace pliant::articulated {
namespace {

using namespace pair_test;

// A fixed box (MJCF geom attributes) and a free capsule r 0.02 dropped on it from
// `pose` (pos + euler); PBAD3 dt 0.01, `steps` steps. Returns the largest geometric
// overlap of the capsule in the box over the last `last` steps, the final speed and height.
struct CapBoxRest {
  double overlap = 0, speed = 0, iterations = 0, z = 0;  // z: the capsule centre's final height
};
// static_box: the box a world geom (an obstacle; self_collision off), else a jointless
// body (a body pair). rk4: RK4 at dt 1e-3 instead.
CapBoxRest capbox_drop(const std::string& box, const std::string& pose, double half, int steps, int last,
                       bool static_box = false, bool rk4 = false) {
  const std::string base = static_box ? "<geom type=\"box\" " + box + "/>"
                                      : "<body name=\"base\"><geom type=\"box\" " + box + "/></body>";
  const Model m = model_from_mjcf("<mujoco><worldbody>" + base + "<body name=\"cap\" " + pose +
                                      "><freejoint/><geom type=\"capsule\" size=\"0.02 " + std::to_string(half) +
                                      "\" euler=\"0 90 0\" mass=\"0.5\"/></body></worldbody></mujoco>",
                                  "capbox.xml");
  SimOptions o;
  o.dt = rk4 ? 1e-3 : 0.01;
  o.integrator = rk4 ? Integrator::Rk4 : Integrator::Pbad3;
  if (rk4) o.contact.damping = 50;  // the explicit spring-damper settles
  o.contact.self_collision = !static_box;
  State s = state_init(m);
  SimWorkspace ws;
  CapBoxRest r;
  for (int i = 0; i < steps; ++i) {
    StepInfo info;
    if (!sim_step(m, o, s, ws, &info)) {
      ADD_FAILURE() << "step " << i;
      break;
    }
    r.iterations += info.iterations;
    if (i >= steps - last) r.overlap = std::max(r.overlap, deepest_capsule_in_box(m, s.qpos));
  }
  r.iterations /= steps;
  r.speed = s.qvel.head<3>().norm();
  r.z = s.qpos[2];
  return r;
}

// Across edges: a capsule dropped across a plank (both ends overhanging, axis
// perpendicular to its top edges) and across a ridge (a box turned 45 degrees about
// the capsule's perpendicular: one edge). Its end spheres are off the box and no box
// corner comes near its axis, so before the segment's contact it fell through (to
// the ground it does not have here; final height -0.5 m and below). At rest it sits
// at the penalty depth (m g / k = 0.05 mm on one contact).
TEST(ContactCapsuleBox, CapsuleAcrossBoxEdgesRestsOnThem) {
  const CapBoxRest plank = capbox_drop("size=\"0.03 0.1 0.05\"", "pos=\"0.004 0 0.075\"", 0.12, 100, 30);
  const CapBoxRest ridge =
      capbox_drop("size=\"0.05 0.1 0.05\" euler=\"0 45 0\"", "pos=\"0 0 0.0925\"", 0.12, 50, 10);
  std::printf("capsule across a plank: overlap %.3g m, speed %.3g m/s, %.2f LM it/step; across a ridge: %.3g m, %.2f\n",
              plank.overlap, plank.speed, plank.iterations, ridge.overlap, ridge.iterations);
  EXPECT_LT(plank.overlap, 1e-3);
  EXPECT_LT(plank.speed, 1e-2);
  EXPECT_NEAR(plank.z, 0.05 + 0.02, 1e-3);  // on the plank's top, not through it
  EXPECT_LT(ridge.overlap, 1e-3);
  EXPECT_NEAR(ridge.z, 0.05 * std::sqrt(2.0) + 0.02, 1e-3);
}

// The same against a static box (a world geom: the obstacle path has the end spheres,
// the pair path the box's edges and the deepest point) with PBAD3, and with RK4 (the
// explicit integrators take the same pair contacts) across the body plank: before,
// both fell through.
TEST(ContactCapsuleBox, CapsuleAcrossAStaticBoxAndWithRk4RestsOnIt) {
  const CapBoxRest fixed = capbox_drop("size=\"0.03 0.1 0.05\"", "pos=\"0.004 0 0.075\"", 0.12, 100, 30, true);
  const CapBoxRest rk4 = capbox_drop("size=\"0.03 0.1 0.05\"", "pos=\"0.004 0 0.075\"", 0.12, 400, 100, false, true);
  std::printf("capsule across a static plank: overlap %.3g m, z %.5f, %.2f LM it/step; RK4 across the body plank: "
              "overlap %.3g m, z %.5f\n",
              fixed.overlap, fixed.z, fixed.iterations, rk4.overlap, rk4.z);
  EXPECT_LT(fixed.overlap, 1e-3);
  EXPECT_LT(fixed.speed, 1e-2);
  EXPECT_NEAR(fixed.z, 0.07, 1e-3);
  EXPECT_LT(rk4.overlap, 1e-3);
  EXPECT_NEAR(rk4.z, 0.07, 1e-3);
}

// PBAD's gradient (penalty, friction on the pair anchors) against central differences
// for a capsule across a static box's edge: the pair contact with the world (body 0
// takes no force), with an end sphere on the obstacle path too.
TEST(ContactCapsuleBox, StaticBoxSideGradientMatchesFiniteDifferences) {
  const Model m = model_from_mjcf(R"(<mujoco><worldbody><geom type="box" size="0.1 0.1 0.05"/>
    <body name="cap" pos="0.12 0.01 0.0675" euler="10 92 30"><freejoint/><geom type="capsule" size="0.02 0.1"/></body>
    </worldbody></mujoco>)", "capbox.xml");
  SimOptions o;
  o.dt = 0.01;
  State s = state_init(m);
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  ASSERT_TRUE(p.any_pairs);
  EXPECT_FALSE(p.pair_anchors.empty());
  VecX q = s.qpos;
  VecX dv(m.nv);
  for (int i = 0; i < m.nv; ++i) dv[i] = 0.0015 * std::sin(1.3 * i + 0.4);
  qpos_integrate(m, q, dv, 1.0);
  const auto moved = [&](int i, double h) {
    VecX e = VecX::Zero(m.nv), qq = q;
    e[i] = h;
    qpos_integrate(m, qq, e, 1.0);
    return qq;
  };
  pbad_evaluate(m, o, s, p, q, ws);
  const VecX g = ws.grad;
  EXPECT_FALSE(ws.pair_contacts.empty());
  for (int i = 0; i < m.nv; ++i) {
    const double fd = (pbad_evaluate(m, o, s, p, moved(i, 1e-7), ws) - pbad_evaluate(m, o, s, p, moved(i, -1e-7), ws)) / 2e-7;
    EXPECT_NEAR(g[i], fd, 1e-6 * (1 + g.norm())) << i;
  }
}

// Across a face diagonally (30 degrees to its edges), ends outside the face: the
// segment over the face carries it; before, it fell through the face.
TEST(ContactCapsuleBox, CapsuleLyingDiagonallyAcrossAFaceRestsOnIt) {
  const CapBoxRest r =
      capbox_drop("size=\"0.1 0.1 0.05\"", "pos=\"0.002 0 0.075\" euler=\"0 0 30\"", 0.15, 100, 30);
  std::printf("capsule across a face: overlap %.3g m, speed %.3g m/s, %.2f LM it/step\n", r.overlap, r.speed,
              r.iterations);
  EXPECT_LT(r.overlap, 1e-3);
  EXPECT_LT(r.speed, 1e-2);
  EXPECT_NEAR(r.z, 0.05 + 0.02, 1e-3);
}

// The contacts' energy sum d^2 as a capsule over a box edge pitches so that the
// segment's nearest point slides from the interior to its end (and the end sphere
// takes over): no jump; and PBAD's gradient matches central differences with the
// segment's contact and an end sphere both active.
TEST(ContactCapsuleBox, SegmentContactIsContinuousAndItsGradientExact) {
  const auto contacts_at = [](double pitch, double x) {
    const Model m = two_bodies("0 0 0", "<geom type=\"box\" size=\"0.1 0.1 0.05\"/>",
                               std::to_string(x) + " 0.01 0.068",
                               "<geom type=\"capsule\" size=\"0.02 0.1\" euler=\"0 " + std::to_string(90 + pitch) +
                                   " 0\"/>");
    return pair_contacts_at(m, state_init(m).qpos);
  };
  const auto energy = [](const std::vector<PairContact>& c) {
    double e = 0;
    for (const PairContact& p : c) e += p.depth * p.depth;
    return e;
  };
  // Centre at x 0.12: the capsule's inner end over the face, its outer part beyond the
  // edge x = 0.1; pitching from -4 to 4 degrees hands the touch from the inner end
  // sphere to the edge's contact.
  double worst = 0, emax = 0;
  double prev = energy(contacts_at(-4, 0.12));
  for (int i = 1; i <= 800; ++i) {
    const double e = energy(contacts_at(-4 + 0.01 * i, 0.12));
    worst = std::max(worst, std::abs(e - prev));
    emax = std::max(emax, e);
    prev = e;
  }
  std::printf("capsule-box energy: largest change per 0.01 degree %.3g of max %.3g\n", worst, emax);
  EXPECT_GT(emax, 0);
  EXPECT_LT(worst, 0.02 * emax);
  // Gradient: capsule across the edge, tilted and turned.
  EXPECT_GE(expect_pair_derivatives(two_bodies("0 0 0", "<geom type=\"box\" size=\"0.1 0.1 0.05\"/>",
                                               "0.12 0.01 0.0675",
                                               "<geom type=\"capsule\" size=\"0.02 0.1\" euler=\"10 92 30\"/>")),
            1u);
}

// A box edge pressed into another box's face with both its corners outside (a box
// leaning on another's edge: before, no contact and the box sank): gradient matching
// central differences, here with the deepest point at a kink between two faces of the
// other box (mixed normal, gain < 1).
TEST(ContactCapsuleBox, BoxEdgeIntoAFaceGradientMatchesFiniteDifferences) {
  const std::string slab = "<geom type=\"box\" size=\"0.1 0.1 0.05\"/>";
  const std::string bar = "<geom type=\"box\" size=\"0.2 0.02 0.02\" euler=\"45 3 2\"/>";
  const Model m = two_bodies("0 0 0", slab, "0.01 0.02 0.077", bar);
  const std::vector<PairContact> c = pair_contacts_at(m, state_init(m).qpos);
  ASSERT_GE(c.size(), 1u);
  double least_gain = 1;
  for (const PairContact& p : c) least_gain = std::min(least_gain, p.gain);
  std::printf("box edge into a face: %zu contacts, least gain %.4f\n", c.size(), least_gain);
  EXPECT_LT(least_gain, 0.9);
  EXPECT_GE(expect_pair_derivatives(m), 1u);
}

}  // namespace
}  // namespace pliant::articulated
