// End-to-end: `pliant validate` / `pliant run` on articulated scenes (the real binary).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "cli_fixture.h"

namespace pliant::test {
namespace {

const std::string kAssets = (kRepo / "assets").string();

class ArticulatedCli : public CliTest {
 protected:
  // `pliant validate` on a scene whose model is this MJCF text.
  ProcessResult validate_mjcf(const std::string& xml) {
    write_text("model.xml", xml);
    const nlohmann::json scene = {{"pliant", 1}, {"kind", "articulated"}, {"model", "model.xml"}};
    return pliant({"validate", write_scene("s.json", scene).string()});
  }
};

TEST_F(ArticulatedCli, ChainSwingRunsAndWritesPosesContactsEnergy) {
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", kAssets + "/scenes/chain_swing.json", "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto events = parse_json_lines(r.out);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back()["event"], "done");
  EXPECT_EQ(events.back()["metrics"]["steps"], 500);
  TakeReader reader(take);
  ASSERT_EQ(reader.frame_count(), 501u);
  const Record last = reader.read_frame_at(500);
  ASSERT_NE(last.find("body_pose"), nullptr);
  EXPECT_EQ(last.find("body_pose")->shape, (std::vector<uint32_t>{10, 7}));
  EXPECT_EQ(last.find("contacts")->shape[1], 6u);
  EXPECT_EQ(last.find("energy")->shape, (std::vector<uint32_t>{3}));
  EXPECT_TRUE(all_finite(last));
  // Energy never grows (fully implicit scheme).
  const Record first = reader.read_frame_at(0);
  EXPECT_LE(last.find("energy")->data[2], first.find("energy")->data[2] + 1e-4f);
}

TEST_F(ArticulatedCli, SlidingBoxStopsAndReportsContacts) {
  const fs::path take = dir_ / "take";
  const ProcessResult r =
      pliant({"run", kAssets + "/scenes/articulated_box_slide.json", "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto events = parse_json_lines(r.out);
  EXPECT_NEAR(events.back()["metrics"]["root_displacement_m"].get<double>(), 0.408, 0.01);
  TakeReader reader(take);
  EXPECT_EQ(reader.read_frame_at(10).find("contacts")->shape[0], 4u);  // bottom corners
}

TEST_F(ArticulatedCli, ShortHopperMpcRuns) {
  std::ifstream in(kAssets + "/scenes/hopper_mpc.json");
  nlohmann::json scene = nlohmann::json::parse(in, nullptr, true, true);
  scene["model"] = kAssets + "/models/hopper2d.xml";
  scene["duration_s"] = 0.1;
  scene["mpc"]["samples"] = 8;
  scene["mpc"]["elites"] = 2;
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", write_scene("hopper.json", scene).string(), "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto events = parse_json_lines(r.out);
  EXPECT_TRUE(events.back()["metrics"].contains("distance_m"));
  EXPECT_TRUE(events.back()["metrics"].contains("airborne_fraction"));
  EXPECT_TRUE(events.back()["metrics"].contains("body1_max_tilt_rad"));
  // The motors do work: the energy's net change, not an integrator's drift.
  EXPECT_TRUE(events.back()["metrics"]["energy_change"].is_number());
  EXPECT_FALSE(events.back()["metrics"].contains("energy_drift"));
  EXPECT_EQ(TakeReader(take).frame_count(), 11u);
}

// A gym-style MJCF (default geom solref / solimp): `pliant validate` refuses it naming
// the attribute and the scene key; with "mjcf": {"ignore_solver_params": true}
// `validate --json` lists what is ignored and `pliant run` prints the list once on stderr and puts it in
// the metrics.
TEST_F(ArticulatedCli, GymStyleMjcfRunsWhenTheSceneIgnoresItsSolverParameters) {
  write_text("gym.xml", R"(<mujoco><default><geom solref=".02 1" solimp=".9 .95 .001"/></default><worldbody>
      <geom type="plane" size="5 5 0.1"/><body pos="0 0 0.5"><freejoint/><geom type="sphere" size="0.1"/></body>
      </worldbody></mujoco>)");
  nlohmann::json scene = {{"pliant", 1}, {"kind", "articulated"}, {"model", "gym.xml"}, {"duration_s", 0.05}};
  const ProcessResult refused = pliant({"validate", write_scene("s.json", scene).string()});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_TRUE(contains(refused.err, "@solref")) << refused.err;
  EXPECT_TRUE(contains(refused.err, "ignore_solver_params")) << refused.err;
  scene["mjcf"] = {{"ignore_solver_params", true}};
  const fs::path file = write_scene("s.json", scene);
  const ProcessResult valid = pliant({"validate", file.string(), "--json"});
  ASSERT_EQ(valid.exit_code, 0) << valid.err;
  EXPECT_EQ(nlohmann::json::parse(valid.out)["ignored_mjcf_attributes"].size(), 4u) << valid.out;
  const ProcessResult r = pliant({"run", file.string(), "--take", (dir_ / "take").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string line = "/mjcf/ignore_solver_params: 4 MJCF solver parameters without effect";
  const size_t at = r.err.find(line);
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(line, at + 1), std::string::npos) << "printed more than once:\n" << r.err;
  const auto events = parse_json_lines(r.out);
  ASSERT_EQ(events.back()["event"], "done");
  EXPECT_EQ(events.back()["metrics"]["ignored_mjcf_attributes"].size(), 4u);
}

TEST_F(ArticulatedCli, MalformedMjcfExitsTwoNamingTheElement) {
  const ProcessResult r =
      validate_mjcf("<mujoco><worldbody><body><geom type=\"capsule\" size=\"-1\"/></body></worldbody></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "/model")) << r.err;
  EXPECT_TRUE(contains(r.err, "/mujoco/worldbody[0]/body[0]/geom[0]/@size")) << r.err;
}

TEST_F(ArticulatedCli, MalformedDefaultsRangesAndMeshesExitTwoNamingTheField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"<mujoco><default><default class=\"leg\"/></default><worldbody><body><geom class=\"arm\" size=\"1\"/></body></worldbody></mujoco>",
       "/mujoco/worldbody[0]/body[0]/geom[0]/@class"},
      {"<mujoco><worldbody><body><joint limited=\"true\" range=\"1 -1\"/><geom size=\"1\"/></body></worldbody></mujoco>",
       "/mujoco/worldbody[0]/body[0]/joint[0]/@range"},
      {"<mujoco><worldbody><body euler=\"1 2\"><geom size=\"1\"/></body></worldbody></mujoco>",
       "/mujoco/worldbody[0]/body[0]/@euler"},
      {"<mujoco><asset><mesh name=\"m\" file=\"missing.obj\"/></asset></mujoco>", "/mujoco/asset[0]/mesh[0]/@file"},
      {"<mujoco><worldbody><body><geom type=\"mesh\" mesh=\"m\"/></body></worldbody></mujoco>",
       "/mujoco/worldbody[0]/body[0]/geom[0]/@mesh"}};
  for (const auto& [xml, where] : cases) {
    const ProcessResult r = validate_mjcf(xml);
    EXPECT_EQ(r.exit_code, 2) << xml;
    EXPECT_TRUE(contains(r.err, where)) << r.err;
  }
}

TEST_F(ArticulatedCli, MalformedSceneFieldExitsTwo) {
  const nlohmann::json scene = {{"pliant", 1},
                                {"kind", "articulated"},
                                {"model", {{"chain", {{"links", 2}}}}},
                                {"integrator", "pbad9"}};
  const ProcessResult r = pliant({"run", write_scene("s.json", scene).string(), "--take", (dir_ / "t").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err + r.out, "/integrator")) << r.err;
  const nlohmann::json scene2 = {{"pliant", 1},
                                 {"kind", "articulated"},
                                 {"model", {{"bodies", {{{"name", "a"}, {"geoms", {{{"type", "box"}, {"size", {1, 2}}}}}}}}}}};
  const ProcessResult r2 = pliant({"validate", write_scene("s2.json", scene2).string()});
  EXPECT_EQ(r2.exit_code, 2);
  EXPECT_TRUE(contains(r2.err, "/model/bodies/0/geoms/0/size")) << r2.err;
}

// pbad4 (the low-dissipation stencil) through the job: a 10-link chain released 30
// degrees from vertical at dt 0.05 keeps its energy several times better than pbad3.
TEST_F(ArticulatedCli, Pbad4KeepsTheChainsEnergyBetterThanPbad3) {
  double loss[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    std::vector<double> qpos(20, 0.0), qvel(20, 0.0);
    qpos[0] = 1.3;
    qvel[1] = 0.3;
    const nlohmann::json scene = {{"pliant", 1},
                                  {"kind", "articulated"},
                                  {"model", {{"chain", {{"links", 10}}}}},
                                  {"integrator", i == 0 ? "pbad3" : "pbad4"},
                                  {"dt", 0.05},
                                  {"duration_s", 2},
                                  {"initial", {{"qpos", qpos}, {"qvel", qvel}}}};
    // Literal names: GCC 12's -Wstringop-overflow misfired on "c" + std::to_string(i).
    const fs::path take = dir_ / (i == 0 ? "take0" : "take1");
    const ProcessResult r = pliant({"run", write_scene(i == 0 ? "c0.json" : "c1.json", scene).string(), "--take",
                                    take.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    TakeReader reader(take);
    ASSERT_EQ(reader.frame_count(), 41u);
    const float e0 = reader.read_frame_at(0).find("energy")->data[2];
    for (uint32_t f = 1; f < 41; ++f)
      loss[i] = std::max(loss[i], std::abs(double(reader.read_frame_at(f).find("energy")->data[2] - e0)));
  }
  EXPECT_GT(loss[0], 0.0);
  EXPECT_LT(loss[1], loss[0] / 4) << loss[0];
}

TEST_F(ArticulatedCli, JsonMeshGeomsAndBallRanges) {
  // A cube mesh next to the scene (relative to the scene's folder), ball joint cone.
  write_text("cube.obj",
             "v -0.1 -0.1 -0.1\nv 0.1 -0.1 -0.1\nv -0.1 0.1 -0.1\nv 0.1 0.1 -0.1\n"
             "v -0.1 -0.1 0.1\nv 0.1 -0.1 0.1\nv -0.1 0.1 0.1\nv 0.1 0.1 0.1\n"
             "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
             "f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n");
  auto scene_with = [](const nlohmann::json& joint, const nlohmann::json& geom) {
    return nlohmann::json{{"pliant", 1},
                          {"kind", "articulated"},
                          {"duration_s", 0.05},
                          {"model", {{"bodies", {{{"name", "a"}, {"pos", {0, 0, 1}}, {"joints", {joint}}, {"geoms", {geom}}}}}}}};
  };
  const nlohmann::json ball = {{"type", "ball"}, {"range", {0, 0.5}}};
  const nlohmann::json mesh = {{"type", "mesh"}, {"file", "cube.obj"}, {"scale", {1, 1, 2}}};
  const ProcessResult ok =
      pliant({"run", write_scene("ok.json", scene_with(ball, mesh)).string(), "--take", (dir_ / "t").string()});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {scene_with(ball, {{"type", "mesh"}, {"file", "missing.obj"}}), "/model/bodies/0/geoms/0/file"},
      {scene_with(ball, {{"type", "mesh"}, {"file", "cube.obj"}, {"scale", {0, 1, 1}}}), "/model/bodies/0/geoms/0/scale"},
      {scene_with({{"type", "ball"}, {"range", {-0.5, 0.5}}}, mesh), "/model/bodies/0/joints/0/range"}};
  for (const auto& [scene, where] : cases) {
    const ProcessResult r = pliant({"validate", write_scene("s.json", scene).string()});
    EXPECT_EQ(r.exit_code, 2) << scene.dump();
    EXPECT_TRUE(contains(r.err, where)) << r.err;
  }
}

// The sixth session's example scenes through `pliant run`: mesh tiles held by a sphere
// and by a box corner (exact corner contacts + face samples), and a ball joint kept
// inside its swing cone (scene joint_limits).
TEST_F(ArticulatedCli, MeshTilesRestOnASphereAndABoxCorner) {
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", kAssets + "/scenes/articulated_mesh_tile.json", "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  TakeReader reader(take);
  const Record last = reader.read_frame_at(reader.frame_count() - 1);
  const Field* pose = last.find("body_pose");
  ASSERT_NE(pose, nullptr);
  ASSERT_EQ(pose->shape, (std::vector<uint32_t>{2, 7}));
  // Sphere of radius 0.03 at the origin, tile 2 cm thick: centre 0.04 above it when held.
  EXPECT_NEAR(pose->data[2], 0.04, 0.005);
  // Box of half-size 0.04 standing on a corner: its top corner at 0.04 sqrt(3).
  EXPECT_NEAR(pose->data[7 + 2], 0.04 * std::sqrt(3.0) + 0.01, 0.005);
}

TEST_F(ArticulatedCli, BallJointStaysInsideItsSwingCone) {
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", kAssets + "/scenes/articulated_ball_limits.json", "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  TakeReader reader(take);
  double max_swing = 0;
  for (uint32_t f = 0; f < reader.frame_count(); ++f) {
    const Field* pose = reader.read_frame_at(f).find("body_pose");
    const double x = pose->data[4], y = pose->data[5];  // quaternion (w, x, y, z) after the position
    max_swing = std::max(max_swing, std::acos(std::clamp(1 - 2 * (x * x + y * y), -1.0, 1.0)));
  }
  EXPECT_GT(max_swing, 0.4);   // thrown hard enough to reach the cone
  EXPECT_LT(max_swing, 0.6);   // penalty limit: a little past 0.5 rad at most (1.2 rad without it)
}

TEST_F(ArticulatedCli, MjcfTendonIsRefusedNamingTheElement) {
  const ProcessResult r =
      validate_mjcf("<mujoco><worldbody><body><joint name=\"a\"/><geom size=\"0.1\"/></body></worldbody>"
                    "<tendon><fixed name=\"t\"><joint joint=\"a\" coef=\"1\"/></fixed></tendon></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "tendon")) << r.err;
}

// Body-body contact through `pliant run` (seventh session): the pile scene's bodies come
// to rest on each other instead of falling through to the ground, and a malformed MJCF
// <contact><exclude> exits 2 naming the attribute.
TEST_F(ArticulatedCli, PileBodiesRestOnEachOther) {
  const fs::path take = dir_ / "take";
  const ProcessResult r = pliant({"run", kAssets + "/scenes/articulated_pile.json", "--take", take.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  TakeReader reader(take);
  const Record last = reader.read_frame_at(reader.frame_count() - 1);
  ASSERT_TRUE(all_finite(last));
  const Field* pose = last.find("body_pose");
  ASSERT_NE(pose, nullptr);
  ASSERT_EQ(pose->shape, (std::vector<uint32_t>{6, 7}));
  // box_low (half-height 0.05) lies on the ground; box_mid (half-height 0.04) on box_low,
  // not at the ground's 0.04 it would reach through it.
  EXPECT_NEAR(pose->data[0 * 7 + 2], 0.05, 0.005);
  EXPECT_GT(pose->data[1 * 7 + 2], 0.05 + 0.05 + 0.04 - 0.01);
  const Field* contacts = last.find("contacts");
  ASSERT_NE(contacts, nullptr);
  EXPECT_GT(contacts->shape[0], 4u);  // more than the bottom box's ground corners
}

TEST_F(ArticulatedCli, MalformedContactExcludeExitsTwoNamingTheAttribute) {
  const ProcessResult r =
      validate_mjcf("<mujoco><worldbody><body name=\"a\"><freejoint/><geom size=\"0.1\"/></body></worldbody>"
                    "<contact><exclude body1=\"a\"/></contact></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "/mujoco/contact[0]/exclude[0]/@body2")) << r.err;
}

// A <pair> with condim 5 (not a MuJoCo value; 4 / 6 are torsional / rolling friction)
// exits 2 naming the attribute and the values allowed.
TEST_F(ArticulatedCli, ContactPairCondimFiveExitsTwoNamingTheAttribute) {
  const ProcessResult r = validate_mjcf(
      "<mujoco><worldbody><body name=\"a\"><freejoint/><geom name=\"ga\" size=\"0.1\"/></body>"
      "<body name=\"b\"><freejoint/><geom name=\"gb\" size=\"0.1\"/></body></worldbody>"
      "<contact><pair geom1=\"ga\" geom2=\"gb\" condim=\"5\"/></contact></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "/mujoco/contact[0]/pair[0]/@condim")) << r.err;
  EXPECT_TRUE(contains(r.err, "must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6")) << r.err;
}

// A geom with condim 2 or a negative friction coefficient (sliding or torsional) exits 2
// naming the geom's attribute; condim 4 and 6 validate.
TEST_F(ArticulatedCli, GeomCondimTwoAndNegativeFrictionExitTwoNamingTheAttribute) {
  ProcessResult r = validate_mjcf("<mujoco><worldbody><body><freejoint/><geom size=\"0.1\" condim=\"2\"/></body></worldbody></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "/mujoco/worldbody[0]/body[0]/geom[0]/@condim")) << r.err;
  EXPECT_TRUE(contains(r.err, "must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6")) << r.err;
  r = validate_mjcf("<mujoco><worldbody><body><freejoint/><geom size=\"0.1\" condim=\"6\" friction=\"1 0.01 0.001\"/></body></worldbody></mujoco>");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = validate_mjcf("<mujoco><worldbody><geom type=\"plane\" friction=\"1 -0.01\"/></worldbody></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "/mujoco/worldbody[0]/geom[0]/@friction")) << r.err;
  r = validate_mjcf("<mujoco><worldbody><geom type=\"plane\" friction=\"-1\"/></worldbody></mujoco>");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "/mujoco/worldbody[0]/geom[0]/@friction")) << r.err;
}

}  // namespace
}  // namespace pliant::test
