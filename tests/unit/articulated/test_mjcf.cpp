#include <gtest/gtest.h>

#include "pliant/articulated/io.h"
#include "pliant/core/error.h"

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
