// Joint-range penalties (joint_limits.cpp): ball joints' swing cone and twist range
// (exact derivatives by finite differences, the LM diagonal bound, the limits holding
// in a simulation, the scene's "joint_limits" keys) and the hinge range and ball cone
// stopping a pendulum under PBAD and Euler.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pliant/articulated/articulated.h"
#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "pliant/core/error.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

Eigen::Vector4d times_exp(const Eigen::Vector4d& q, const Vec3& dv) {
  const double a = dv.norm();
  const Quat e = a > 0 ? Quat(Eigen::AngleAxisd(a, dv / a)) : Quat::Identity();
  const Quat r = Quat(q[0], q[1], q[2], q[3]) * e;
  return Eigen::Vector4d(r.w(), r.x(), r.y(), r.z());
}

Eigen::Vector4d quat_of(const Vec3& rotvec) {
  const Eigen::Vector4d id(1, 0, 0, 0);
  return times_exp(id, rotvec);
}

TEST(JointLimits, SwingAndTwistDerivativesMatchFiniteDifferences) {
  Joint j;
  j.type = JointType::Ball;
  j.axis = Vec3(0.2, -0.3, 1).normalized();
  const double k = 7;
  struct Case {
    double swing;
    bool twist;
    Vec3 rot;
  };
  const Case cases[] = {{0.3, false, Vec3(0.5, 0.2, 0.1)},   // swing only
                        {-1, true, Vec3(0.1, -0.2, 0.9)},    // twist beyond the upper bound
                        {-1, true, Vec3(0.3, 0.1, -1.1)},    // below the lower bound
                        {0.2, true, Vec3(-0.6, 0.4, 1.0)},   // both
                        {0.2, true, Vec3(1.4, -1.0, -2.0)}}; // large rotation, both
  for (const Case& c : cases) {
    j.swing_max = c.swing;
    j.twist_limited = c.twist;
    j.twist_min = -0.4;
    j.twist_max = 0.5;
    const Eigen::Vector4d q = quat_of(c.rot);
    Vec3 g;
    Mat3 h;
    const double e0 = ball_swing_twist_penalty(j, k, q, &g, &h);
    ASSERT_GT(e0, 0) << c.rot.transpose();
    const auto f = [&](const Vec3& dv) { return ball_swing_twist_penalty(j, k, times_exp(q, dv), nullptr, nullptr); };
    const double hg = 1e-6, hh = 1e-4;
    for (int a = 0; a < 3; ++a) {
      const Vec3 ea = Vec3::Unit(a);
      EXPECT_NEAR(g[a], (f(hg * ea) - f(-hg * ea)) / (2 * hg), 1e-7 * (1 + g.norm())) << c.rot.transpose();
      for (int b = 0; b < 3; ++b) {
        const Vec3 eb = Vec3::Unit(b);
        const double fd = (f(hh * (ea + eb)) - f(hh * (ea - eb)) - f(hh * (eb - ea)) + f(-hh * (ea + eb))) / (4 * hh * hh);
        EXPECT_NEAR(h(a, b), fd, 1e-5 * (1 + h.norm())) << c.rot.transpose() << " (" << a << "," << b << ")";
      }
    }
    // The LM diagonal dominates the exact Hessian.
    const Vec3 d = hessian_diagonal_bound(h);
    const Mat3 gap = Mat3(d.asDiagonal()) - h;
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat3>(gap).eigenvalues().minCoeff(), -1e-12);
    EXPECT_GE(d.minCoeff(), 0);
  }
  // Inside both ranges: nothing.
  j.swing_max = 0.5;
  Vec3 g;
  EXPECT_EQ(ball_swing_twist_penalty(j, k, quat_of(Vec3(0.1, 0, 0.2)), &g, nullptr), 0);
  EXPECT_EQ(g.norm(), 0);
}

TEST(JointLimits, SwingConeAndTwistRangeHoldInASimulation) {
  // A ball pendulum hanging along -z (axis z): thrown sideways (swing) or spun about
  // its axis (twist); the free joint reaches ~1.4 rad / 1.5 rad, the limited one stops
  // near its bound (stiff penalty).
  Model m = model_from_mjcf(
      "<mujoco><worldbody><body><joint name=\"b\" type=\"ball\"/><inertial pos=\"0 0 -1\" mass=\"1\" "
      "diaginertia=\"0.01 0.01 0.01\"/></body></worldbody></mujoco>",
      "ball.xml");
  SimOptions o;
  o.dt = 0.005;
  o.contact.limit_stiffness = 1e4;
  const auto run = [&](const Model& model, const Vec3& w0, double* swing, double* twist) {
    State s = state_init(model);
    s.qvel = w0;
    SimWorkspace ws;
    *swing = 0, *twist = 0;
    while (s.time < 0.5) {
      ASSERT_TRUE(sim_step(model, o, s, ws));
      Eigen::Vector4d q = s.qpos.head<4>().normalized();
      if (q[0] < 0) q = -q;
      const Mat3 r = Quat(q[0], q[1], q[2], q[3]).toRotationMatrix();
      *swing = std::max(*swing, std::acos(std::clamp(r(2, 2), -1.0, 1.0)));
      *twist = std::max(*twist, std::abs(2 * std::atan2(q[3], q[0])));
    }
  };
  double swing, twist;
  run(m, Vec3(3.2, 2.4, 0), &swing, &twist);
  EXPECT_GT(swing, 1.2);
  run(m, Vec3(0, 0, 3), &swing, &twist);
  EXPECT_GT(twist, 1.4);
  m.joints[0].swing_max = 0.5;
  m.joints[0].twist_limited = true;
  m.joints[0].twist_min = -0.3;
  m.joints[0].twist_max = 0.3;
  run(m, Vec3(3.2, 2.4, 0), &swing, &twist);
  EXPECT_LT(swing, 0.6);
  EXPECT_GT(swing, 0.45);
  run(m, Vec3(0, 0, 3), &swing, &twist);
  EXPECT_LT(twist, 0.36);
  EXPECT_GT(twist, 0.28);
}

Scene limits_scene_of(const nlohmann::json& limits) {
  const nlohmann::json j = {{"pliant", 1}, {"kind", "articulated"},
                            {"model", {{"bodies", {{{"name", "p"}, {"pos", {0, 0, 0}},
                                                    {"joints", {{{"type", "ball"}, {"name", "shoulder"}, {"axis", {0, 1, 0}}}}},
                                                    {"geoms", {{{"type", "sphere"}, {"size", {0.1}}, {"mass", 1}}}}}}}}},
                            {"joint_limits", limits}};
  return parse_scene(j.dump(), "s.json", PLIANT_ASSETS_DIR "/scenes");
}

std::string limits_error_of(const nlohmann::json& limits) {
  try {
    articulated_compile(limits_scene_of(limits));
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "no error";
}

TEST(JointLimits, SceneKeysSetTheLimitsAndBadOnesNameTheirPointer) {
  const ArticulatedScene a = articulated_compile(limits_scene_of({{"shoulder", {{"swing", 0.7}, {"twist", {-0.2, 0.4}}}}}));
  EXPECT_EQ(a.model.joints[0].swing_max, 0.7);
  EXPECT_TRUE(a.model.joints[0].twist_limited);
  EXPECT_EQ(a.model.joints[0].twist_min, -0.2);
  EXPECT_EQ(a.model.joints[0].twist_max, 0.4);
  EXPECT_NE(limits_error_of({{"shouldr", {{"swing", 0.7}}}}).find("/joint_limits/shouldr | no ball joint named \"shouldr\"; did you mean \"shoulder\""),
            std::string::npos);
  EXPECT_NE(limits_error_of({{"shoulder", {{"swing", -1}}}}).find("/joint_limits/shoulder/swing"), std::string::npos);
  EXPECT_NE(limits_error_of({{"shoulder", {{"twist", {0.4, -0.2}}}}}).find("/joint_limits/shoulder/twist | lower bound"),
            std::string::npos);
  EXPECT_NE(limits_error_of({{"shoulder", {{"swng", 0.3}}}}).find("/joint_limits/shoulder/swng"), std::string::npos);
}


TEST(Sim, JointRangeStopsThePendulumAtItsLimit) {
  // A pendulum thrown at 5 rad/s towards a 0.5 rad limit: it stops there (penetration
  // of the stiff penalty only) and bounces back.
  Model m = test::pendulum(1.0);
  m.joints[0].limited = true;
  m.joints[0].range_min = -0.5;
  m.joints[0].range_max = 0.5;
  for (Integrator integ : {Integrator::Pbad3, Integrator::Euler}) {
    SimOptions o;
    o.integrator = integ;
    o.dt = integ == Integrator::Euler ? 0.0005 : 0.005;
    o.contact.limit_stiffness = 1e5;
    State s = state_init(m);
    s.qvel[0] = 5;
    SimWorkspace ws;
    const double e0 = state_energy(m, o, s, ws).total;
    double qmax = 0;
    while (s.time < 0.5) {
      ASSERT_TRUE(sim_step(m, o, s, ws));
      qmax = std::max(qmax, s.qpos[0]);
    }
    EXPECT_GT(qmax, 0.5) << integrator_name(integ);
    EXPECT_LT(qmax, 0.5 + 0.03) << integrator_name(integ);  // free flight would reach 2.1 rad
    // Euler keeps the bounce's energy; PBAD's backward stencil damps the stiff
    // penalty mode (omega dt ~ 1.6 here) but never adds energy.
    const double e1 = state_energy(m, o, s, ws).total, kinetic0 = 12.5;
    if (integ == Integrator::Euler) EXPECT_NEAR(e1, e0, 0.05 * kinetic0);
    else EXPECT_LT(e1, e0 + 0.01 * kinetic0);
  }
}

TEST(Sim, BallJointConeStopsTheSwing) {
  // A ball-jointed pendulum thrown sideways at 4 rad/s with a 0.5 rad cone: the total
  // rotation angle stops at the cone (stiff penalty) instead of the free swing's ~1.4 rad.
  const Model free_model = model_from_mjcf(
      "<mujoco><worldbody><body><joint type=\"ball\"/><inertial pos=\"0 0 -1\" mass=\"1\" "
      "diaginertia=\"1e-4 1e-4 1e-4\"/></body></worldbody></mujoco>",
      "ball.xml");
  Model m = free_model;
  m.joints[0].limited = true;
  m.joints[0].range_max = 0.5;
  for (Integrator integ : {Integrator::Pbad3, Integrator::Euler}) {
    SimOptions o;
    o.integrator = integ;
    o.dt = integ == Integrator::Euler ? 0.0005 : 0.005;
    o.contact.limit_stiffness = 1e5;
    double amax = 0;
    for (const Model* model : {&free_model, static_cast<const Model*>(&m)}) {
      State s = state_init(*model);
      s.qvel << 3.2, 2.4, 0;  // local angular velocity, 4 rad/s about a tilted axis
      SimWorkspace ws;
      double angle = 0;
      while (s.time < 0.6) {
        ASSERT_TRUE(sim_step(*model, o, s, ws));
        const Quat q(s.qpos[0], s.qpos[1], s.qpos[2], s.qpos[3]);
        angle = std::max(angle, Eigen::AngleAxisd(q.normalized()).angle());
      }
      if (model == &free_model) {
        EXPECT_GT(angle, 1.2) << integrator_name(integ);
      }
      amax = angle;
    }
    EXPECT_GT(amax, 0.5) << integrator_name(integ);
    EXPECT_LT(amax, 0.5 + 0.03) << integrator_name(integ);
  }
}


// A hinge spring (MJCF stiffness / springref) without gravity: a rotor of inertia
// I = 0.01 kg m^2 (+ armature 0.0025) on k = 0.5 N m/rad oscillates about springref
// with the period 2 pi sqrt(I / k) = 0.993 s, under PBAD and RK4; the spring's energy is
// in the state's potential (total energy kept); ref shifts the start (qpos0), not the
// spring. Without the spring term (stiffness ignored) the rotor would not move.
TEST(JointLimits, HingeSpringOscillatesWithTheAnalyticPeriod) {
  const Model m = model_from_mjcf(
      R"(<mujoco><compiler angle="radian"/><option gravity="0 0 0"/><worldbody><body>
        <joint axis="0 0 1" stiffness="0.5" springref="-0.2" ref="0.1" armature="0.0025" limited="false"/>
        <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>)",
      "spring.xml");
  ASSERT_NEAR(m.qpos0[0], 0.1, 1e-15);
  const double period = 2 * M_PI * std::sqrt(0.0125 / 0.5);
  for (Integrator integ : {Integrator::Pbad3, Integrator::Rk4}) {
    const SimOptions o = test::contact_free_options(integ, 0.001);
    State s = state_init(m);
    SimWorkspace ws;
    const double e0 = state_energy(m, o, s, ws).total;
    EXPECT_NEAR(e0, 0.5 * 0.5 * 0.3 * 0.3, 1e-12);  // 1/2 k (q0 - springref)^2, at rest
    // Upward crossings of springref (at 0.75, 1.75, 2.75 periods): the first and third.
    std::vector<double> up;
    double prev = s.qpos[0] + 0.2;
    while (s.time < 3.5 * period) {
      ASSERT_TRUE(sim_step(m, o, s, ws));
      const double x = s.qpos[0] + 0.2;
      if (prev < 0 && x >= 0) up.push_back(s.time - o.dt * x / (x - prev));
      prev = x;
    }
    ASSERT_GE(up.size(), 3u) << integrator_name(integ);
    EXPECT_NEAR((up[2] - up[0]) / 2, period, 0.002 * period) << integrator_name(integ);
    EXPECT_NEAR(state_energy(m, o, s, ws).total, e0, 0.01 * e0) << integrator_name(integ);
  }
}

}  // namespace
}  // namespace pliant::articulated
