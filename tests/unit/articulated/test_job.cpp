#include <gtest/gtest.h>

#include "pliant/articulated/articulated.h"
#include "pliant/core/error.h"

namespace pliant::articulated {
namespace {

Scene scene_of(const nlohmann::json& j) { return parse_scene(j.dump(), "s.json", PLIANT_ASSETS_DIR "/scenes"); }

TEST(Job, CompileReadsOptionsAndCountsFrames) {
  const Scene sc = scene_of({{"pliant", 1},
                             {"kind", "articulated"},
                             {"model", "../models/chain10.xml"},
                             {"integrator", "rk4"},
                             {"dt", 0.02},
                             {"duration_s", 1},
                             {"write_every", 5},
                             {"contact", {{"friction", "ck"}, {"ck", 3}}}});
  const ArticulatedScene a = articulated_compile(sc);
  EXPECT_EQ(a.options.integrator, Integrator::Rk4);
  EXPECT_EQ(a.steps, 50);
  EXPECT_EQ(a.frames, 11);
  EXPECT_EQ(a.options.contact.friction, FrictionModel::Ck);
  EXPECT_EQ(articulated_summary(sc)["nv"], 20);
}

TEST(Job, FrameRecordShapes) {
  const Scene sc = scene_of({{"pliant", 1}, {"kind", "articulated"}, {"model", {{"chain", {{"links", 3}}}}}});
  const ArticulatedScene a = articulated_compile(sc);
  SimWorkspace ws;
  const Record r = articulated_frame_record(a.model, a.options, a.initial, 0, ws);
  EXPECT_EQ(r.find("body_pose")->shape, (std::vector<uint32_t>{3, 7}));
  EXPECT_EQ(r.find("contacts")->shape, (std::vector<uint32_t>{0, 6}));
  const auto& e = r.find("energy")->data;
  EXPECT_NEAR(e[2], e[0] + e[1], 1e-6);
  EXPECT_FLOAT_EQ(r.find("body_pose")->data[3], 1.0f);  // qw of the first link
}

TEST(Job, BadFieldsNameTheirPointer) {
  auto pointer_of = [](const nlohmann::json& j) {
    try {
      articulated_compile(scene_of(j));
    } catch (const InputError& e) {
      return e.pointer();
    }
    return std::string("no error");
  };
  const nlohmann::json base = {{"pliant", 1}, {"kind", "articulated"}, {"model", {{"chain", {{"links", 2}}}}}};
  nlohmann::json j = base;
  j["initial"] = {{"qpos", {1, 2}}};
  EXPECT_EQ(pointer_of(j), "/initial/qpos");
  j = base;
  j["dt"] = -1;
  EXPECT_EQ(pointer_of(j), "/dt");
  j = base;
  j["mpc"] = {{"horizon", 3}};
  EXPECT_EQ(pointer_of(j), "/mpc/horizon");  // chain has no actuators
  j = base;
  j["model"] = "../models/missing.xml";
  EXPECT_EQ(pointer_of(j), "/model");
}

}  // namespace
}  // namespace pliant::articulated
