// Cylinders and ellipsoids against planes at their exact surface (contact_support.cpp):
// the support point is the deepest point of the shape, its curvature is the support
// function's Hessian, an ellipsoid of equal radii rolls as the sphere geom does, and a
// cylinder rolls on its side at a constant axis height where its 32-gon bumps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// One free body with `geom` over a plane tilted by `tilt` (the world z is not special).
Model shape_model(const std::string& geom, const char* plane_euler = "0 0 0", const MjcfOptions& options = {}) {
  return model_from_mjcf(std::string("<mujoco><worldbody><geom type=\"plane\" size=\"5 5 0.1\" euler=\"") +
                             plane_euler + "\"/><body pos=\"0 0 1\"><freejoint/><geom " + geom +
                             "/></body></worldbody></mujoco>",
                         "shape.xml", {}, options);
}

std::vector<ContactPoint> supports(const Model& m) {
  std::vector<ContactPoint> out;
  for (const ContactPoint& p : contact_points(m))
    if (p.support != PointSupport::Fixed) out.push_back(p);
  return out;
}

// Over many body rotations: the support point lies on the shape's surface and no
// surface point (dense parametric samples) is deeper along the plane's normal; its
// curvature is the derivative of the world support point along directions u, as
// central differences of contact_point_local (s(u) = grad h(u)) give it.
TEST(ContactSupport, SupportPointIsTheDeepestPointAndItsCurvatureTheSupportHessian) {
  const char* shapes[] = {R"(type="ellipsoid" size="0.03 0.07 0.05" pos="0.01 0 0.02" euler="10 20 30")",
                          R"(type="cylinder" size="0.04 0.06" pos="0 0.02 0" euler="40 0 -15")"};
  for (const char* shape : shapes) {
    const Model m = shape_model(shape, "17 -9 0");
    const Geom& g = m.geoms[1];
    const std::vector<ContactPoint> sp = supports(m);
    ASSERT_EQ(sp.size(), g.tessellates == Geom::Tessellated::Ellipsoid ? 1u : 2u) << shape;
    const Vec3 n = m.geoms[0].quat * Vec3::UnitZ();
    for (int t = 0; t < 20; ++t) {
      const Mat3 rot = Eigen::AngleAxisd(0.37 * t + 0.1, Vec3(std::sin(t), std::cos(2.0 * t), 0.5).normalized())
                           .toRotationMatrix();
      const Mat3 rg = rot * g.quat.toRotationMatrix();
      const Vec3 centre = rot * g.pos;
      // Deepest point of the whole shape from dense samples of its surface.
      double deepest = 1e300;
      for (int i = 0; i <= 200; ++i)
        for (int j = 0; j < 400; ++j) {
          const double a = 2 * M_PI * j / 400, b = M_PI * i / 200;
          Vec3 y;
          if (g.tessellates == Geom::Tessellated::Ellipsoid)
            y = Vec3(g.size[0] * std::sin(b) * std::cos(a), g.size[1] * std::sin(b) * std::sin(a), g.size[2] * std::cos(b));
          else
            y = Vec3(g.size[0] * std::cos(a), g.size[0] * std::sin(a), (i % 2 ? 1 : -1) * g.size[1]);  // the rims
          deepest = std::min(deepest, n.dot(centre + rg * y));
        }
      double best = 1e300;
      for (const ContactPoint& p : sp) {
        Mat3 h;
        const Vec3 local = contact_point_local(m, p, rot, &h);
        best = std::min(best, n.dot(rot * local));
        const Vec3 y = rg.transpose() * (rot * local - centre);  // on the surface
        if (g.tessellates == Geom::Tessellated::Ellipsoid)
          EXPECT_NEAR(y.cwiseQuotient(g.size).squaredNorm(), 1, 1e-12);
        else
          EXPECT_NEAR(std::hypot(y.x(), y.y()), g.size[0], 1e-12);
        // d s / d u for the world direction u = -n: turn the body instead of the plane,
        // u' = -(n + e v) seen in the body frame; s(u) is homogeneous of degree 0, so
        // only the part of v across u counts, and the Hessian is zero along u.
        for (int k = 0; k < 3; ++k) {
          const Vec3 v = Vec3::Unit(k) - Vec3::Unit(k).dot(n) * n;
          const double e = 1e-6;
          const auto world_support = [&](double s) {
            const Vec3 np = (n + s * v).normalized();
            // A rotation taking np to n turns the body so that the plane reads np.
            const Mat3 turn = Eigen::Quaterniond::FromTwoVectors(np, n).toRotationMatrix();
            return Vec3(turn.transpose() * (turn * rot * contact_point_local(m, p, turn * rot)));
          };
          const Vec3 ds = (world_support(e) - world_support(-e)) / (2 * e);
          // s(u) with u = -(n + s v): d s / d s = -H v (|n + s v| = 1 + O(s^2)).
          const double rho = std::hypot((rg.transpose() * n).x(), (rg.transpose() * n).y());
          if (g.tessellates == Geom::Tessellated::Cylinder && rho < 0.2) continue;  // the floored flat cap
          EXPECT_LT((ds + h * v).norm(), 1e-5 * (1 + (h * v).norm())) << shape << " t " << t << " k " << k;
        }
      }
      EXPECT_NEAR(best, deepest, 2e-4 * g.size.maxCoeff()) << shape << " t " << t;  // sampling error
      EXPECT_LE(best, deepest + 1e-12) << shape << " t " << t;  // never shallower than a sample
    }
  }
}

// mjcf.curved_contact "tessellated" (MjcfOptions::exact_plane_contact false): the
// tessellation's samples meet the plane, no support points; without a plane, none
// either (nothing to support against).
TEST(ContactSupport, TessellatedOptionAndPlanelessModelsKeepTheSamples) {
  MjcfOptions tess;
  tess.exact_plane_contact = false;
  for (const char* shape : {R"(type="ellipsoid" size="0.03 0.07 0.05")", R"(type="cylinder" size="0.04 0.06")"}) {
    const Model exact = shape_model(shape), sampled = shape_model(shape, "0 0 0", tess);
    EXPECT_FALSE(supports(exact).empty());
    EXPECT_TRUE(supports(sampled).empty());
    for (const ContactPoint& p : contact_points(sampled)) EXPECT_EQ(p.role, PointRole::All);
    int not_planes = 0;
    for (const ContactPoint& p : contact_points(exact)) not_planes += p.role == PointRole::NotPlanes;
    EXPECT_EQ(not_planes, static_cast<int>(mesh_contact_samples(*exact.geoms[1].mesh).size()));
    const Model planeless = model_from_mjcf(std::string("<mujoco><worldbody><geom type=\"box\" size=\"1 1 0.1\"/>"
                                                        "<body pos=\"0 0 1\"><freejoint/><geom ") +
                                                shape + "/></body></worldbody></mujoco>",
                                            "box.xml");
    for (const ContactPoint& p : contact_points(planeless)) EXPECT_EQ(p.role, PointRole::All);
  }
}

// An ellipsoid of equal radii is a sphere: its one support point, on the surface,
// must give the sphere geom's motion (a centre point with a radius, exact since the
// earliest sessions) when both are thrown sliding and spinning onto a tilted plane,
// to the LM tolerance; the support's curvature term is what makes the models equal
// (without it the ellipsoid's Newton model is off by r f in its tilts).
TEST(ContactSupport, EllipsoidOfEqualRadiiMovesAsTheSphere) {
  const Model sphere = shape_model(R"(type="sphere" size="0.05" mass="1")", "8 -5 0");
  const Model ellipsoid = shape_model(R"(type="ellipsoid" size="0.05 0.05 0.05" mass="1")", "8 -5 0");
  ASSERT_NEAR(sphere.bodies[1].inertia(0, 0), ellipsoid.bodies[1].inertia(0, 0), 1e-15);
  for (Integrator integ : {Integrator::Pbad3, Integrator::Rk4}) {
    SimOptions o;
    o.integrator = integ;
    o.dt = integ == Integrator::Rk4 ? 1e-3 : 0.01;
    o.contact.mu = 0.3;
    if (integ == Integrator::Rk4) o.contact.damping = 20, o.contact.slip_eps = 1e-5;
    State a = state_init(sphere), b = state_init(ellipsoid);
    for (State* s : {&a, &b}) {
      s->qpos[2] = 0.06;
      s->qvel << 1.0, 0.3, -0.2, 2, -5, 7;
    }
    SimWorkspace wa, wb;
    double iterations[2] = {0, 0};
    int steps = 0;
    while (a.time < 1.0 - 1e-9) {
      StepInfo ia, ib;
      ASSERT_TRUE(sim_step(sphere, o, a, wa, &ia));
      ASSERT_TRUE(sim_step(ellipsoid, o, b, wb, &ib));
      iterations[0] += ia.iterations, iterations[1] += ib.iterations;
      ++steps;
    }
    const double dx = (a.qpos.head<3>() - b.qpos.head<3>()).norm(), dv = (a.qvel - b.qvel).norm();
    std::printf("ellipsoid as sphere (integrator %d): |dx| %.2e m, |dv| %.2e, LM it/step %.2f vs %.2f, x %.4f m\n",
                static_cast<int>(integ), dx, dv, iterations[1] / steps, iterations[0] / steps, a.qpos[0]);
    EXPECT_GT(a.qpos.head<2>().norm(), 0.3);  // it went somewhere
    EXPECT_LT(dx, 1e-5) << static_cast<int>(integ);
    EXPECT_LT(dv, 1e-4) << static_cast<int>(integ);
    if (integ == Integrator::Pbad3) EXPECT_LT(iterations[1], 1.2 * iterations[0] + steps);
  }
}

// A cylinder on its side rolling at 1 m/s: with the rims' support points its axis stays
// at its rest height (the penalty's depth only) and it keeps its speed; the 32-gon of
// the tessellation lifts and drops the axis by r (1 - cos(pi / 32)) and brakes it.
struct CylinderRoll {
  double height_range, speed;
};
CylinderRoll roll_cylinder(bool exact) {
  MjcfOptions opt;
  opt.exact_plane_contact = exact;
  const double r = 0.05;
  const Model m = shape_model(R"(type="cylinder" size="0.05 0.1" mass="1" euler="90 0 0")", "0 0 0", opt);
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.005;
  o.contact.mu = 1;
  State s = state_init(m);
  const double depth = 9.81 / (2 * o.contact.stiffness);  // two rims share the weight
  s.qpos[2] = r - depth;
  s.qvel[0] = 1;
  s.qvel[4] = 1 / r;  // rolling about +y
  SimWorkspace ws;
  double lo = 1e9, hi = -1e9;
  while (s.time < 1.0 - 1e-9) {
    EXPECT_TRUE(sim_step(m, o, s, ws));
    if (s.time > 0.2) lo = std::min(lo, s.qpos[2]), hi = std::max(hi, s.qpos[2]);
  }
  return {hi - lo, s.qvel[0]};
}

TEST(ContactSupport, CylinderRollsOnItsRimsAtAConstantHeight) {
  const CylinderRoll exact = roll_cylinder(true), sampled = roll_cylinder(false);
  std::printf("cylinder rolling 1 s: exact axis height range %.2e m, speed %.4f m/s; 32-gon %.2e m, %.4f m/s\n",
              exact.height_range, exact.speed, sampled.height_range, sampled.speed);
  const double bump = 0.05 * (1 - std::cos(M_PI / 32));  // 0.24 mm
  EXPECT_LT(exact.height_range, 0.02 * bump);
  EXPECT_NEAR(exact.speed, 1.0, 0.01);
  EXPECT_GT(sampled.height_range, 0.5 * bump);  // what the exact contact removes
}

}  // namespace
}  // namespace pliant::articulated
