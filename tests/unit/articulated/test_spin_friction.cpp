// Torsional and rolling friction (condim 4 / 6, spin_friction.cpp): a spinning sphere
// stops after the analytic time, a rolling ball decelerates at the analytic rate and
// stops after the analytic distance (PBAD and RK4), PBAD's gradient with the new
// potential matches finite differences. (MuJoCo's compiled values:
// test_mujoco_reference.cpp; bad values: test_geom_contact.cpp, test_mjcf.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "pliant/articulated/contact.h"
#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "mesh_fixture.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

constexpr double kSpinG = 9.81;

// A 1 kg sphere of radius 0.1 m resting on a floor (at the penalty's equilibrium
// depth), the floor's geom attributes `floor_attrs`.
Model spin_sphere_model(const std::string& floor_attrs) {
  return model_from_mjcf(
      "<mujoco><option gravity=\"0 0 -9.81\"/><worldbody><geom type=\"plane\" size=\"5 5 0.1\" " + floor_attrs +
          "/><body><freejoint/><geom type=\"sphere\" size=\"0.1\" mass=\"1\"/></body></worldbody></mujoco>",
      "spin.xml");
}

State spin_sphere_state(const Model& m, const SimOptions& o) {
  State s = state_init(m);
  s.qpos[2] = 0.1 - kSpinG / o.contact.stiffness;  // resting depth m g / k
  return s;
}

// Time at which the spin about the vertical (qvel[5], the body z = world z) first
// drops below 1% of w0, linearly interpolated; also the spin at t_probe.
double spin_stop_time(const Model& m, const SimOptions& o, double w0, double t_end, double t_probe, double* w_probe) {
  State s = spin_sphere_state(m, o);
  s.qvel[5] = w0;
  SimWorkspace ws;
  double w_prev = w0, t_prev = 0;
  *w_probe = -1;
  while (s.time < t_end - 1e-9) {
    EXPECT_TRUE(sim_step(m, o, s, ws));
    const double w = s.qvel[5];
    if (*w_probe < 0 && s.time >= t_probe - 1e-9) *w_probe = w;
    if (w < 0.01 * w0) return t_prev + (w_prev - 0.01 * w0) / (w_prev - w) * (s.time - t_prev);
    w_prev = w;
    t_prev = s.time;
  }
  return 1e9;
}

// Torsional friction mu_t = 0.01 m: torque mu_t m g opposes the spin of I = 2/5 m r^2,
// which stops after w0 I / (mu_t m g) = 0.4077 s from 10 rad/s (PBAD3, dt 0.01).
TEST(SpinFriction, SpinningSphereStopsAfterTheAnalyticTime) {
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  const double w0 = 10, inertia = 0.4 * 0.01, mu_t = 0.01;
  const double t_stop = w0 * inertia / (mu_t * kSpinG);
  double w_mid;
  const double t = spin_stop_time(spin_sphere_model("condim=\"4\" friction=\"1 0.01 0\""), o, w0, 0.8, 0.2, &w_mid);
  EXPECT_NEAR(t, t_stop, 0.03 * t_stop);
  EXPECT_NEAR(w_mid, w0 * (1 - 0.2 / t_stop), 0.03 * w0);  // linear decay
  // Condim 3 (the default): no torque about the normal; it keeps spinning.
  const double t3 = spin_stop_time(spin_sphere_model("friction=\"1 0.01 0\""), o, w0, 0.8, 0.6, &w_mid);
  EXPECT_EQ(t3, 1e9);
  EXPECT_GT(w_mid, 0.95 * w0);
}

// The same law in RK4 on the angular velocity (regularised with spin_eps / dt: 1 rad/s
// here, so the probe at w ~ 5 rad/s sees 98% of the dry torque).
TEST(SpinFriction, Rk4SpinDecaysAtTheAnalyticRate) {
  SimOptions o;
  o.integrator = Integrator::Rk4;
  o.dt = 1e-3;
  o.contact.damping = 20;
  o.contact.spin_eps = 1e-3;
  const double w0 = 10, inertia = 0.4 * 0.01, mu_t = 0.01;
  double w_mid;
  spin_stop_time(spin_sphere_model("condim=\"4\" friction=\"1 0.01 0\""), o, w0, 0.2, 0.2, &w_mid);
  const double decel = mu_t * kSpinG / inertia;
  EXPECT_NEAR((w0 - w_mid) / 0.2, decel, 0.03 * decel);
}

// Rolling friction mu_r: resistance torque mu_r m g, deceleration
// a = mu_r m g r / (I + m r^2) = mu_r g / (1.4 r) for a solid sphere; from v0 it stops
// after v0^2 / (2 a). mu_r = 0.01 m, r = 0.1 m: a = 0.7007 m/s^2, 0.1784 m from 0.5 m/s.
void spin_expect_rolling_stop(Integrator integ, double dt, double tol) {
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  o.contact.mu = 1;
  if (integ == Integrator::Rk4) o.contact.damping = 20, o.contact.spin_eps = 1e-4, o.contact.slip_eps = 1e-5;
  const Model m = spin_sphere_model("condim=\"6\" friction=\"1 0 0.01\"");
  State s = spin_sphere_state(m, o);
  const double v0 = 0.5, r = 0.1;
  s.qvel[0] = v0;
  s.qvel[4] = v0 / r;  // rolling about +y (body y = world y while it rolls about it)
  SimWorkspace ws;
  const double a = 0.01 * kSpinG / (1.4 * r);
  double v_probe = -1;
  while (s.time < 1.0 - 1e-9) {
    ASSERT_TRUE(sim_step(m, o, s, ws));
    if (v_probe < 0 && s.time >= 0.3 - 1e-9) v_probe = s.qvel[0];
  }
  EXPECT_NEAR((v0 - v_probe) / 0.3, a, tol * a) << "x " << s.qpos[0] << " v " << s.qvel[0];
  EXPECT_NEAR(s.qpos[0], v0 * v0 / (2 * a), tol * v0 * v0 / (2 * a)) << "v " << s.qvel[0];
  EXPECT_LT(std::abs(s.qvel[0]), 0.02 * v0);
}

TEST(SpinFriction, RollingBallStopsAfterTheAnalyticDistance) {
  spin_expect_rolling_stop(Integrator::Pbad3, 0.01, 0.03);
}

TEST(SpinFriction, Rk4RollingBallStopsAfterTheAnalyticDistance) {
  spin_expect_rolling_stop(Integrator::Rk4, 1e-3, 0.05);
}

// Central differences of PBAD's energy against its gradient with torsional and rolling
// friction on body-obstacle contacts (a box's corners on the floor, condim 6 from the
// box) and on an explicit body-body pair (two spheres, condim 6 from the pair).
TEST(SpinFriction, GradientMatchesFiniteDifferences) {
  const Model m = model_from_mjcf(
      R"(<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
        <body name="box" pos="0 0 0.099"><freejoint/><geom name="gbox" type="box" size="0.1 0.1 0.1" condim="6" friction="0.5 0.05 0.02"/></body>
        <body name="a" pos="1 0 1"><freejoint/><geom name="ga" size="0.1"/></body>
        <body name="b" pos="1.19 0 1.02"><freejoint/><geom name="gb" size="0.1"/></body></worldbody>
        <contact><pair geom1="ga" geom2="gb" condim="6" friction="0.5 0.5 0.04 0.03 0.03"/></contact></mujoco>)",
      "fd.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  State s = state_init(m);
  for (int i = 0; i < m.nv; ++i) s.qvel[i] = 0.3 * std::cos(0.9 * i + 0.2);
  SimWorkspace ws;
  PbadStep p;
  pbad_begin(m, o, s, p, ws);
  ASSERT_TRUE(p.any_spin);
  ASSERT_FALSE(p.pair_anchors.empty());
  VecX q = p.q;
  VecX dq(m.nv);
  for (int i = 0; i < m.nv; ++i) dq[i] = 0.02 * std::sin(1.3 * i + 0.4);  // rotations >> spin_eps
  qpos_integrate(m, q, dq, 1.0);
  pbad_evaluate(m, o, s, p, q, ws);
  const VecX grad = ws.grad;
  // The spin terms' share of the gradient: the same evaluation without them.
  PbadStep p3 = p;
  p3.any_spin = false;
  pbad_evaluate(m, o, s, p3, q, ws);
  const VecX grad3 = ws.grad;
  const double spin_share = (grad - grad3).norm();
  EXPECT_GT(spin_share, 10.0);
  const double h = 1e-6;
  VecX fd(m.nv);
  for (int i = 0; i < m.nv; ++i) {
    VecX qp = q, qm = q;  // free joints: quaternions, so step along each dof
    qpos_integrate(m, qp, VecX::Unit(m.nv, i), h);
    qpos_integrate(m, qm, VecX::Unit(m.nv, i), -h);
    fd[i] = (pbad_evaluate(m, o, s, p, qp, ws) - pbad_evaluate(m, o, s, p, qm, ws)) / (2 * h);
  }
  EXPECT_LT((fd - grad).norm(), 1e-4 * spin_share) << "fd " << fd.transpose() << "\ngrad " << grad.transpose();
}

// The feature-contact path (an obstacle box's corner under a moving mesh tile): a tile
// spinning about the vertical on the upturned corner, torsion 0.01 m on the tile
// (condim 4), stops after w0 I_zz / (mu_t m g); condim 3 keeps spinning.
double spin_tile_stop_time(const std::string& tile_attrs, double* w_end) {
  const std::string obj = test::write_box_obj("pliant_spin_tile", 0.1, 0.1, 0.01);
  const Quat up = Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3::UnitZ());
  const double tip = 0.04 * std::sqrt(3.0), k = 1e5, rest = 0.5 * 9.81 / k;
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco><asset><mesh name=\"tile\" file=\"" << obj << "\"/></asset><worldbody><geom type=\"box\" "
    << "size=\"0.04 0.04 0.04\" quat=\"" << up.w() << " " << up.x() << " " << up.y() << " " << up.z()
    << "\"/><body pos=\"0 0 " << tip + 0.01 - rest << "\"><joint type=\"slide\" axis=\"0 0 1\"/>"
    << "<joint type=\"hinge\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"tile\" mass=\"0.5\" " << tile_attrs
    << "/></body></worldbody></mujoco>";
  const Model m = model_from_mjcf(x.str(), "m.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.005;
  o.contact.stiffness = k;
  State s = state_init(m);
  const double w0 = 3;
  s.qvel[1] = w0;
  SimWorkspace ws;
  double t_stop = 1e9, w_prev = w0;
  for (int i = 0; i < 60; ++i) {
    EXPECT_TRUE(sim_step(m, o, s, ws));
    if (t_stop > 1e8 && s.qvel[1] < 0.01 * w0)
      t_stop = s.time - o.dt * (0.01 * w0 - s.qvel[1]) / (w_prev - s.qvel[1]);
    w_prev = s.qvel[1];
  }
  *w_end = s.qvel[1];
  return t_stop * 0.5 * 9.81 * 0.01 / (w0 * m.bodies[1].inertia(2, 2));  // / the analytic time
}

TEST(SpinFriction, MeshTileOnABoxCornerStopsSpinning) {
  double w_end;
  const double ratio = spin_tile_stop_time("condim=\"4\" friction=\"0.5 0.01 0\"", &w_end);
  std::printf("tile on a corner: stops at %.4f x the analytic time\n", ratio);
  EXPECT_NEAR(ratio, 1, 0.03);
  spin_tile_stop_time("friction=\"0.5 0.01 0\"", &w_end);
  EXPECT_GT(w_end, 0.95 * 3);
}

// condim, torsion and roll mix as MuJoCo 2.2.2's mj_contactParam: equal priorities take
// the larger of each, otherwise the higher-priority geom's.
TEST(SpinFriction, CondimTorsionAndRollMixByMaxOrPriority) {
  Geom a, b;
  a.condim = 4, a.torsion = 0.02, a.roll = 0.0001;
  b.condim = 6, b.torsion = 0.005, b.roll = 0.003;
  ContactMix c = contact_mix(a, b);
  EXPECT_EQ(c.condim, 6);
  EXPECT_EQ(c.torsion, 0.02);
  EXPECT_EQ(c.roll, 0.003);
  a.priority = 1;
  c = contact_mix(a, b);
  EXPECT_EQ(c.condim, 4);
  EXPECT_EQ(c.torsion, 0.02);
  EXPECT_EQ(c.roll, 0.0001);
  b.priority = 2;
  c = contact_mix(b, a);
  EXPECT_EQ(c.condim, 6);
  EXPECT_EQ(c.torsion, 0.005);
}

// rotation_increment's Jacobian against differences of a world-frame rotation.
TEST(SpinFriction, RotationIncrementJacobianMatchesFiniteDifferences) {
  const Mat3 r0 = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Mat3 r = Eigen::AngleAxisd(0.4, Vec3(-2, 1, 0.5).normalized()).toRotationMatrix() * r0;
  Mat3 jac;
  const Vec3 phi = rotation_increment(r, r0, &jac);
  EXPECT_NEAR(phi.norm(), std::sin(0.4), 1e-12);
  const double h = 1e-6;
  for (int a = 0; a < 3; ++a) {
    const Mat3 rp = Eigen::AngleAxisd(h, Vec3::Unit(a)).toRotationMatrix() * r;
    const Mat3 rm = Eigen::AngleAxisd(-h, Vec3::Unit(a)).toRotationMatrix() * r;
    const Vec3 col = (rotation_increment(rp, r0, nullptr) - rotation_increment(rm, r0, nullptr)) / (2 * h);
    EXPECT_LT((col - jac.col(a)).norm(), 1e-8) << a;
  }
}

}  // namespace
}  // namespace pliant::articulated
