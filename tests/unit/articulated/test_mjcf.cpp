#include <gtest/gtest.h>

#include <algorithm>

#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "mesh_fixture.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

std::string error_of(const std::string& xml) { return test::mjcf_error(xml); }

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

// Features that would change the physics exit 2 naming the element; harmless ones
// (sensors, keyframes, sites, cameras, lights, visual attributes) are ignored.
TEST(Mjcf, UnsupportedPhysicsNamesTheElementAndHarmlessPartsAreIgnored) {
  const std::string b = "<mujoco><worldbody><body name=\"a\"><joint name=\"j\"/><geom size=\"0.1\"/></body></worldbody>";
  EXPECT_NE(error_of(b + "<tendon><fixed/></tendon></mujoco>").find("/mujoco/tendon[0] | unsupported element <tendon>"),
            std::string::npos);
  EXPECT_NE(error_of(b + "<equality><weld body1=\"a\"/></equality></mujoco>").find("/mujoco/equality[0] | unsupported element <equality>"),
            std::string::npos);
  EXPECT_NE(error_of(b + "<contact><bogus/></contact></mujoco>").find("/mujoco/contact[0]/bogus[0] | unsupported element <bogus>"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><option><flag gravity=\"disable\"/></option></mujoco>").find("/mujoco/option[0]/flag[0] | unsupported element <flag>"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><compiler coordinate=\"polar\"/></mujoco>").find("/mujoco/compiler[0]/@coordinate | expected local or global"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><compiler inertiafromgeom=\"false\"/></mujoco>").find("/mujoco/compiler[0]/@inertiafromgeom"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><include file=\"x.xml\"/></mujoco>").find("/mujoco/include[0]/@file | cannot read included file"),
            std::string::npos);  // includes are read (test_mjcf_include.cpp)
  // Springs and ref on hinges and slides (test_mujoco_reference.cpp); not on ball / free joints.
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint type=\"ball\" stiffness=\"3\"/><geom size=\"0.1\"/></body></worldbody></mujoco>")
                .find("joint[0]/@stiffness | a nonzero stiffness is supported on hinge and slide joints only"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint type=\"free\" ref=\"1\"/><geom size=\"0.1\"/></body></worldbody></mujoco>")
                .find("joint[0]/@ref | a nonzero ref"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint stiffness=\"-1\"/><geom size=\"0.1\"/></body></worldbody></mujoco>")
                .find("joint[0]/@stiffness | must be >= 0"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><joint springref=\"x\"/><geom size=\"0.1\"/></body></worldbody></mujoco>")
                .find("joint[0]/@springref"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><geom type=\"hfield\" size=\"0.1 0.1\"/></body></worldbody></mujoco>")
                .find("geom[0]/@type | unsupported geom type \"hfield\""),
            std::string::npos);  // cylinders and ellipsoids are read (test_primitive_meshes.cpp)
  EXPECT_NE(error_of("<mujoco><default><tendon/></default></mujoco>").find("/mujoco/default[0]/tendon[0]"), std::string::npos);
  // Harmless: compiles to the same model as without them.
  const Model plain = model_from_mjcf(b + "</mujoco>", "a.xml");
  const Model extra = model_from_mjcf(
      "<mujoco><compiler texturedir=\"tex\"/><visual/><statistic/><worldbody><light/><camera/><body name=\"a\">"
      "<site name=\"s\"/><camera/><joint name=\"j\"/><geom size=\"0.1\" rgba=\"1 0 0 1\" group=\"2\"/></body></worldbody>"
      "<sensor><jointpos joint=\"j\"/></sensor><keyframe><key qpos=\"0.3\"/></keyframe></mujoco>",
      "a.xml");
  EXPECT_EQ(extra.bodies.size(), plain.bodies.size());
  EXPECT_EQ(extra.bodies[1].mass, plain.bodies[1].mass);
  EXPECT_EQ(extra.nq, plain.nq);
}

TEST(Mjcf, ContactExcludeAndMasksAreReadAndMalformedOnesNameTheElement) {
  const std::string b = "<mujoco><worldbody><body name=\"a\"><freejoint/><geom size=\"0.1\" contype=\"3\" conaffinity=\"5\"/></body>"
                        "<body name=\"b\"><freejoint/><geom size=\"0.1\"/></body></worldbody>";
  const Model m = model_from_mjcf(b + "<contact><exclude name=\"x\" body1=\"b\" body2=\"a\"/></contact></mujoco>", "a.xml");
  ASSERT_EQ(m.contact_exclude.size(), 1u);
  EXPECT_EQ(m.contact_exclude[0], (std::array<int, 2>{1, 2}));
  EXPECT_EQ(m.geoms[0].contype, 3);
  EXPECT_EQ(m.geoms[0].conaffinity, 5);
  EXPECT_EQ(error_of(b + "<contact><exclude body1=\"a\"/></contact></mujoco>"),
            "/mujoco/contact[0]/exclude[0]/@body2 | <exclude> needs body1 and body2");
  EXPECT_EQ(error_of(b + "<contact><exclude body1=\"a\" body2=\"bb\"/></contact></mujoco>"),
            "/mujoco/contact[0]/exclude[0]/@body2 | no body named \"bb\"; did you mean \"b\"?");
  EXPECT_EQ(error_of(b + "<contact><exclude body1=\"a\" body2=\"a\"/></contact></mujoco>"),
            "/mujoco/contact[0]/exclude[0]/@body2 | a body cannot be excluded from itself");
  EXPECT_NE(error_of(b + "<contact><exclude body1=\"a\" body2=\"b\" margin=\"1\"/></contact></mujoco>")
                .find("/mujoco/contact[0]/exclude[0]/@margin | unsupported attribute"),
            std::string::npos);
  EXPECT_EQ(error_of("<mujoco><worldbody><body><geom size=\"0.1\" contype=\"1.5\"/></body></worldbody></mujoco>"),
            "/mujoco/worldbody[0]/body[0]/geom[0]/@contype | must be a non-negative integer");
}

// <contact><pair>: explicit pairs by geom name, friction's first value kept, margin
// and condim 1 / 3 / 4 / 6 read, 2 / 5 and solver parameters rejected; errors name the pair.
TEST(Mjcf, ContactPairsAreReadAndMalformedOnesNameThePair) {
  const std::string b = "<mujoco><worldbody><body name=\"a\"><freejoint/><geom name=\"ga\" size=\"0.1\" contype=\"0\" conaffinity=\"0\"/>"
                        "<geom name=\"ga2\" size=\"0.1\"/></body>"
                        "<body name=\"b\"><freejoint/><geom name=\"gb\" size=\"0.1\"/></body><geom name=\"floor\" type=\"plane\"/></worldbody>";
  const Model m = model_from_mjcf(
      b + "<contact><pair name=\"p\" geom1=\"gb\" geom2=\"ga\" friction=\"0.3 0.3 0.005\" condim=\"3\" margin=\"0.01\"/>"
          "<pair geom1=\"ga2\" geom2=\"gb\"/></contact></mujoco>",
      "a.xml");
  ASSERT_EQ(m.contact_pairs.size(), 2u);
  EXPECT_EQ(m.contact_pairs[0].geom1, 2);
  EXPECT_EQ(m.contact_pairs[0].geom2, 0);
  EXPECT_EQ(m.contact_pairs[0].mu, 0.3);
  EXPECT_LT(m.contact_pairs[1].mu, 0);  // the scene's
  EXPECT_EQ(m.contact_pairs[0].margin, 0.01);
  EXPECT_FALSE(m.contact_pairs[0].frictionless);
  EXPECT_EQ(m.contact_pairs[1].margin, 0);
  EXPECT_TRUE(model_from_mjcf(b + "<contact><pair geom1=\"ga\" geom2=\"gb\" condim=\"1\"/></contact></mujoco>", "a.xml")
                  .contact_pairs[0]
                  .frictionless);
  const Model m6 = model_from_mjcf(
      b + "<contact><pair geom1=\"ga\" geom2=\"gb\" condim=\"6\" friction=\"0.4 0.4 0.02 0.003 0.003\"/></contact></mujoco>",
      "a.xml");
  EXPECT_EQ(m6.contact_pairs[0].condim, 6);  // torsional and rolling (test_spin_friction.cpp)
  EXPECT_EQ(m6.contact_pairs[0].torsion, 0.02);
  EXPECT_EQ(m6.contact_pairs[0].roll, 0.003);
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga2\" geom2=\"gb\"/><pair geom1=\"ga\" geom2=\"gb\" condim=\"5\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[1]/@condim | must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6 (+ rolling friction)");
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"gb\" condim=\"2\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[0]/@condim | must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6 (+ rolling friction)");
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"gb\" friction=\"1 1 -0.1\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[0]/@friction | must be >= 0");
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"gb\" margin=\"-0.1\"/></contact></mujoco>").rfind(
                "/mujoco/contact[0]/pair[0]/@margin | must be >= 0", 0),
            0u);
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[0]/@geom2 | <pair> needs geom1 and geom2");
  EXPECT_EQ(error_of(b + "<contact><exclude body1=\"a\" body2=\"b\"/><pair geom1=\"ga\" geom2=\"gbb\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[0]/@geom2 | no geom named \"gbb\"; did you mean \"gb\"?");
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"ga2\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[0]/@geom2 | both geoms belong to one body");
  EXPECT_NE(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"floor\"/></contact></mujoco>")
                .find("/mujoco/contact[0]/pair[0]/@geom2 | pairs with world geoms are not supported"),
            std::string::npos);
  EXPECT_EQ(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"gb\" friction=\"-1\"/></contact></mujoco>"),
            "/mujoco/contact[0]/pair[0]/@friction | must be >= 0");
  EXPECT_NE(error_of(b + "<contact><pair geom1=\"ga\" geom2=\"gb\" solref=\"0.02 1\"/></contact></mujoco>")
                .find("/mujoco/contact[0]/pair[0]/@solref | MuJoCo's constraint-solver parameter"),
            std::string::npos);
}

TEST(Mjcf, MalformedOrientationsAndFromtoNameTheField) {
  const std::string w = "<mujoco><worldbody><body ";
  const std::string e = "><geom size=\"0.1\"/></body></worldbody></mujoco>";
  EXPECT_NE(error_of(w + "xyaxes=\"1 0 0 2 0 0\"" + e).find("body[0]/@xyaxes | y axis is zero or parallel"), std::string::npos);
  EXPECT_NE(error_of(w + "xyaxes=\"0 0 0 0 1 0\"" + e).find("body[0]/@xyaxes | x axis is zero"), std::string::npos);
  EXPECT_NE(error_of(w + "xyaxes=\"1 0 0 0 1\"" + e).find("body[0]/@xyaxes | expected 6 numbers"), std::string::npos);
  EXPECT_NE(error_of(w + "zaxis=\"0 0 0\"" + e).find("body[0]/@zaxis | axis is zero"), std::string::npos);
  EXPECT_NE(error_of(w + "zaxis=\"0 0 1\" euler=\"0 0 1\"" + e).find("body[0]/@zaxis | give one orientation"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><geom size=\"0.1\" fromto=\"0 0 0 1 0 0\"/></body></worldbody></mujoco>")
                .find("geom[0]/@fromto | fromto is supported for capsules, cylinders and boxes only"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><geom type=\"box\" size=\"0.1\" fromto=\"0 0 0 0 0 0\"/></body></worldbody></mujoco>")
                .find("geom[0]/@fromto | zero length"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><worldbody><body><inertial mass=\"1\" fullinertia=\"1 1 1 0 0 0\" zaxis=\"1 0 0\"/>"
                     "</body></worldbody></mujoco>")
                .find("inertial[0]/@zaxis | fullinertia is in the body frame"),
            std::string::npos);
}

TEST(Mjcf, MeshDefaultClassesApplyTheirScale) {
  const std::string obj = test::write_box_obj("pliant_mesh_default", 0.1, 0.1, 0.1);
  const std::string body = "<worldbody><body><freejoint/><geom type=\"mesh\" mesh=\"m\"/></body></worldbody></mujoco>";
  const Model explicit_scale = model_from_mjcf(
      "<mujoco><asset><mesh name=\"m\" file=\"" + obj + "\" scale=\"2 1 0.5\"/></asset>" + body, "m.xml");
  const Model by_class = model_from_mjcf("<mujoco><default><default class=\"big\"><mesh scale=\"2 1 0.5\"/></default></default>"
                                         "<asset><mesh name=\"m\" class=\"big\" file=\"" + obj + "\"/></asset>" + body,
                                         "m.xml");
  const Model by_main = model_from_mjcf("<mujoco><default><mesh scale=\"2 1 0.5\"/></default>"
                                        "<asset><mesh name=\"m\" file=\"" + obj + "\"/></asset>" + body,
                                        "m.xml");
  std::filesystem::remove(obj);
  EXPECT_NEAR(explicit_scale.bodies[1].mass, 1000 * 0.4 * 0.2 * 0.1, 1e-5);  // (assimp: single precision)
  EXPECT_EQ(by_class.bodies[1].mass, explicit_scale.bodies[1].mass);
  EXPECT_EQ(by_main.bodies[1].mass, explicit_scale.bodies[1].mass);
  EXPECT_EQ((by_class.bodies[1].inertia - explicit_scale.bodies[1].inertia).norm(), 0);
}

}  // namespace
}  // namespace pliant::articulated

namespace pliant::articulated {
namespace {

// MjcfOptions::ignore_solver_params: geom and pair solref / solimp / solmix are
// recorded, not refused; anything else unsupported (geom gap) still exits 2.
TEST(Mjcf, SolverParametersAreRecordedWhenAskedToIgnoreThem) {
  const std::string xml = R"(<mujoco><worldbody><body><freejoint/>
    <geom name="a" type="sphere" size="0.1" solmix="0.5"/></body>
    <body pos="1 0 0"><freejoint/><geom name="b" type="sphere" size="0.1"/></body></worldbody>
    <contact><pair geom1="a" geom2="b" solref="0.01 1"/></contact></mujoco>)";
  EXPECT_EQ(test::mjcf_error(xml).substr(0, 52), "/mujoco/worldbody[0]/body[0]/geom[0]/@solmix | MuJoC");
  MjcfOptions o;
  o.ignore_solver_params = true;
  const Model m = model_from_mjcf(xml, "pairs.xml", {}, o);
  ASSERT_EQ(m.ignored_attributes.size(), 2u);
  EXPECT_EQ(m.ignored_attributes[0], "/mujoco/worldbody[0]/body[0]/geom[0]/@solmix");
  EXPECT_EQ(m.ignored_attributes[1], "/mujoco/contact[0]/pair[0]/@solref");
  EXPECT_THROW(model_from_mjcf(R"(<mujoco><worldbody><geom type="plane" size="1 1 1" gap="0.1"/></worldbody></mujoco>)",
                               "gap.xml", {}, o),
               InputError);
}

// The same for joints' limit / friction constraint parameters (also from a default
// class) and option's friction-cone settings; option's pure solver numerics
// (tolerance, jacobian, mpr_*) load without the switch, as iterations and solver do.
TEST(Mjcf, JointAndOptionSolverParametersFollowTheSameSwitch) {
  const std::string xml = R"(<mujoco><option timestep="0.01" tolerance="1e-10" jacobian="dense" impratio="10" cone="elliptic"/>
    <default><joint solreflimit="0.02 1" solimpfriction="0.9 0.95 0.001"/></default>
    <worldbody><body><joint name="h" axis="0 1 0" range="-1 1" limited="true" frictionloss="0.1"
      solreffriction="0.01 1"/><geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body></worldbody></mujoco>)";
  const std::string refused = test::mjcf_error(xml);
  EXPECT_EQ(refused.substr(0, 36), "/mujoco/option[0]/@impratio | MuJoCo") << refused;
  EXPECT_NE(refused.find("ignore_solver_params"), std::string::npos) << refused;
  MjcfOptions o;
  o.ignore_solver_params = true;
  const Model m = model_from_mjcf(xml, "joint.xml", {}, o);
  ASSERT_EQ(m.ignored_attributes.size(), 5u);
  EXPECT_EQ(m.ignored_attributes[0], "/mujoco/option[0]/@impratio");  // in the file's order
  EXPECT_EQ(m.ignored_attributes[1], "/mujoco/option[0]/@cone");
  const std::string joint = "/mujoco/worldbody[0]/body[0]/joint[0]/@";
  std::vector<std::string> rest(m.ignored_attributes.begin() + 2, m.ignored_attributes.end());
  std::sort(rest.begin(), rest.end());
  EXPECT_EQ(rest, (std::vector<std::string>{joint + "solimpfriction", joint + "solreffriction", joint + "solreflimit"}));
  EXPECT_EQ(m.joints[0].frictionloss, 0.1);  // the rest of the joint is read as before
  EXPECT_EQ(m.timestep, 0.01);
  // Without the cone-related settings, the solver numerics alone need no switch.
  EXPECT_NO_THROW(model_from_mjcf(R"(<mujoco><option tolerance="1e-10" jacobian="sparse" mpr_iterations="50"/>
    <worldbody><body><joint axis="0 1 0"/><geom type="sphere" size="0.1"/></body></worldbody></mujoco>)",
                                  "numerics.xml"));
}

}  // namespace
}  // namespace pliant::articulated
