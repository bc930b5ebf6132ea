#include <gtest/gtest.h>

#include <cmath>

#include "pliant/articulated/contact.h"
#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "mesh_fixture.h"

namespace pliant::articulated {
namespace {

Model from_json(const nlohmann::json& j) {
  JsonReader r(j, "m.json");
  Model m = model_from_json(r);
  r.finish();
  return m;
}

// The JSON pointer of the InputError that model j raises, or "no error".
std::string json_error_pointer(const nlohmann::json& j) {
  try {
    from_json(j);
  } catch (const InputError& e) {
    return e.pointer();
  }
  return "no error";
}

TEST(ModelJson, BodiesJointsGeomsAndObstacles) {
  const nlohmann::json j = {
      {"gravity", {0, 0, -10}},
      {"bodies",
       {{{"name", "torso"},
         {"pos", {0, 0, 1}},
         {"joints", {{{"type", "slide"}, {"axis", {1, 0, 0}}, {"name", "x"}}}},
         {"geoms", {{{"type", "box"}, {"size", {0.1, 0.2, 0.3}}, {"mass", 2}}}}},
        {{"name", "leg"},
         {"parent", "torso"},
         {"joints", {{{"type", "hinge"}, {"axis", {0, 1, 0}}, {"name", "hip"}, {"range", {-0.5, 1.0}}}}},
         {"inertial", {{"mass", 1.5}, {"pos", {0, 0, -0.2}}, {"diaginertia", {0.1, 0.1, 0.01}}}}}}},
      {"actuators", {{{"joint", "hip"}, {"gear", 5}}}},
      {"obstacles", {{{"type", "plane"}}}}};
  const Model m = from_json(j);
  EXPECT_EQ(m.nv, 2);
  EXPECT_EQ(m.bodies[1].mass, 2);
  EXPECT_NEAR(m.bodies[1].inertia(0, 0), 2.0 / 12 * (0.16 + 0.36), 1e-12);
  EXPECT_EQ(m.bodies[2].mass, 1.5);
  EXPECT_EQ(m.gravity.z(), -10);
  EXPECT_EQ(m.geoms.back().body, 0);
  EXPECT_EQ(m.actuators[0].gear, 5);
  EXPECT_FALSE(m.joints[0].limited);
  EXPECT_TRUE(m.joints[1].limited);
  EXPECT_EQ(m.joints[1].range_min, -0.5);
  EXPECT_EQ(m.joints[1].range_max, 1.0);
}

TEST(ModelJson, ErrorsNameTheField) {
  const auto pointer_of = json_error_pointer;
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"parent", "nope"}}}}}), "/bodies/0/parent");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"geoms", {{{"type", "cone"}}}}}}}}), "/bodies/0/geoms/0/type");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"jionts", nlohmann::json::array()}}}}}), "/bodies/0/jionts");
  EXPECT_EQ(pointer_of({{"chain", {{"links", 0}}}}), "/chain/links");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"joints", {{{"range", {1, 0}}}}}}}}}), "/bodies/0/joints/0/range");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"joints", {{{"type", "ball"}, {"range", {-1, 1}}}}}}}}}),
            "/bodies/0/joints/0/range");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"joints", {{{"type", "free"}, {"range", {0, 1}}}}}}}}}),
            "/bodies/0/joints/0/range");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"joints", {{{"stiffness", -1}}}}}}}}), "/bodies/0/joints/0/stiffness");
  EXPECT_EQ(pointer_of({{"bodies", {{{"name", "a"}, {"joints", {{{"type", "ball"}, {"stiffness", 2}}}}}}}}),
            "/bodies/0/joints/0/stiffness");
}

// Cylinders and ellipsoids in JSON as in MJCF: the same masses, inertias and geom
// frames as the MJCF model of the same shapes (a cylinder by fromto, a posed
// ellipsoid), tessellated mesh geoms with support points against the plane; fromto on
// an ellipsoid names its field.
TEST(ModelJson, CylindersAndEllipsoidsCompileAsInMjcf) {
  const Model json = from_json(
      {{"bodies",
        {{{"name", "a"},
          {"pos", {0, 0, 1}},
          {"joints", {{{"type", "free"}}}},
          {"geoms", {{{"type", "cylinder"}, {"fromto", {0, 0, 0, 0.2, 0.1, 0.05}}, {"size", {0.03}}},
                     {{"type", "ellipsoid"}, {"size", {0.04, 0.06, 0.02}}, {"pos", {0.1, 0, 0}}, {"quat", {0.9, 0.1, 0.3, 0}}}}}}}},
       {"obstacles", {{{"type", "plane"}}}}});
  const Model mjcf = model_from_mjcf(
      "<mujoco><worldbody><geom type=\"plane\"/><body pos=\"0 0 1\"><freejoint/>"
      "<geom type=\"cylinder\" fromto=\"0.2 0.1 0.05 0 0 0\" size=\"0.03\"/>"
      "<geom type=\"ellipsoid\" size=\"0.04 0.06 0.02\" pos=\"0.1 0 0\" quat=\"0.9 0.1 0.3 0\"/></body></worldbody></mujoco>",
      "m.xml");
  EXPECT_NEAR(json.bodies[1].mass, mjcf.bodies[1].mass, 1e-12);
  EXPECT_NEAR(json.bodies[1].mass, 1000 * (M_PI * 0.03 * 0.03 * std::sqrt(0.0525) + 4.0 / 3 * M_PI * 0.04 * 0.06 * 0.02), 1e-9);
  EXPECT_LT((json.bodies[1].com - mjcf.bodies[1].com).norm(), 1e-12);
  EXPECT_LT((json.bodies[1].inertia - mjcf.bodies[1].inertia).norm(), 1e-12);
  int supports = 0;
  for (const ContactPoint& p : contact_points(json)) supports += p.support != PointSupport::Fixed;
  EXPECT_EQ(supports, 3);  // the cylinder's two rims, the ellipsoid
  for (int g : {0, 1}) {
    EXPECT_EQ(json.geoms[g].type, GeomType::Mesh);
    EXPECT_EQ(json.geoms[g].tessellates, mjcf.geoms[g + 1].tessellates);
    EXPECT_LT((json.geoms[g].pos - mjcf.geoms[g + 1].pos).norm(), 1e-12);
    EXPECT_LT((json.geoms[g].size - mjcf.geoms[g + 1].size).norm(), 1e-12);
    // Frames: the same axis (a cylinder's z may point either way along fromto).
    const Vec3 zj = json.geoms[g].quat * Vec3::UnitZ(), zm = mjcf.geoms[g + 1].quat * Vec3::UnitZ();
    EXPECT_NEAR(std::abs(zj.dot(zm)), 1, 1e-12);
  }
  EXPECT_EQ(json_error_pointer({{"bodies", {{{"name", "a"}, {"geoms", {{{"type", "ellipsoid"}, {"size", {0.1, 0.1, 0.1}},
                                                                 {"fromto", {0, 0, 0, 1, 0, 0}}}}}}}}}),
            "/bodies/0/geoms/0/fromto");
  EXPECT_EQ(json_error_pointer({{"bodies", {{{"name", "a"}, {"geoms", {{{"type", "cylinder"}, {"size", {0.1}}}}}}}}}),
            "/bodies/0/geoms/0/size");
}

// Joint springs and ref (as MJCF's): they reach the model, ref is the model-pose value
// (qpos0) of a slide.
TEST(ModelJson, JointSpringRefAndFriction) {
  const Model m = from_json({{"bodies",
                              {{{"name", "a"},
                                {"joints", {{{"type", "slide"}, {"axis", {0, 0, 1}}, {"stiffness", 40}, {"springref", 0.1},
                                             {"ref", 0.3}, {"frictionloss", 0.7}}}},
                                {"geoms", {{{"type", "sphere"}, {"size", {0.1}}}}}}}}});
  EXPECT_EQ(m.joints[0].frictionloss, 0.7);
  EXPECT_EQ(m.joints[0].stiffness, 40);
  EXPECT_EQ(m.joints[0].springref, 0.1);
  EXPECT_EQ(m.joints[0].ref, 0.3);
  EXPECT_EQ(m.qpos0[0], 0.3);
}

TEST(ModelJson, BodyContactFiltersAndExcludes) {
  const auto body = [](const char* name, nlohmann::json geom) {
    return nlohmann::json{{"name", name}, {"joints", {{{"type", "free"}}}}, {"geoms", {geom}}};
  };
  const nlohmann::json sphere = {{"type", "sphere"}, {"size", {0.1}}};
  nlohmann::json j = {{"bodies",
                       {body("a", sphere), body("b", sphere), body("c", {{"type", "sphere"}, {"size", {0.1}}, {"contact", false}}),
                        body("d", {{"type", "sphere"}, {"size", {0.1}}, {"contype", 2}, {"conaffinity", 2}})}},
                      {"exclude", {{{"body1", "b"}, {"body2", "a"}}}}};
  const Model m = from_json(j);
  EXPECT_EQ(m.geoms[2].contype, 0);  // "contact": false clears both masks
  EXPECT_EQ(m.geoms[3].conaffinity, 2);
  ASSERT_EQ(m.contact_exclude.size(), 1u);
  EXPECT_EQ(m.contact_exclude[0], (std::array<int, 2>{1, 2}));
  EXPECT_TRUE(contact_geom_pairs(m).empty());  // a-b excluded, c off, d's masks meet nobody's
  auto pointer_of = [](const nlohmann::json& bad) {
    try {
      from_json(bad);
    } catch (const InputError& e) {
      return e.pointer() + " | " + e.problem();
    }
    return std::string("no error");
  };
  nlohmann::json bad = j;
  bad["exclude"] = {{{"body1", "bb"}, {"body2", "a"}}};
  EXPECT_EQ(pointer_of(bad), "/exclude/0/body1 | no body named \"bb\"; did you mean \"b\"?");
  bad["exclude"] = {{{"body1", "a"}}};
  EXPECT_EQ(pointer_of(bad).substr(0, 16), "/exclude/0/body2");
  bad = j;
  bad["bodies"][0]["geoms"][0]["contype"] = -1;
  EXPECT_EQ(pointer_of(bad).substr(0, 26), "/bodies/0/geoms/0/contype ");
}

TEST(ModelJson, BallRangeIsAConeAngle) {
  const Model m = from_json({{"bodies",
                              {{{"name", "a"},
                                {"joints", {{{"type", "ball"}, {"range", {0, 0.6}}}}},
                                {"geoms", {{{"type", "sphere"}, {"size", {0.1}}}}}}}}});
  EXPECT_TRUE(m.joints[0].limited);
  EXPECT_EQ(m.joints[0].range_min, 0);
  EXPECT_EQ(m.joints[0].range_max, 0.6);
}

// Mesh geoms as in MJCF (file + scale; the same loader): equal mass properties and
// geometry, files relative to the model's folder; errors name the geom's field.
TEST(ModelJson, MeshGeomsMatchMjcf) {
  const std::string obj = test::write_box_obj("pliant_json_mesh", 0.1, 0.2, 0.05, 0.3, 0, 0);
  const std::filesystem::path path(obj);
  const nlohmann::json geom = {{"type", "mesh"}, {"file", path.filename().string()}, {"scale", {2, 1, 1}},
                               {"pos", {0, 0, 1}}};
  const nlohmann::json doc = {{"bodies", {{{"name", "a"}, {"joints", {{{"type", "free"}}}}, {"geoms", {geom}}}}}};
  JsonReader r(doc, "m.json");
  const Model json = model_from_json(r, path.parent_path());
  const Model mjcf = model_from_mjcf("<mujoco><asset><mesh name=\"b\" file=\"" + obj +
                                         "\" scale=\"2 1 1\"/></asset><worldbody><body><freejoint/>"
                                         "<geom type=\"mesh\" mesh=\"b\" pos=\"0 0 1\"/></body></worldbody></mujoco>",
                                     "m.xml");
  ASSERT_EQ(json.geoms[0].type, GeomType::Mesh);
  EXPECT_EQ(json.bodies[1].mass, mjcf.bodies[1].mass);
  EXPECT_NEAR(json.bodies[1].mass, 1000 * 0.4 * 0.4 * 0.1, 1e-6);  // scaled box 0.4 x 0.4 x 0.1
  EXPECT_EQ((json.bodies[1].inertia - mjcf.bodies[1].inertia).norm(), 0);
  EXPECT_EQ((json.geoms[0].pos - mjcf.geoms[0].pos).norm(), 0);
  EXPECT_EQ(json.geoms[0].mesh->vertices.size(), mjcf.geoms[0].mesh->vertices.size());

  auto pointer_of = [&](nlohmann::json g) {
    try {
      const nlohmann::json bad = {{"bodies", {{{"name", "a"}, {"geoms", {g}}}}}};
      JsonReader rr(bad, "m.json");
      model_from_json(rr, path.parent_path());
    } catch (const InputError& e) {
      return e.pointer() + " | " + e.problem();
    }
    return std::string("no error");
  };
  EXPECT_NE(pointer_of({{"type", "mesh"}}).find("/bodies/0/geoms/0/file"), std::string::npos);
  EXPECT_NE(pointer_of({{"type", "mesh"}, {"file", "no_such_file.obj"}}).find("/bodies/0/geoms/0/file"),
            std::string::npos);
  EXPECT_NE(pointer_of({{"type", "mesh"}, {"file", obj}, {"scale", {1, -1, 1}}}).find("/bodies/0/geoms/0/scale"),
            std::string::npos);
  EXPECT_NE(pointer_of({{"type", "mesh"}, {"file", obj}, {"size", {1}}}).find("/bodies/0/geoms/0/size"),
            std::string::npos);
  EXPECT_NE(pointer_of({{"type", "box"}, {"size", {1, 1, 1}}, {"file", obj}}).find("/bodies/0/geoms/0/file"),
            std::string::npos);
  EXPECT_NE(pointer_of({{"type", "mesh"}, {"file", obj}, {"scale", {1, 1}}}).find("/bodies/0/geoms/0/scale"),
            std::string::npos);
  std::filesystem::remove(obj);
}

TEST(ModelJson, ChainGeneratorMatchesMjcf) {
  const Model a = from_json({{"chain", {{"links", 3}, {"link_length", 0.2}}}});
  const Model b = model_from_mjcf(chain_mjcf(3, 0.2), "c.xml");
  EXPECT_EQ(a.nv, b.nv);
  EXPECT_EQ(a.bodies[3].mass, b.bodies[3].mass);
}

}  // namespace
}  // namespace pliant::articulated
