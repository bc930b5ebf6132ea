// Soft scene helpers of the editor (doc/soft_scene.h): tolerant reading of the
// scene for drawing, the goal used for framing, and pin edits of the
// partial-keyframe objective.
#include "doc/soft_scene.h"

#include <gtest/gtest.h>

namespace pliant::editor {
namespace {

using nlohmann::json;

json spider() {
  return json::parse(R"({"pliant": 1, "kind": "soft", "name": "s",
    "environment": {"type": "ground", "ground_height_m": -0.1},
    "simulation": {"dt_s": 0.05, "frames": 40, "start_offset_m": [0, 0.2, 0]},
    "objectives": {"velocity": {"target_m_per_s": [0.2, 0, 0.1], "weight": 10},
                   "heading": {"body_axis": [2, 0, 0], "direction": [0, 0, 3]},
                   "jump": {"height_m": 0.15}},
    "optimizer": {"horizon_frames": 12}})");
}

TEST(SoftScene, ReadsWhatTheViewportDraws) {
  const SoftSceneInfo in = soft_scene_info(spider());
  EXPECT_FALSE(in.water);
  EXPECT_TRUE(in.ground);
  EXPECT_DOUBLE_EQ(in.ground_y, -0.1);
  EXPECT_DOUBLE_EQ(in.dt_s, 0.05);
  EXPECT_EQ(in.frames, 40);
  EXPECT_EQ(in.horizon, 12);
  EXPECT_DOUBLE_EQ(in.start_offset[1], 0.2);
  ASSERT_TRUE(in.has_heading);
  EXPECT_DOUBLE_EQ(in.heading_axis[0], 1.0);      // normalized
  EXPECT_DOUBLE_EQ(in.heading_direction[2], 1.0);
  ASSERT_TRUE(in.has_jump);
  EXPECT_DOUBLE_EQ(in.jump_height, 0.15);
  EXPECT_FALSE(in.has_position);
}

TEST(SoftScene, DefaultsAndBrokenFieldsNeverThrow) {
  const SoftSceneInfo water = soft_scene_info(json::parse(R"({"kind": "soft", "environment": {"type": "water"}})"));
  EXPECT_TRUE(water.water);
  EXPECT_FALSE(water.ground);  // no ground in water unless asked
  EXPECT_EQ(water.horizon, 60);
  const SoftSceneInfo broken = soft_scene_info(
      json::parse(R"({"simulation": {"dt_s": "x", "frames": 10}, "objectives": {"position": {"target_m": [1, 2]}}})"));
  EXPECT_DOUBLE_EQ(broken.dt_s, 1.0 / 30);
  EXPECT_EQ(broken.horizon, 10);  // min(frames, 60)
  EXPECT_TRUE(broken.has_position);
  EXPECT_DOUBLE_EQ(broken.position_target[0], 0.0);  // wrong length: default
  EXPECT_NO_THROW(soft_scene_info(json(42)));
  const SoftSceneInfo obstacles = soft_scene_info(json::parse(R"({"environment": {"obstacles": [
      {"type": "sphere", "center_m": [1, 0, 2], "radius_m": 0.3}, {"type": "plane"}, {"radius_m": -1}]}})"));
  ASSERT_EQ(obstacles.spheres.size(), 1u);  // planes and broken spheres are not drawn
  EXPECT_DOUBLE_EQ(obstacles.spheres[0].center[2], 2.0);
  EXPECT_DOUBLE_EQ(obstacles.spheres[0].radius, 0.3);
}

TEST(SoftScene, GoalIsTargetOrWhereTheVelocityCarriesTheBody) {
  SoftSceneInfo in = soft_scene_info(spider());
  const SoftVec3 g = soft_goal(in, {1, 0, 0});
  EXPECT_NEAR(g[0], 1 + 0.2 * 40 * 0.05, 1e-12);  // 2 s at 0.2 m/s
  EXPECT_NEAR(g[2], 0.1 * 40 * 0.05, 1e-12);
  in.has_position = true;
  in.position_target = {3, 4, 5};
  EXPECT_EQ(soft_goal(in, {1, 0, 0}), (SoftVec3{3, 4, 5}));
}

TEST(SoftScene, PinsJoinEntriesOfTheSameFrameAndOffset) {
  json s = soft_with_pin(spider(), 5, 12, {0.1, 0, 0});
  ASSERT_TRUE(s["objectives"].contains("keyframes"));
  EXPECT_EQ(s["objectives"]["keyframes"]["weight"], 10);
  s = soft_with_pin(s, 5, 3, {0.1, 0, 0});   // same frame and offset: same entry
  s = soft_with_pin(s, 5, 7, {0.2, 0, 0});   // other offset: new entry
  s = soft_with_pin(s, 9, 12, {0, 0, 0});    // other frame
  const json& frames = s["objectives"]["keyframes"]["frames"];
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0]["vertices"], json({12, 3}));
  EXPECT_EQ(soft_pins(s).size(), 4u);
  EXPECT_EQ(soft_pins_at(s, 5).size(), 3u);
  // Re-pinning moves the vertex; unpinning the last vertex of an entry drops it.
  s = soft_with_pin(s, 5, 12, {0.2, 0, 0});
  EXPECT_EQ(s["objectives"]["keyframes"]["frames"][0]["vertices"], json({3}));
  EXPECT_EQ(soft_pins_at(s, 5).size(), 3u);
  s = soft_without_pin(s, 9, 12);
  EXPECT_EQ(s["objectives"]["keyframes"]["frames"].size(), 2u);
  EXPECT_TRUE(soft_pins_at(s, 9).empty());
  // Other objectives are left alone.
  EXPECT_EQ(s["objectives"]["velocity"], spider()["objectives"]["velocity"]);
}

}  // namespace
}  // namespace pliant::editor
