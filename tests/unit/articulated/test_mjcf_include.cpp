// MJCF <include> (mjcf_include.cpp): spliced in place, nested, paths from the main
// file's folder; a missing, repeated or empty include exits naming the include.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "pliant/articulated/io.h"
#include "pliant/core/error.h"

namespace pliant::articulated {
namespace {

namespace fs = std::filesystem;

struct Files {
  fs::path dir = fs::temp_directory_path() / ("pliant_mjcf_include_" + std::to_string(::getpid()));
  Files() { fs::create_directories(dir / "parts"); }
  ~Files() { fs::remove_all(dir); }
  fs::path write(const std::string& rel, const std::string& text) const {
    std::ofstream(dir / rel) << text;
    return dir / rel;
  }
};

const char* kDefaults = R"(<mujoco><default><geom type="capsule" size="0.02" density="700"/>
  <default class="heavy"><geom density="3000"/></default></default></mujoco>)";
const char* kArm = R"(<mujoco><body name="arm" pos="0 0 1"><joint axis="0 1 0"/>
  <geom fromto="0 0 0 0.3 0 0"/><include file="parts/hand.xml"/></body></mujoco>)";
const char* kHand = R"(<mujoco><body name="hand" pos="0.3 0 0"><joint axis="0 0 1"/>
  <geom class="heavy" type="sphere" size="0.04"/></body></mujoco>)";

// The same model written in one file.
const char* kWhole = R"(<mujoco><default><geom type="capsule" size="0.02" density="700"/>
  <default class="heavy"><geom density="3000"/></default></default>
  <worldbody><geom type="plane" size="1 1 0.1"/>
  <body name="arm" pos="0 0 1"><joint axis="0 1 0"/><geom fromto="0 0 0 0.3 0 0"/>
    <body name="hand" pos="0.3 0 0"><joint axis="0 0 1"/><geom class="heavy" type="sphere" size="0.04"/></body>
  </body></worldbody></mujoco>)";

TEST(MjcfInclude, IncludedFilesSpliceInPlaceAndNest) {
  Files f;
  f.write("parts/defaults.xml", kDefaults);
  f.write("parts/arm.xml", kArm);
  f.write("parts/hand.xml", kHand);  // included from parts/arm.xml, named from the main file's folder
  const fs::path main = f.write("main.xml", R"(<mujoco><include file="parts/defaults.xml"/>
    <worldbody><geom type="plane" size="1 1 0.1"/><include file="parts/arm.xml"/></worldbody></mujoco>)");
  const Model split = model_load_file(main, "main.xml");
  const Model whole = model_from_mjcf(kWhole, "whole.xml");
  ASSERT_EQ(split.bodies.size(), 3u);
  ASSERT_EQ(split.bodies.size(), whole.bodies.size());
  ASSERT_EQ(split.geoms.size(), whole.geoms.size());
  EXPECT_EQ(split.nv, whole.nv);
  for (size_t b = 0; b < whole.bodies.size(); ++b) {
    EXPECT_EQ(split.bodies[b].name, whole.bodies[b].name);
    EXPECT_EQ(split.bodies[b].parent, whole.bodies[b].parent);
    EXPECT_DOUBLE_EQ(split.bodies[b].mass, whole.bodies[b].mass) << b;
  }
  // The hand's class from the included defaults: a 3000 kg/m^3 sphere.
  EXPECT_NEAR(split.bodies[2].mass, 3000 * 4.0 / 3.0 * M_PI * 0.04 * 0.04 * 0.04, 1e-9);
}

std::string error_of(const fs::path& main) {
  try {
    model_load_file(main, "main.xml");
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "";
}

TEST(MjcfInclude, MissingRepeatedOrEmptyIncludesNameTheInclude) {
  Files f;
  const std::string missing = error_of(f.write("a.xml", R"(<mujoco><worldbody><include file="nowhere.xml"/></worldbody></mujoco>)"));
  EXPECT_NE(missing.find("/mujoco/worldbody[0]/include[0]/@file | cannot read included file"), std::string::npos) << missing;
  EXPECT_NE(missing.find("nowhere.xml"), std::string::npos) << missing;
  f.write("parts/hand.xml", kHand);
  const std::string twice = error_of(f.write(
      "b.xml", R"(<mujoco><worldbody><include file="parts/hand.xml"/><include file="parts/hand.xml"/></worldbody></mujoco>)"));
  EXPECT_NE(twice.find("/mujoco/worldbody[0]/include[1]/@file"), std::string::npos) << twice;
  EXPECT_NE(twice.find("more than once"), std::string::npos) << twice;
  f.write("parts/empty.xml", "<mujoco/>");
  const std::string empty = error_of(f.write("c.xml", R"(<mujoco><include file="parts/empty.xml"/></mujoco>)"));
  EXPECT_NE(empty.find("has nothing below"), std::string::npos) << empty;
  const std::string no_file = error_of(f.write("d.xml", R"(<mujoco><include/></mujoco>)"));
  EXPECT_NE(no_file.find("/mujoco/include[0]/@file"), std::string::npos) << no_file;
  // A broken included file's XML error names that file.
  f.write("parts/broken.xml", "<mujoco><body></mujoco>");
  try {
    model_load_file(f.write("e.xml", R"(<mujoco><worldbody><include file="parts/broken.xml"/></worldbody></mujoco>)"), "e.xml");
    ADD_FAILURE() << "a broken included file loaded";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("broken.xml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pliant::articulated
