#include <gtest/gtest.h>

#include "pliant/core/error.h"
#include "pliant/liquid/liquid.h"
#include "pliant/liquid/problem_generator.h"

namespace pliant::liquid {
namespace {

const char* kGood = R"({
  "pliant": 1, "kind": "liquid", "dim": 2,
  "domain": {"min_m": [-0.1, 0], "max_m": [0.3, 0.3], "cell_size_m": 0.01},
  "source": {"container": {"shape": "cylinder", "radius_m": 0.04, "height_m": 0.1, "wall_m": 0.012},
             "position_m": [0, 0.1],
             "trajectory": [{"time_s": 0, "position_m": [0, 0.1]}, {"time_s": 1, "position_m": [0, 0.1], "tilt_deg": 90}]},
  "target": {"container": {"shape": "box", "radius_m": 0.06, "height_m": 0.06}, "position_m": [0.2, 0]}
})";

std::string problem_of(nlohmann::json doc) {
  try {
    liquid_compile(parse_scene(doc.dump(), "scene.json"));
  } catch (const InputError& e) {
    return e.pointer() + ": " + e.problem();
  }
  return "";
}

TEST(LiquidCompile, GoodSceneCompiles) {
  const LiquidModel m = liquid_compile(parse_scene(kGood, "scene.json"));
  EXPECT_EQ(m.dim, 2);
  EXPECT_EQ(m.n[0], 40);
  EXPECT_EQ(m.n[1], 30);
  EXPECT_EQ(m.source_path.keys.size(), 2u);
  EXPECT_NEAR(m.source_path.keys[1].pose.tilt_rad, 3.14159265358979 / 2, 1e-12);
  EXPECT_EQ(m.target.shape.type, ContainerShape::Box);
  EXPECT_GT(liquid_init(m).count(), 50u);
  EXPECT_FALSE(target_moves(m));
  auto d = nlohmann::json::parse(kGood);
  d["target"]["velocity_mps"] = {0.05, -0.01};
  const LiquidModel mv = liquid_compile(parse_scene(d.dump(), "scene.json"));
  EXPECT_TRUE(target_moves(mv));
  EXPECT_EQ(mv.target_velocity_mps, (Vec3{0.05, -0.01, 0}));
  EXPECT_NEAR(target_pose_at(mv, 2.0).position_m[0], 0.2 + 0.1, 1e-12);
}

TEST(LiquidCompile, ErrorsNameTheirPointer) {
  const auto good = nlohmann::json::parse(kGood);
  EXPECT_EQ(problem_of({{"pliant", 1}, {"kind", "liquid"}}).rfind("/domain:", 0), 0u);
  auto d = good;
  d["source"]["container"]["wall_m"] = 0.002;
  EXPECT_NE(problem_of(d).find("/source/container: wall_m"), std::string::npos) << problem_of(d);
  d = good;
  d["source"]["trajectory"][1]["time_s"] = 0;
  EXPECT_EQ(problem_of(d).rfind("/source/trajectory/1/time_s", 0), 0u) << problem_of(d);
  d = good;
  d["source"]["container"]["shape"] = "cilinder";
  EXPECT_NE(problem_of(d).find("cylinder"), std::string::npos) << problem_of(d);  // suggestion
  d = good;
  d["liquid"] = {{"viscosty_pa_s", 0.1}};
  EXPECT_NE(problem_of(d).find("viscosity_pa_s"), std::string::npos) << problem_of(d);
  d = good;
  d["source"]["container"] = "no/such/container.json";
  EXPECT_EQ(problem_of(d).rfind("/source/container", 0), 0u) << problem_of(d);
  d = good;
  d["target"]["velocity_mps"] = {0.1};
  EXPECT_EQ(problem_of(d).rfind("/target/velocity_mps", 0), 0u) << problem_of(d);
  d = good;
  d["planner"] = {{"mode", "simplified"}};
  d.erase("target");
  EXPECT_EQ(problem_of(d).rfind("/planner/mode", 0), 0u) << problem_of(d);
}

TEST(LiquidCompile, ContainerFilesOfTheAssetsLoad) {
  for (const char* name : {"cylinder", "oval", "box", "cup", "bottle", "target_basin", "mug"}) {
    auto d = nlohmann::json::parse(kGood);
    d["dim"] = 3;
    d["domain"]["min_m"] = {-0.1, 0, -0.1};
    d["domain"]["max_m"] = {0.3, 0.4, 0.1};
    d["source"]["container"] = std::string(PLIANT_ASSETS_DIR) + "/containers/" + name + ".json";
    d["source"]["position_m"] = {0, 0.1, 0};
    d["source"].erase("trajectory");
    d["target"]["position_m"] = {0.2, 0, 0};
    EXPECT_EQ(problem_of(d), "") << name;
  }
}

}  // namespace
}  // namespace pliant::liquid

namespace pliant::liquid {
namespace {

// "problem": a generator problem as a scene (dataset sweeps); the split is checked.
TEST(LiquidCompile, GeneratorProblemScene) {
  const nlohmann::json doc = {{"pliant", 1}, {"kind", "liquid"}, {"dim", 2},
                              {"problem", {{"seed", 2026}, {"id", 7}}},
                              {"planner", {{"mode", "simplified"}, {"record_samples", true}, {"sample_rollouts", 2}}}};
  const LiquidModel m = liquid_compile(parse_scene(doc.dump(), "scene.json"));
  const LiquidModel g = generate_problem(7, 2026, 2).model;
  EXPECT_EQ(m.target.pose.position_m, g.target.pose.position_m);
  EXPECT_EQ(m.fill_fraction, g.fill_fraction);
  EXPECT_EQ(m.planner.planner, Planner::Simplified);
  EXPECT_TRUE(m.planner.record_samples);
  EXPECT_EQ(m.planner.sample_rollouts, 2);
  nlohmann::json held = doc;
  held["problem"]["id"] = 10;
  EXPECT_EQ(problem_of(held).rfind("/problem/id: problem 10 is held out", 0), 0u) << problem_of(held);
  held["problem"]["split"] = "held_out";
  EXPECT_EQ(problem_of(held), "");
  nlohmann::json extra = doc;
  extra["domain"] = nlohmann::json::object();
  EXPECT_EQ(problem_of(extra).rfind("/domain:", 0), 0u);
  nlohmann::json net = doc;
  net["planner"]["mode"] = "feedback";
  net["planner"]["network"] = "no_such_net.json";
  EXPECT_EQ(problem_of(net).rfind("/planner/network: cannot read", 0), 0u) << problem_of(net);
}

}  // namespace
}  // namespace pliant::liquid
