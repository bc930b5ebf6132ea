// Liquid scene edits (doc/liquid_scene_edit.cpp): key poses stay sorted with
// strictly increasing times and interpolated poses, moving a container moves
// its key poses, resizing needs an inline container, inlining reads the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "doc/liquid_scene_edit.h"

namespace pliant::editor {
namespace {

using nlohmann::json;

json pour_scene() {
  return {{"pliant", 1}, {"kind", "liquid"}, {"dim", 2},
          {"time", {{"dt_s", 0.02}, {"frames", 50}}},
          {"source", {{"container", "cyl.json"}, {"position_m", {0.0, 0.2}}, {"tilt_deg", 0},
                      {"trajectory", {{{"time_s", 0.0}, {"position_m", {0.0, 0.2}}, {"tilt_deg", 0}},
                                      {{"time_s", 0.8}, {"position_m", {0.08, 0.24}}, {"tilt_deg", 120}}}}}},
          {"target", {{"container", {{"shape", "cylinder"}, {"radius_m", 0.07}, {"height_m", 0.08}}},
                      {"position_m", {0.22, 0.0}}}}};
}

TEST(LiquidSceneEdit, DurationAndKeyTimes) {
  const json s = pour_scene();
  EXPECT_DOUBLE_EQ(liquid_duration_s(s), 1.0);
  EXPECT_EQ(liquid_key_times(s), (std::vector<double>{0.0, 0.8}));
  EXPECT_TRUE(liquid_key_times(json::object()).empty());
}

TEST(LiquidSceneEdit, AddKeyInterpolatesAndKeepsOrder) {
  int index = -1;
  const json s = liquid_add_key(pour_scene(), 0.2, &index);
  ASSERT_EQ(index, 1);
  EXPECT_EQ(liquid_key_times(s), (std::vector<double>{0.0, 0.2, 0.8}));
  const json& k = s["source"]["trajectory"][1];
  EXPECT_NEAR(k["position_m"][0].get<double>(), 0.02, 1e-12);
  EXPECT_NEAR(k["position_m"][1].get<double>(), 0.21, 1e-12);
  EXPECT_NEAR(k["tilt_deg"].get<double>(), 30.0, 1e-12);
  // After the last key: a copy of the last pose; at an existing time: refused.
  const json t = liquid_add_key(s, 0.9, &index);
  EXPECT_EQ(index, 3);
  EXPECT_EQ(t["source"]["trajectory"][3]["tilt_deg"], 120);
  EXPECT_EQ(liquid_add_key(t, 0.2005, &index), t);
  EXPECT_EQ(index, -1);
}

TEST(LiquidSceneEdit, FirstKeyTakesTheStaticPose) {
  json s = pour_scene();
  s["source"].erase("trajectory");
  s["source"]["tilt_deg"] = 10;
  int index = -1;
  const json t = liquid_add_key(s, 0.4, &index);
  ASSERT_EQ(index, 0);
  EXPECT_EQ(t["source"]["trajectory"][0]["position_m"], json({0.0, 0.2}));
  EXPECT_EQ(t["source"]["trajectory"][0]["tilt_deg"], 10);
}

TEST(LiquidSceneEdit, MoveKeyIsClampedBetweenNeighbours) {
  int index = -1;
  const json s = liquid_add_key(pour_scene(), 0.4, &index);
  const json a = liquid_move_key(s, 1, 0.5);
  EXPECT_DOUBLE_EQ(liquid_key_times(a)[1], 0.5);
  const std::vector<double> past = liquid_key_times(liquid_move_key(s, 1, 2.0));
  EXPECT_LT(past[1], past[2]);
  const std::vector<double> before = liquid_key_times(liquid_move_key(s, 1, -1.0));
  EXPECT_GT(before[1], before[0]);
  EXPECT_EQ(liquid_move_key(s, 7, 0.1), s);  // out of range: unchanged
}

TEST(LiquidSceneEdit, DeleteKeyAndTheLastOne) {
  json s = liquid_delete_key(pour_scene(), 0);
  EXPECT_EQ(liquid_key_times(s), (std::vector<double>{0.8}));
  s = liquid_delete_key(s, 0);
  EXPECT_FALSE(s["source"].contains("trajectory"));
  EXPECT_EQ(liquid_delete_key(s, 0), s);
}

TEST(LiquidSceneEdit, MovingTheSourceMovesItsKeys) {
  const json s = liquid_move_container(pour_scene(), "source", 0.01, -0.02);
  EXPECT_NEAR(s["source"]["position_m"][0].get<double>(), 0.01, 1e-12);
  EXPECT_NEAR(s["source"]["position_m"][1].get<double>(), 0.18, 1e-12);
  EXPECT_NEAR(s["source"]["trajectory"][1]["position_m"][0].get<double>(), 0.09, 1e-12);
  EXPECT_NEAR(s["source"]["trajectory"][1]["position_m"][1].get<double>(), 0.22, 1e-12);
  const json t = liquid_move_container(pour_scene(), "target", 0.03, 0);
  EXPECT_NEAR(t["target"]["position_m"][0].get<double>(), 0.25, 1e-12);
  EXPECT_EQ(t["source"], pour_scene()["source"]);
}

TEST(LiquidSceneEdit, MovingAKeyPositionMovesOnlyThatKey) {
  const json s0 = pour_scene();
  const json s = liquid_move_key_position(s0, 1, 0.01, -0.02);
  const json& k = s["source"]["trajectory"][1];
  EXPECT_NEAR(k["position_m"][0].get<double>(), 0.09, 1e-12);
  EXPECT_NEAR(k["position_m"][1].get<double>(), 0.22, 1e-12);
  EXPECT_EQ(k["tilt_deg"], 120);
  EXPECT_EQ(k["time_s"], 0.8);
  EXPECT_EQ(s["source"]["trajectory"][0], s0["source"]["trajectory"][0]);
  EXPECT_EQ(s["source"]["position_m"], s0["source"]["position_m"]);
  EXPECT_EQ(liquid_move_key_position(s0, 2, 1, 1), s0);
  EXPECT_EQ(liquid_move_key_position(s0, -1, 1, 1), s0);
  const json t = liquid_set_key_tilt(s0, 0, 45.5);
  EXPECT_EQ(t["source"]["trajectory"][0]["tilt_deg"], 45.5);
  EXPECT_EQ(t["source"]["trajectory"][0]["position_m"], s0["source"]["trajectory"][0]["position_m"]);
  EXPECT_EQ(t["source"]["trajectory"][1], s0["source"]["trajectory"][1]);
  EXPECT_EQ(liquid_set_key_tilt(s0, 5, 10), s0);
}

TEST(LiquidSceneEdit, AdoptingAPlannedTrajectorySetsKeysAndPlannerNone) {
  json s0 = pour_scene();
  s0["planner"] = {{"mode", "correction"}, {"iterations", 2}};
  // As the job reports it: 3 coordinates in 2D.
  const json planned = {{{"time_s", 0.0}, {"position_m", {0.0, 0.2, 0.0}}, {"tilt_deg", 0.0}},
                        {{"time_s", 0.5}, {"position_m", {0.05, 0.21, 0.0}}, {"tilt_deg", 90.0}}};
  const json s = liquid_adopt_trajectory(s0, planned);
  EXPECT_EQ(s["planner"]["mode"], "none");
  EXPECT_EQ(s["planner"]["iterations"], 2);
  ASSERT_EQ(s["source"]["trajectory"].size(), 2u);
  EXPECT_EQ(s["source"]["trajectory"][1]["position_m"], json({0.05, 0.21}));
  EXPECT_EQ(s["source"]["trajectory"][1]["tilt_deg"], 90.0);
  EXPECT_EQ(s["source"]["trajectory"][1]["time_s"], 0.5);
  EXPECT_EQ(liquid_adopt_trajectory(s0, json::array()), s0);
  EXPECT_EQ(liquid_adopt_trajectory(s0, json()), s0);
}

TEST(LiquidSceneEdit, MeshFileBecomesAMeshContainer) {
  const json s = liquid_set_mesh_container(pour_scene(), "target", "meshes/mug.obj");
  EXPECT_EQ(s["target"]["container"], json({{"shape", "mesh"}, {"file", "meshes/mug.obj"}}));
  EXPECT_EQ(s["target"]["position_m"], pour_scene()["target"]["position_m"]);
  EXPECT_EQ(s["source"], pour_scene()["source"]);
  json no_source = pour_scene();
  no_source.erase("source");
  const json t = liquid_set_mesh_container(no_source, "source", "/abs/cup.stl");
  EXPECT_EQ(t["source"]["position_m"], json({0.0, 0.0}));
  EXPECT_EQ(t["source"]["container"]["file"], "/abs/cup.stl");
  EXPECT_TRUE(liquid_is_mesh_file("a/b/Mug.OBJ"));
  EXPECT_TRUE(liquid_is_mesh_file("x.stl"));
  EXPECT_TRUE(liquid_is_mesh_file("x.ply"));
  EXPECT_FALSE(liquid_is_mesh_file("x.json"));
  EXPECT_FALSE(liquid_is_mesh_file("obj"));
}

TEST(LiquidSceneEdit, ResizeNeedsInlineAndInliningReadsTheFile) {
  const json s = pour_scene();
  EXPECT_FALSE(liquid_container_is_inline(s, "source"));
  EXPECT_TRUE(liquid_container_is_inline(s, "target"));
  EXPECT_EQ(liquid_resize_container(s, "source", 0.1, 0.1), s);
  const json t = liquid_resize_container(s, "target", 0.05, 0.1);
  EXPECT_EQ(t["target"]["container"]["radius_m"], 0.05);
  EXPECT_EQ(t["target"]["container"]["height_m"], 0.1);

  const auto dir = std::filesystem::temp_directory_path() / ("liquid_edit_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cyl.json") << R"({"comment": "x", "shape": "cylinder", "radius_m": 0.04, "height_m": 0.1})";
  json u = s;
  std::string err;
  ASSERT_TRUE(liquid_inline_container(&u, "source", dir, &err)) << err;
  EXPECT_EQ(u["source"]["container"], json({{"shape", "cylinder"}, {"radius_m", 0.04}, {"height_m", 0.1}}));
  json v = s;
  EXPECT_FALSE(liquid_inline_container(&v, "source", dir / "missing", &err));
  EXPECT_NE(err.find("cyl.json"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(LiquidSceneEdit, LibraryListsJsonFilesSorted) {
  const auto dir = std::filesystem::temp_directory_path() / ("liquid_lib_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "b.json") << "{}";
  std::ofstream(dir / "a.json") << "{}";
  std::ofstream(dir / "notes.txt") << "";
  const auto lib = liquid_container_library(dir);
  ASSERT_EQ(lib.size(), 2u);
  EXPECT_EQ(lib[0].filename(), "a.json");
  EXPECT_EQ(lib[1].filename(), "b.json");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pliant::editor
