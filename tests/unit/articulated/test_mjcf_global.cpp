// <compiler coordinate="global"> (mjcf_global.cpp): a gym-style hopper written in world
// coordinates compiles to the same model as its twin written in local ones; errors
// keep naming the element. (Against MuJoCo's own compiler: test_mujoco_reference.cpp.)
#include <gtest/gtest.h>

#include "pliant/articulated/io.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

const char* kGlobalHopper = R"(<mujoco><compiler angle="degree" coordinate="global" inertiafromgeom="true"/>
  <worldbody><geom type="plane" size="5 5 0.1"/>
    <body name="torso" pos="0 0 1.25">
      <joint name="rootx" type="slide" axis="1 0 0" pos="0 0 0"/>
      <joint name="rootz" type="slide" axis="0 0 1" pos="0 0 0"/>
      <joint name="rooty" axis="0 1 0" pos="0 0 1.25"/>
      <geom type="capsule" fromto="0 0 1.45 0 0 1.05" size="0.05"/>
      <body name="thigh" pos="0 0 1.05"><joint name="thigh_joint" axis="0 -1 0" pos="0 0 1.05"/>
        <geom type="capsule" fromto="0 0 1.05 0 0 0.6" size="0.05"/>
        <body name="leg" pos="0 0 0.35"><joint name="leg_joint" axis="0 -1 0" pos="0 0 0.6"/>
          <geom type="capsule" fromto="0 0 0.6 0 0 0.1" size="0.04"/>
          <body name="foot" pos="0.13 0 0.1"><joint name="foot_joint" axis="0 -1 0" pos="0 0 0.1"/>
            <geom type="capsule" fromto="-0.13 0 0.1 0.26 0 0.1" size="0.06"/>
          </body></body></body></body></worldbody></mujoco>)";

// The same hopper, every frame in its parent body's frame (worked out by hand).
const char* kLocalHopper = R"(<mujoco><compiler angle="degree" inertiafromgeom="true"/>
  <worldbody><geom type="plane" size="5 5 0.1"/>
    <body name="torso" pos="0 0 1.25">
      <joint name="rootx" type="slide" axis="1 0 0" pos="0 0 -1.25"/>
      <joint name="rootz" type="slide" axis="0 0 1" pos="0 0 -1.25"/>
      <joint name="rooty" axis="0 1 0" pos="0 0 0"/>
      <geom type="capsule" fromto="0 0 0.2 0 0 -0.2" size="0.05"/>
      <body name="thigh" pos="0 0 -0.2"><joint name="thigh_joint" axis="0 -1 0" pos="0 0 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.45" size="0.05"/>
        <body name="leg" pos="0 0 -0.7"><joint name="leg_joint" axis="0 -1 0" pos="0 0 0.25"/>
          <geom type="capsule" fromto="0 0 0.25 0 0 -0.25" size="0.04"/>
          <body name="foot" pos="0.13 0 -0.25"><joint name="foot_joint" axis="0 -1 0" pos="-0.13 0 0"/>
            <geom type="capsule" fromto="-0.26 0 0 0.13 0 0" size="0.06"/>
          </body></body></body></body></worldbody></mujoco>)";

TEST(MjcfGlobal, GymStyleHopperEqualsItsLocalTwin) {
  const Model g = model_from_mjcf(kGlobalHopper, "global.xml");
  const Model l = model_from_mjcf(kLocalHopper, "local.xml");
  ASSERT_EQ(g.bodies.size(), l.bodies.size());
  ASSERT_EQ(g.joints.size(), l.joints.size());
  ASSERT_EQ(g.geoms.size(), l.geoms.size());
  for (size_t b = 1; b < g.bodies.size(); ++b) {
    EXPECT_LT((g.bodies[b].pos - l.bodies[b].pos).norm(), 1e-12) << "body " << b;
    EXPECT_LT(g.bodies[b].quat.angularDistance(l.bodies[b].quat), 1e-12) << "body " << b;
    EXPECT_NEAR(g.bodies[b].mass, l.bodies[b].mass, 1e-12 * l.bodies[b].mass) << "body " << b;
    EXPECT_LT((g.bodies[b].com - l.bodies[b].com).norm(), 1e-12) << "body " << b;
    EXPECT_LT((g.bodies[b].inertia - l.bodies[b].inertia).norm(), 1e-12) << "body " << b;
  }
  for (size_t j = 0; j < g.joints.size(); ++j) {
    EXPECT_EQ(g.joints[j].name, l.joints[j].name);
    EXPECT_LT((g.joints[j].pos - l.joints[j].pos).norm(), 1e-12) << g.joints[j].name;
    EXPECT_LT((g.joints[j].axis - l.joints[j].axis).norm(), 1e-12) << g.joints[j].name;
  }
  for (size_t k = 0; k < g.geoms.size(); ++k) {
    EXPECT_EQ(g.geoms[k].body, l.geoms[k].body);
    EXPECT_LT((g.geoms[k].pos - l.geoms[k].pos).norm(), 1e-12) << "geom " << k;
    EXPECT_LT((g.geoms[k].size - l.geoms[k].size).norm(), 1e-12) << "geom " << k;
    // Capsules are symmetric about their axis: compare the axes.
    EXPECT_LT((g.geoms[k].quat * Vec3::UnitZ() - l.geoms[k].quat * Vec3::UnitZ()).norm(), 1e-12) << "geom " << k;
  }
  // The torso's frame in the world is where the global file put it.
  EXPECT_LT((g.bodies[1].pos - Vec3(0, 0, 1.25)).norm(), 1e-15);
}

TEST(MjcfGlobal, MalformedGlobalModelsNameTheElement) {
  const auto error_of = test::mjcf_error;
  const std::string head = "<mujoco><compiler coordinate=\"global\"/><worldbody><body pos=\"0 0 1\">";
  EXPECT_NE(error_of(head + "<geom type=\"capsule\" fromto=\"0 0 1 0 0 1\" size=\"0.1\"/></body></worldbody></mujoco>")
                .find("body[0]/geom[0]/@fromto | zero length"),
            std::string::npos);
  EXPECT_NE(error_of(head + "<geom type=\"sphere\" pos=\"0 0\" size=\"0.1\"/></body></worldbody></mujoco>")
                .find("body[0]/geom[0]/@pos"),
            std::string::npos);
  EXPECT_NE(error_of(head + "<joint axis=\"0 0 0\"/><geom size=\"0.1\"/></body></worldbody></mujoco>")
                .find("body[0]/joint[0]/@axis | axis is zero"),
            std::string::npos);
  EXPECT_NE(error_of("<mujoco><compiler coordinate=\"global\"/><worldbody><body euler=\"1 2\"><geom size=\"0.1\"/></body>"
                     "</worldbody></mujoco>")
                .find("body[0]/@euler"),
            std::string::npos);
}

}  // namespace
}  // namespace pliant::articulated
