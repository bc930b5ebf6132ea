#include <gtest/gtest.h>

#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "mesh_fixture.h"

namespace pliant::articulated {
namespace {

std::string error_of(const std::string& xml) {
  try {
    model_from_mjcf(xml, "bad.xml");
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "no error";
}

TEST(Mjcf, ChainCompiles) {
  const Model m = model_from_mjcf(chain_mjcf(4, 0.2, 0.02), "chain.xml");
  EXPECT_EQ(m.bodies.size(), 5u);
  EXPECT_EQ(m.nq, 8);
  EXPECT_EQ(m.nv, 8);
  EXPECT_EQ(m.bodies[2].parent, 1);
  EXPECT_NEAR(m.bodies[1].com.x(), 0.1, 1e-12);
  const double r = 0.02, h = 0.2;
  EXPECT_NEAR(m.bodies[1].mass, 1000 * (M_PI * r * r * h + 4.0 / 3.0 * M_PI * r * r * r), 1e-9);
}

TEST(Mjcf, MalformedInputNamesTheElement) {
  EXPECT_NE(error_of("<mujoco><worldbody><body><geom type=\"cone\" size=\"1\"/></body></worldbody></mujoco>")
                .find("/mujoco/worldbody[0]/body[0]/geom[0]/@type"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint axis=\"0 1\"/><geom size=\"1\"/></body></worldbody></mujoco>")
                .find("/mujoco/worldbody[0]/body[0]/joint[0]/@axis"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><geom size=\"1\" densty=\"3\"/></body></worldbody></mujoco>")
                .find("did you mean \"density\""),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><tendon/></body></worldbody></mujoco>").find("<tendon>"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body></worldbody></mujoco>").find("XML line 1"), std::string::npos);
  EXPECT_NE(error_of("<robot/>").find("root element must be <mujoco>"), std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint/></body></worldbody></mujoco>").find("no mass"),
            std::string::npos);
  // More than 6 joint dofs on one body (the tree solve's joint block would be singular).
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint type=\"ball\"/><joint type=\"ball\"/><joint/>"
                     "<geom size=\"1\"/></body></worldbody></mujoco>")
                .find("at most 6"),
            std::string::npos);
}

TEST(Mjcf, DefaultsOrientationsAndRanges) {
  const Model m = model_from_mjcf(R"(<mujoco><compiler angle="radian" autolimits="true"/>
    <default><geom type="sphere" size="0.1"/><default class="big"><geom size="0.2"/><joint range="-0.5 0.5"/></default></default>
    <worldbody><body childclass="big" euler="0 0 1.5707963267948966"><joint/><geom/>
      <body><joint range="-1 2" class="main"/><geom class="main"/></body></body></worldbody></mujoco>)",
                                 "d.xml");
  EXPECT_NEAR(m.bodies[1].mass, 1000 * 4.0 / 3.0 * M_PI * 0.008, 1e-9);
  EXPECT_NEAR(m.bodies[2].mass, 1000 * 4.0 / 3.0 * M_PI * 0.001, 1e-9);
  EXPECT_TRUE(m.joints[0].limited);
  EXPECT_DOUBLE_EQ(m.joints[0].range_max, 0.5);
  EXPECT_DOUBLE_EQ(m.joints[1].range_min, -1);
  EXPECT_NEAR((m.bodies[1].quat.toRotationMatrix() * Vec3::UnitX() - Vec3::UnitY()).norm(), 0, 1e-12);
  const Model deg = model_from_mjcf(
      "<mujoco><worldbody><body axisangle=\"0 0 1 90\"><joint limited=\"true\" range=\"-90 45\"/><geom size=\"0.1\"/></body></worldbody></mujoco>", "d.xml");
  EXPECT_NEAR(deg.joints[0].range_min, -M_PI / 2, 1e-12);
  EXPECT_NEAR((deg.bodies[1].quat.toRotationMatrix() * Vec3::UnitX() - Vec3::UnitY()).norm(), 0, 1e-12);
}

TEST(Mjcf, MalformedDefaultsOrientationsAndRangesNameTheField) {
  const std::string w = "<mujoco><worldbody><body>";
  const std::string e = "<geom size=\"0.1\"/></body></worldbody></mujoco>";
  EXPECT_NE(error_of("<mujoco><default><default class=\"leg\"/></default><worldbody><body><geom class=\"lge\" size=\"1\"/></body></worldbody></mujoco>")
                .find("/mujoco/worldbody[0]/body[0]/geom[0]/@class | no default class \"lge\"; did you mean \"leg\""),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body childclass=\"x\"><geom size=\"1\"/></body></worldbody></mujoco>")
                .find("/mujoco/worldbody[0]/body[0]/@childclass"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><default><default/></default></mujoco>").find("/mujoco/default[0]/default[0]/@class"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><default><tendon/></default></mujoco>").find("/mujoco/default[0]/tendon[0]"),
            std::string::npos);
  EXPECT_NE(error_of(w + "<joint limited=\"true\" range=\"1 -1\"/>" + e).find("joint[0]/@range | lower bound"), std::string::npos);
  EXPECT_NE(error_of(w + "<joint range=\"-1 1\"/>" + e).find("joint[0]/@limited | joint has a range but no limited"),
            std::string::npos);
  EXPECT_NE(error_of(w + "<joint limited=\"true\"/>" + e).find("joint[0]/@range | a limited joint needs a range"),
            std::string::npos);
  EXPECT_NE(error_of(w + "<joint type=\"ball\" limited=\"true\" range=\"-1 1\"/>" + e).find("joint[0]/@range | a ball joint's range"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint type=\"free\" limited=\"true\" range=\"0 1\"/>" + e)
                .find("joint[0]/@range | free joints take no range"),
            std::string::npos);
  EXPECT_NE(error_of(w + "<joint limited=\"yes\" range=\"0 1\"/>" + e).find("joint[0]/@limited"), std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body euler=\"1 2\">" + e).find("body[0]/@euler | expected 3 numbers"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body euler=\"1 2 3\" quat=\"1 0 0 0\">" + e).find("body[0]/@euler | give one"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body axisangle=\"0 0 0 1\">" + e).find("body[0]/@axisangle | axis is zero"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><compiler eulerseq=\"xyw\"/><worldbody/></mujoco>").find("compiler[0]/@eulerseq"),
            std::string::npos);
}

TEST(Mjcf, MeshGeomMatchesTheEquivalentBox) {
  // An off-centre box mesh: re-centred (geom pos moved), mass and inertia of the box.
  const std::string obj = test::write_box_obj("pliant_mesh_box", 0.1, 0.2, 0.05, 0.3, 0, 0);
  const Model mesh = model_from_mjcf("<mujoco><asset><mesh name=\"b\" file=\"" + obj +
                                         "\"/></asset><worldbody><body><freejoint/><geom type=\"mesh\" mesh=\"b\" "
                                         "pos=\"0 0 1\"/></body></worldbody></mujoco>",
                                     "m.xml");
  const Model box = model_from_mjcf("<mujoco><worldbody><body><freejoint/><geom type=\"box\" size=\"0.1 0.2 0.05\" "
                                    "pos=\"0.3 0 1\"/></body></worldbody></mujoco>",
                                    "b.xml");
  std::filesystem::remove(obj);
  // (assimp reads vertices in single precision: 1e-7 relative)
  EXPECT_NEAR(mesh.bodies[1].mass, box.bodies[1].mass, 1e-6 * box.bodies[1].mass);
  EXPECT_NEAR((mesh.bodies[1].com - box.bodies[1].com).norm(), 0, 1e-7);
  EXPECT_NEAR((mesh.bodies[1].inertia - box.bodies[1].inertia).norm(), 0, 1e-6 * box.bodies[1].inertia.norm());
  ASSERT_EQ(mesh.geoms[0].type, GeomType::Mesh);
  EXPECT_NEAR((mesh.geoms[0].pos - Vec3(0.3, 0, 1)).norm(), 0, 1e-7);
  EXPECT_EQ(mesh.geoms[0].mesh->vertices.size(), 8u);
  double xmax = -1;
  for (const Vec3& v : mesh.geoms[0].mesh->vertices) xmax = std::max(xmax, v.x());
  EXPECT_NEAR(xmax, 0.1, 1e-7);  // re-centred
}

TEST(Mjcf, MalformedMeshesNameTheField) {
  const std::string obj = test::write_box_obj("pliant_mesh_bad", 0.1, 0.1, 0.1);
  const std::string a = "<mujoco><asset><mesh name=\"cube\" file=\"" + obj + "\"/></asset><worldbody><body>";
  const std::string z = "</body></worldbody></mujoco>";
  EXPECT_NE(error_of(a + "<geom type=\"mesh\" mesh=\"cub\"/>" + z).find("geom[0]/@mesh | no mesh named \"cub\"; did you mean \"cube\""),
            std::string::npos);
  EXPECT_NE(error_of(a + "<geom type=\"mesh\"/>" + z).find("geom[0]/@mesh"), std::string::npos);
  EXPECT_NE(error_of(a + "<geom size=\"1\" mesh=\"cube\"/>" + z).find("geom[0]/@mesh | mesh= needs type"), std::string::npos);
  EXPECT_NE(error_of("<mujoco><asset><mesh file=\"/nonexistent/x.obj\"/></asset></mujoco>").find("/mujoco/asset[0]/mesh[0]/@file"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><asset><mesh/></asset></mujoco>").find("mesh[0]/@file | mesh needs a file"), std::string::npos);
  EXPECT_NE(error_of("<mujoco><asset><mesh name=\"m\" file=\"" + obj + "\" scale=\"-1 1 1\"/></asset><worldbody><body>"
                     "<geom type=\"mesh\" mesh=\"m\"/>" + z).find("no positive volume"),
            std::string::npos);
  std::filesystem::remove(obj);
}

TEST(Mjcf, ActuatorsFollowJointReordering) {
  const Model m = model_from_mjcf(
      "<mujoco><worldbody><body name=\"a\"><joint name=\"ja\"/><geom size=\"0.1\"/>"
      "<body name=\"b\"><joint name=\"jb\" type=\"slide\"/><geom size=\"0.1\"/></body></body></worldbody>"
      "<actuator><motor joint=\"jb\" gear=\"3\" ctrlrange=\"-2 2\"/></actuator></mujoco>",
      "act.xml");
  ASSERT_EQ(m.actuators.size(), 1u);
  EXPECT_EQ(m.joints[m.actuators[0].joint].name, "jb");
  EXPECT_EQ(m.actuators[0].gear, 3);
  EXPECT_EQ(m.actuators[0].ctrl_max, 2);
}

}  // namespace
}  // namespace pliant::articulated
