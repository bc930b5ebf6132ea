// Sliding friction at a sphere's / capsule's contact point (condim 3, pbad_energy.cpp
// contact_point_friction; Euler/RK4 on the contact point's velocity): a ball rolling
// on a floor keeps rolling, a ball thrown sliding without spin ends rolling at 5/7 of
// its speed (PBAD3 and RK4), and PBAD's gradient matches finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

constexpr double kRollG = 9.81, kRollR = 0.1;

// A 1 kg solid sphere of radius 0.1 m resting on a floor (at the penalty's equilibrium
// depth m g / k), condim 3 (the default), Coulomb mu; x speed v0, spin w0 about +y.
struct RollRun {
  double v, w;  // x speed and spin about +y at t_end
};
RollRun roll_run(Integrator integ, double dt, double mu, double v0, double w0, double t_end) {
  const Model m = model_from_mjcf(
      "<mujoco><option gravity=\"0 0 -9.81\"/><worldbody><geom type=\"plane\" size=\"5 5 0.1\"/><body><freejoint/>"
      "<geom type=\"sphere\" size=\"0.1\" mass=\"1\"/></body></worldbody></mujoco>",
      "roll.xml");
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  o.contact.mu = mu;
  if (integ == Integrator::Rk4) o.contact.damping = 20, o.contact.slip_eps = 1e-5;
  State s = state_init(m);
  s.qpos[2] = kRollR - kRollG / o.contact.stiffness;
  s.qvel[0] = v0;
  s.qvel[4] = w0;  // body y = world y while it rolls about it
  SimWorkspace ws;
  while (s.time < t_end - 1e-9)
    if (!sim_step(m, o, s, ws)) {
      ADD_FAILURE() << "step failed at t " << s.time;
      break;
    }
  return {s.qvel[0], s.qvel[4]};
}

// Rolling without slipping at 0.5 m/s: no force at the contact point is needed, so
// without rolling friction it keeps v0 (the centre's slip used to brake it to rest
// within 1.4 cm in PBAD).
TEST(RollingContact, BallRollingOnAFloorKeepsRolling) {
  for (Integrator integ : {Integrator::Pbad3, Integrator::Rk4}) {
    const double v0 = 0.5;
    const RollRun r = roll_run(integ, integ == Integrator::Rk4 ? 1e-3 : 0.01, 1.0, v0, v0 / kRollR, 1.0);
    std::printf("rolling (integrator %d): v %.5f w r %.5f m/s after 1 s\n", static_cast<int>(integ), r.v, r.w * kRollR);
    EXPECT_NEAR(r.v, v0, 0.015 * v0) << static_cast<int>(integ);
    EXPECT_NEAR(r.w * kRollR, r.v, 0.01 * v0) << static_cast<int>(integ);
  }
}

// Thrown sliding at v0 without spin: friction mu m g decelerates the centre and spins
// the ball up (I = 2/5 m r^2) until v = w r, reached at v = 5/7 v0 after
// 2 v0 / (7 mu g) = 0.058 s (mu 0.5, v0 1 m/s); then it rolls on.
TEST(RollingContact, SlidingBallEndsRollingAtFiveSeventhsOfItsSpeed) {
  for (Integrator integ : {Integrator::Pbad3, Integrator::Rk4}) {
    const double v0 = 1.0;
    const RollRun r = roll_run(integ, integ == Integrator::Rk4 ? 1e-3 : 0.01, 0.5, v0, 0, 0.4);
    std::printf("thrown (integrator %d): v %.5f w r %.5f m/s, 5/7 v0 = %.5f\n", static_cast<int>(integ), r.v,
                r.w * kRollR, 5.0 / 7.0 * v0);
    EXPECT_NEAR(r.v, 5.0 / 7.0 * v0, 0.02 * 5.0 / 7.0 * v0) << static_cast<int>(integ);
    EXPECT_NEAR(r.w * kRollR, r.v, 0.01 * v0) << static_cast<int>(integ);
  }
}

// Central differences of PBAD's energy against its gradient with sliding friction at
// contact points a reach inside the body: a sphere and a capsule (end spheres) on the
// floor, and a box with a margin (corners, reach = margin), all turning.
TEST(RollingContact, ContactPointFrictionGradientMatchesFiniteDifferences) {
  const Model m = model_from_mjcf(
      R"(<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
        <body pos="0 0 0.098"><freejoint/><geom size="0.1"/></body>
        <body pos="1 0 0.048" euler="0 90 0"><freejoint/><geom type="capsule" size="0.05 0.2"/></body>
        <body pos="-1 0 0.105"><freejoint/><geom type="box" size="0.1 0.1 0.1" margin="0.01"/></body>
        </worldbody></mujoco>)",
      "rollfd.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.8;
  State s = state_init(m);
  for (int i = 0; i < m.nv; ++i) s.qvel[i] = 0.3 * std::cos(0.9 * i + 0.2);
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  VecX q = p.q;
  VecX dq(m.nv);
  for (int i = 0; i < m.nv; ++i) dq[i] = 0.02 * std::sin(1.3 * i + 0.4);  // slips >> slip_eps
  qpos_integrate(m, q, dq, 1.0);
  pbad_evaluate(m, o, s, p, q, ws);
  const VecX grad = ws.grad;
  // Friction's share of the gradient: the same evaluation without it.
  SimOptions o0 = o;
  o0.contact.friction = FrictionModel::None;
  pbad_evaluate(m, o0, s, p, q, ws);
  const double friction_share = (grad - ws.grad).norm();
  EXPECT_GT(friction_share, 10.0);
  std::printf("friction share of |grad| %.4g\n", friction_share);
  const double h = 1e-6;
  VecX fd(m.nv);
  for (int i = 0; i < m.nv; ++i) {
    VecX qp = q, qm = q;  // free joints: quaternions, so step along each dof
    qpos_integrate(m, qp, VecX::Unit(m.nv, i), h);
    qpos_integrate(m, qm, VecX::Unit(m.nv, i), -h);
    fd[i] = (pbad_evaluate(m, o, s, p, qp, ws) - pbad_evaluate(m, o, s, p, qm, ws)) / (2 * h);
  }
  std::printf("|fd - grad| %.3g, |grad| %.4g\n", (fd - grad).norm(), grad.norm());
  EXPECT_LT((fd - grad).norm(), 1e-4 * friction_share) << "fd " << fd.transpose() << "\ngrad " << grad.transpose();
}

}  // namespace
}  // namespace pliant::articulated
