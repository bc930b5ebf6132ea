// Geom-level contact parameters (Geom::friction / margin / condim / priority) and their
// mixing per contact (contact_mix, MuJoCo 2.2.2's rule for automatic contacts): MJCF
// and JSON reading, bad values, and their effect on obstacle and body-body contacts
// against analytic answers. (MuJoCo's own compiled values: test_mujoco_reference.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "pliant/articulated/articulated.h"
#include "pliant/articulated/contact.h"
#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "pliant/core/error.h"
#include "mesh_fixture.h"

namespace pliant::articulated {
namespace {

std::string gc_mjcf_error(const std::string& xml) {
  try {
    model_from_mjcf(xml, "bad.xml");
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "no error";
}

std::string gc_json_error(const nlohmann::json& j) {
  try {
    JsonReader r(j, "m.json");
    model_from_json(r);
    r.finish();
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "no error";
}

TEST(GeomContact, MjcfReadsFrictionMarginCondimPriorityThroughDefaults) {
  const Model m = model_from_mjcf(
      R"(<mujoco><default><geom friction="0.7 0.01 0.001" margin="0.002"/>
           <default class="slick"><geom friction="0.1" condim="1" priority="2"/></default></default>
         <worldbody><geom name="floor" type="plane" friction="1.2"/>
           <body childclass="slick"><freejoint/><geom name="a" type="box" size="0.1 0.1 0.1"/>
             <geom name="b" size="0.05" margin="0.01" condim="3"/></body>
           <body><freejoint/><geom name="c" size="0.05" class="main"/></body>
         </worldbody></mujoco>)",
      "m.xml");
  ASSERT_EQ(m.geoms.size(), 4u);
  EXPECT_EQ(m.geoms[0].friction, 1.2);  // own value over the main class
  EXPECT_EQ(m.geoms[0].margin, 0.002);
  EXPECT_EQ(m.geoms[0].condim, 3);
  EXPECT_EQ(m.geoms[1].friction, 0.1);  // childclass, which inherits main's margin
  EXPECT_EQ(m.geoms[1].margin, 0.002);
  EXPECT_EQ(m.geoms[1].condim, 1);
  EXPECT_EQ(m.geoms[1].priority, 2);
  EXPECT_EQ(m.geoms[2].margin, 0.01);
  EXPECT_EQ(m.geoms[2].condim, 3);
  EXPECT_EQ(m.geoms[3].friction, 0.7);
  EXPECT_EQ(m.geoms[3].priority, 0);
  // Without any: unset friction (the scene's), margin 0, condim 3, priority 0.
  const Model plain = model_from_mjcf("<mujoco><worldbody><body><geom size=\"1\"/></body></worldbody></mujoco>", "p.xml");
  EXPECT_LT(plain.geoms[0].friction, 0);
  EXPECT_EQ(plain.geoms[0].margin, 0);
  EXPECT_EQ(plain.geoms[0].condim, 3);
}

TEST(GeomContact, JsonGeomsTakeTheMjcfNames) {
  const nlohmann::json j = {
      {"bodies",
       {{{"name", "ball"},
         {"joints", {{{"type", "free"}}}},
         {"geoms", {{{"type", "sphere"}, {"size", {0.1}}, {"friction", 0.3}, {"margin", 0.004}, {"condim", 1},
                     {"priority", 1}},
                    {{"type", "sphere"}, {"size", {0.1}}, {"friction", {0.6, 0.02, 0.003}}, {"condim", 6}}}}}}},
      {"obstacles", {{{"type", "plane"}, {"friction", 0.9}}}}};
  JsonReader r(j, "m.json");
  const Model m = model_from_json(r);
  r.finish();
  EXPECT_EQ(m.geoms[0].friction, 0.3);
  EXPECT_EQ(m.geoms[0].margin, 0.004);
  EXPECT_EQ(m.geoms[0].condim, 1);
  EXPECT_EQ(m.geoms[0].priority, 1);
  EXPECT_EQ(m.geoms[1].friction, 0.6);
  EXPECT_EQ(m.geoms[1].torsion, 0.02);  // torsional / rolling (condim 4 / 6)
  EXPECT_EQ(m.geoms[1].roll, 0.003);
  EXPECT_EQ(m.geoms[1].condim, 6);
  EXPECT_EQ(m.geoms[2].friction, 0.9);
  EXPECT_EQ(m.geoms[2].torsion, 0.005);  // MuJoCo's defaults
  EXPECT_EQ(m.geoms[2].roll, 0.0001);
  const auto with = [](const char* key, const nlohmann::json& v) {
    return nlohmann::json{{"bodies", {{{"name", "b"}, {"geoms", {{{"type", "sphere"}, {"size", {0.1}}, {key, v}}}}}}}};
  };
  EXPECT_EQ(gc_json_error(with("friction", -0.1)).rfind("/bodies/0/geoms/0/friction | ", 0), 0u);
  EXPECT_EQ(gc_json_error(with("friction", {0.5, -1})).rfind("/bodies/0/geoms/0/friction/1 | ", 0), 0u);
  EXPECT_EQ(gc_json_error(with("friction", "high")).rfind("/bodies/0/geoms/0/friction | ", 0), 0u);
  EXPECT_EQ(gc_json_error(with("margin", -0.01)).rfind("/bodies/0/geoms/0/margin | ", 0), 0u);
  EXPECT_EQ(gc_json_error(with("condim", 4)), "no error");  // torsional friction (test_spin_friction.cpp)
  EXPECT_EQ(gc_json_error(with("condim", 5)), "/bodies/0/geoms/0/condim | must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6 (+ rolling friction)");
  EXPECT_EQ(gc_json_error(with("condim", 2)).rfind("/bodies/0/geoms/0/condim | must be 1 (frictionless), 3", 0), 0u);
  EXPECT_EQ(gc_json_error(with("priority", 1.5)).rfind("/bodies/0/geoms/0/priority | ", 0), 0u);
}

TEST(GeomContact, MjcfBadValuesNameElementAndAttribute) {
  const auto geom = [](const std::string& attrs) {
    return "<mujoco><worldbody><body><geom size=\"0.1\" " + attrs + "/></body></worldbody></mujoco>";
  };
  const std::string at = "/mujoco/worldbody[0]/body[0]/geom[0]/@";
  EXPECT_EQ(gc_mjcf_error(geom("friction=\"-0.5\"")), at + "friction | friction coefficients must be >= 0");
  EXPECT_EQ(gc_mjcf_error(geom("friction=\"0.5 -0.1\"")), at + "friction | friction coefficients must be >= 0");
  EXPECT_EQ(gc_mjcf_error(geom("friction=\"0.5 0.1 0.1 0.1\"")), at + "friction | expected 1 to 3 numbers, got 4");
  EXPECT_EQ(gc_mjcf_error(geom("friction=\"grippy\"")), at + "friction | expected numbers, got \"grippy\"");
  EXPECT_EQ(gc_mjcf_error(geom("margin=\"-1\"")).rfind(at + "margin | must be >= 0", 0), 0u);
  EXPECT_EQ(gc_mjcf_error(geom("condim=\"2\"")), at + "condim | must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6 (+ rolling friction)");
  EXPECT_EQ(gc_mjcf_error(geom("condim=\"5\"")), at + "condim | must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6 (+ rolling friction)");
  EXPECT_EQ(gc_mjcf_error(geom("condim=\"6\"")), "no error");
  EXPECT_EQ(gc_mjcf_error(geom("condim=\"4\"")), "no error");
  EXPECT_EQ(gc_mjcf_error(geom("priority=\"0.5\"")), at + "priority | must be an integer");
  // Through a default class: the element that inherits it is named.
  EXPECT_EQ(gc_mjcf_error("<mujoco><default><geom condim=\"5\"/></default><worldbody><body><geom size=\"0.1\"/></body>"
                          "</worldbody></mujoco>")
                .rfind(at + "condim | must be 1", 0),
            0u);
}

TEST(GeomContact, MixingTakesTheMaximumOrTheHigherPriority) {
  Geom a, b;
  ContactMix c = contact_mix(a, b);  // nothing set: the scene's mu, no margin, condim 3
  EXPECT_EQ(contact_mu(c, 0.37), 0.37);
  EXPECT_EQ(c.margin, 0);
  EXPECT_FALSE(c.frictionless);
  a.friction = 0.2;
  EXPECT_EQ(contact_mu(contact_mix(a, b), 0.37), 0.37);  // the unset geom counts as the scene's
  EXPECT_EQ(contact_mu(contact_mix(a, b), 0.1), 0.2);
  b.friction = 0.9;
  b.margin = 0.01;
  a.margin = 0.002;
  a.condim = 1;
  c = contact_mix(a, b);
  EXPECT_EQ(contact_mu(c, 5.0), 0.9);  // both set: the scene takes no part
  EXPECT_EQ(c.margin, 0.01);
  EXPECT_FALSE(c.frictionless);  // max(1, 3)
  b.condim = 1;
  EXPECT_TRUE(contact_mix(a, b).frictionless);
  b.condim = 3;
  a.priority = 1;  // a wins friction and condim; the margin stays the larger
  c = contact_mix(b, a);
  EXPECT_EQ(contact_mu(c, 5.0), 0.2);
  EXPECT_TRUE(c.frictionless);
  EXPECT_EQ(c.margin, 0.01);
  a.friction = -1;  // the winner has no friction: the scene's, even below the other's
  EXPECT_EQ(contact_mu(contact_mix(a, b), 0.3), 0.3);
}

// A 1 kg box (half size 0.1) with a free joint resting on a plane tilted by `slope`
// about y; `box` and `plane` are extra geom attributes.
Model gc_box_on_slope(double slope, const std::string& box, const std::string& plane) {
  const Quat q(Eigen::AngleAxisd(slope, Vec3::UnitY()));
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco><worldbody><geom type=\"plane\" quat=\"" << q.w() << " " << q.x() << " " << q.y() << " " << q.z()
    << "\" " << plane << "/><body pos=\"0 0 0.1\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\" mass=\"1\" "
    << box << "/></body></worldbody></mujoco>";
  return model_from_mjcf(x.str(), "slope.xml");
}

State gc_resting_on_slope(const Model& m, double slope, double stiffness, double margin) {
  const Quat q(Eigen::AngleAxisd(slope, Vec3::UnitY()));
  State s = state_init(m);
  s.qpos.head<3>() = q * Vec3::UnitZ() * (0.1 + margin - 9.81 * std::cos(slope) / (4 * stiffness));
  s.qpos.segment<4>(3) << q.w(), q.x(), q.y(), q.z();
  return s;
}

// Distance the box moves in `seconds`.
double gc_slide(const Model& m, double slope, const SimOptions& o, double seconds) {
  State s = gc_resting_on_slope(m, slope, o.contact.stiffness, 0);
  SimWorkspace ws;
  const Vec3 p0 = s.qpos.head<3>();
  const int steps = static_cast<int>(std::lround(seconds / o.dt));
  for (int i = 0; i < steps; ++i)
    if (!sim_step(m, o, s, ws)) return 1e9;
  return (s.qpos.head<3>() - p0).norm();
}

TEST(GeomContact, GeomFrictionDecidesWhetherABoxSticksOnASlope) {
  // 20 degrees: tan = 0.364. The scene's mu (0.05) alone would let the box slide; the
  // box's geom friction 0.8 holds it; 0.2 lets it slide 1/2 g (sin - 0.2 cos) t^2.
  const double slope = 20 * M_PI / 180, t = 1.0;
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.05;
  const double expect = 0.5 * 9.81 * (std::sin(slope) - 0.2 * std::cos(slope)) * t * t;
  const double stick = gc_slide(gc_box_on_slope(slope, "friction=\"0.8\"", ""), slope, o, t);
  const double slip = gc_slide(gc_box_on_slope(slope, "friction=\"0.2 0.005 0.0001\"", ""), slope, o, t);
  // Plane 0.8, box 0.2: the larger holds it, unless the box has the higher priority.
  const double both = gc_slide(gc_box_on_slope(slope, "friction=\"0.2\"", "friction=\"0.8\""), slope, o, t);
  const double prio = gc_slide(gc_box_on_slope(slope, "friction=\"0.2\" priority=\"1\"", "friction=\"0.8\""), slope, o, t);
  std::printf("slope 20 deg, 1 s: box mu 0.8 %.2e m, 0.2 %.4f m (analytic %.4f), plane 0.8 %.2e m, priority %.4f m\n",
              stick, slip, expect, both, prio);
  EXPECT_LT(stick, 1e-3);
  EXPECT_NEAR(slip / expect, 1.0, 0.03);
  EXPECT_LT(both, 1e-3);
  EXPECT_NEAR(prio / expect, 1.0, 0.03);
  // Explicit integrators take the same coefficient (RK4, small steps for the penalty).
  SimOptions r = o;
  r.integrator = Integrator::Rk4;
  r.dt = 2e-4;
  const double rk4 = gc_slide(gc_box_on_slope(slope, "friction=\"0.2\"", ""), slope, r, 0.4);
  EXPECT_NEAR(rk4 / (expect * 0.16), 1.0, 0.03) << rk4;
}

TEST(GeomContact, MarginHoldsABoxAtTheMarginsDistance) {
  // Penalty on margin - distance: at rest m g = 4 k (margin - gap), so the box floats
  // margin - m g / (4 k) above the floor (1 cm margin, 0.025 mm penalty depth).
  const double margin = 0.01;
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  const Model m = gc_box_on_slope(0, "margin=\"0.01\"", "");
  State s = gc_resting_on_slope(m, 0, o.contact.stiffness, margin);
  s.qpos[2] += 0.002;  // dropped from 2 mm above its rest height
  SimWorkspace ws;
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
  const double gap = s.qpos[2] - 0.1, expect = margin - 9.81 / (4 * o.contact.stiffness);
  std::printf("box with margin 0.01 at rest: gap %.6f m (expected %.6f)\n", gap, expect);
  EXPECT_NEAR(gap, expect, 1e-5);
  // Body-body: a box on a fixed box whose geom has the margin (self_collision).
  const Model pile = model_from_mjcf(
      "<mujoco><worldbody><body name=\"base\"><geom type=\"box\" size=\"0.2 0.2 0.05\" margin=\"0.01\"/></body>"
      "<body name=\"top\" pos=\"0 0 0.15\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\" mass=\"1\"/></body>"
      "</worldbody></mujoco>",
      "pile.xml");
  o.contact.self_collision = true;
  State p = state_init(pile);
  p.qpos[2] += margin;  // touching at the margin, as above
  SimWorkspace pw;
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(sim_step(pile, o, p, pw));
  EXPECT_NEAR(p.qpos[2] - 0.15, expect, 1e-5);
}

TEST(GeomContact, CondimOneMakesContactsFrictionless) {
  // A box pushed at 1 m/s on a flat floor (scene mu 0.5): Coulomb friction stops it
  // after v^2 / (2 mu g) = 0.102 m; frictionless it keeps going (1 m in 1 s). condim
  // mixes as the maximum: condim 1 on the box alone keeps friction (MuJoCo's rule)
  // unless the floor's is 1 too or the box has the higher priority.
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  const auto push = [&o](const Model& m) {
    State s = gc_resting_on_slope(m, 0, o.contact.stiffness, 0);
    s.qvel[0] = 1;
    SimWorkspace ws;
    for (int i = 0; i < 100; ++i)
      if (!sim_step(m, o, s, ws)) return 1e9;
    return s.qpos[0];
  };
  const double box_only = push(gc_box_on_slope(0, "condim=\"1\"", ""));
  const double both = push(gc_box_on_slope(0, "condim=\"1\"", "condim=\"1\""));
  const double prio = push(gc_box_on_slope(0, "condim=\"1\" priority=\"1\"", ""));
  std::printf("pushed box, 1 s: condim 1 on the box %.4f m, on both %.4f m, with priority %.4f m\n", box_only, both, prio);
  EXPECT_NEAR(box_only, 1 / (2 * 0.5 * 9.81), 0.01);
  EXPECT_NEAR(both, 1.0, 0.002);
  EXPECT_NEAR(prio, 1.0, 0.002);
  // Body-body: a box pushed on a fixed box, both geoms condim 1.
  const Model pile = model_from_mjcf(
      "<mujoco><worldbody><body name=\"base\"><geom type=\"box\" size=\"1 1 0.05\" condim=\"1\"/></body>"
      "<body name=\"top\" pos=\"0 0 0.15\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\" mass=\"1\" condim=\"1\"/>"
      "</body></worldbody></mujoco>",
      "pile.xml");
  o.contact.self_collision = true;
  State p = state_init(pile);
  p.qpos[2] -= 9.81 / (4 * o.contact.stiffness);
  p.qvel[0] = 1;
  SimWorkspace pw;
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(sim_step(pile, o, p, pw));
  EXPECT_NEAR(p.qpos[0], 0.5, 0.002);
}

// Obstacle features against a moving mesh (mesh_feature_contacts) mix too: a mesh tile
// on two slides resting on an upturned box corner, pushed at 0.2 m/s, stops after
// v^2 / (2 mu g) = 8.15 mm with the tile's geom friction 0.25 (the scene's 0.05 alone:
// 40.8 mm), and a margin of 5 mm on the box holds the tile that far above the corner
// (without it the tile would drop 5 mm).
TEST(GeomContact, MeshOnABoxCornerTakesTheGeomsFrictionAndMargin) {
  const std::string obj = test::write_box_obj("pliant_gc_tile", 0.1, 0.1, 0.01);
  const Quat up = Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3::UnitZ());
  const double tip = 0.04 * std::sqrt(3.0), k = 1e5, rest = 0.5 * 9.81 / k;
  const auto tile_model = [&](const std::string& tile, const std::string& box, double margin) {
    std::ostringstream x;
    x.precision(17);
    x << "<mujoco><asset><mesh name=\"tile\" file=\"" << obj << "\"/></asset><worldbody><geom type=\"box\" "
      << "size=\"0.04 0.04 0.04\" quat=\"" << up.w() << " " << up.x() << " " << up.y() << " " << up.z() << "\" " << box
      << "/><body pos=\"0 0 " << tip + 0.01 + margin - rest << "\"><joint type=\"slide\" axis=\"1 0 0\"/>"
      << "<joint type=\"slide\" axis=\"0 0 1\"/><geom type=\"mesh\" mesh=\"tile\" mass=\"0.5\" " << tile
      << "/></body></worldbody></mujoco>";
    return model_from_mjcf(x.str(), "m.xml");
  };
  const Model slide = tile_model("friction=\"0.25\"", "", 0), lifted = tile_model("", "margin=\"0.005\"", 0.005);
  std::filesystem::remove(obj);
  SimOptions o;
  o.dt = 0.005;
  o.contact.stiffness = k;
  o.contact.mu = 0.05;
  State s = state_init(slide);
  s.qvel[0] = 0.2;
  SimWorkspace ws;
  for (int i = 0; i < 80; ++i) ASSERT_TRUE(sim_step(slide, o, s, ws));
  const double stop = 0.04 / (2 * 0.25 * 9.81);
  State l = state_init(lifted);
  SimWorkspace lw;
  for (int i = 0; i < 80; ++i) ASSERT_TRUE(sim_step(lifted, o, l, lw));
  std::printf("tile on a corner: stops at %.5f m (v^2 / (2 mu g) %.5f), margin 5 mm: %.3e m off its rest height\n",
              s.qpos[0], stop, l.qpos[1]);
  EXPECT_NEAR(s.qpos[0], stop, 0.03 * stop);
  EXPECT_NEAR(s.qvel[0], 0, 1e-3);
  EXPECT_NEAR(l.qpos[1], 0, 2e-5);  // slide z from the rest height with the margin
}

// The shipped scene (JSON geoms through the scene loader): after 1 s on the 20 degree
// slope each box has moved 1/2 g (sin - mu cos) t^2 with its mixed mu: rubber 0.9
// holds, plain the scene's 0.3, slick its own 0.05 (priority over the slope), ice 0.
// 5%: near the friction angle PBAD3's slide is long by a few % whatever sets the mu
// (scene mu 0.2 / 0.25 / 0.3 alone: -0.6 / +0.5 / +3.3%).
TEST(GeomContact, FrictionSceneBoxesSlideAsTheirGeomsSay) {
  const Scene sc = load_scene(std::filesystem::path(PLIANT_ASSETS_DIR) / "scenes" / "articulated_geom_friction.json");
  const ArticulatedScene a = articulated_compile(sc);
  State s = a.initial;
  SimWorkspace ws;
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim_step(a.model, a.options, s, ws));
  const double slope = 20 * M_PI / 180;
  const double mu[4] = {0.9, 0.3, 0.05, 0};
  for (int b = 0; b < 4; ++b) {
    const double moved = (s.qpos.segment<3>(7 * b) - a.initial.qpos.segment<3>(7 * b)).norm();
    const double expect = std::max(0.0, 0.5 * 9.81 * (std::sin(slope) - mu[b] * std::cos(slope)));
    std::printf("%s: %.4f m in 1 s (analytic %.4f)\n", a.model.bodies[b + 1].name.c_str(), moved, expect);
    if (expect == 0) EXPECT_LT(moved, 1e-3);
    else EXPECT_NEAR(moved / expect, 1.0, 0.05) << a.model.bodies[b + 1].name;
  }
}

}  // namespace
}  // namespace pliant::articulated
