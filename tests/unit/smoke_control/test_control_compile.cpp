// The scene's "control" section: the shipped scenes compile; invalid keyframes are
// InputErrors naming the JSON pointer (issue 3: frame past T, empty mask, mesh that
// fails to load, unreadable image).
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/geom/painted_grid.h"
#include "pliant/smoke/control.h"

namespace pliant::smoke {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(PLIANT_ASSETS_DIR) / "scenes";

// A 2D control scene with the given keyframes JSON (and optional 3D grid).
Scene scene_with(const std::string& keyframes, bool three_d = false, const std::string& extra = "") {
  const std::string grid = three_d ? R"("resolution": [8, 8, 8], "cell_size_m": 0.125)"
                                   : R"("resolution": [16, 16], "cell_size_m": 0.0625)";
  const std::string text = R"({"pliant": 1, "kind": "smoke", "grid": {)" + grid +
                           R"(}, "time": {"dt_s": 0.05, "frames": 10}, "control": {"method": "lbfgs", "r": 0.01,
     "initial_density": [{"type": "circle", "radius": 0.2}],
     "keyframes": )" + keyframes + extra + "}}";
  return parse_scene(text, "test_scene.json", std::filesystem::temp_directory_path());
}

std::string error_of(const Scene& s) {
  try {
    control_compile(s);
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "no error";
}

TEST(ControlCompile, CircleToSquareScene) {
  const Scene s = load_scene(kScenes / "smoke_circle_to_square.json");
  ASSERT_TRUE(scene_has_control(s));
  const ControlModel m = control_compile(s);
  EXPECT_EQ(m.sim.n[0], 32);
  EXPECT_EQ(m.sim.frames, 20);
  ASSERT_EQ(m.keyframes.size(), 1u);
  EXPECT_EQ(m.keyframes[0].frame, 20);
  double mass = 0, target = 0;
  for (float v : m.initial_density) mass += v;
  for (float v : m.keyframes[0].density) target += v;
  EXPECT_NEAR(mass, std::numbers::pi * 0.15 * 0.15 * 1024, 0.02 * mass);
  EXPECT_NEAR(target, 4 * 0.133 * 0.133 * 1024, 0.02 * target);
  EXPECT_EQ(m.method, ControlMethod::Admm);
}

TEST(ControlCompile, TextKeyframesOfTheFluidScene) {
  const Scene s = load_scene(kScenes / "smoke_fluid_letters.json");
  const ControlModel m = control_compile(s);
  ASSERT_EQ(m.keyframes.size(), 5u);
  for (const Keyframe& k : m.keyframes) {
    double ink = 0;
    for (float v : k.density) ink += v;
    EXPECT_GT(ink, 500) << k.source;  // a letter covers hundreds of 128^2 cells
    EXPECT_LT(ink, 0.3 * 128 * 128) << k.source;
  }
  EXPECT_EQ(m.keyframes[0].source, "text \"F\"");
}

TEST(ControlCompile, EveryShippedControlSceneCompilesWithMatchedMass) {
  // Incompressible flow cannot compress smoke: each keyframe must hold about the
  // initial mass, or its IoU is capped. The scenes size their targets for that.
  for (const char* name : {"smoke_circle_to_square.json", "smoke_circle_to_letter.json", "smoke_fluid_letters.json",
                           "smoke_circle_to_heart.json", "smoke_sphere_to_box_3d.json", "smoke_circles_to_bunny.json",
                           "smoke_sphere_to_bunny_3d.json"}) {
    const ControlModel m = control_compile(load_scene(kScenes / name));
    double mass = 0;
    for (float v : m.initial_density) mass += v;
    for (const Keyframe& k : m.keyframes) {
      double km = 0;
      for (float v : k.density) km += v;
      EXPECT_NEAR(km, mass, 0.04 * mass) << name << " " << k.source;
    }
  }
}

TEST(ControlCompile, SeveralTargetsAtOneFrameAreTheirUnionAndFramesAreUnique) {
  const std::string one = R"({"type": "circle", "center": [0.3, 0.5], "radius": 0.1})";
  const std::string two = R"({"type": "circle", "center": [0.7, 0.5], "radius": 0.1})";
  const ControlModel a = control_compile(scene_with(R"([{"frame": 4, "target": )" + one + "}]"));
  const ControlModel b = control_compile(scene_with(R"([{"frame": 4, "target": )" + two + "}]"));
  const ControlModel u = control_compile(scene_with(R"([{"frame": 4, "targets": [)" + one + ", " + two + "]}]"));
  ASSERT_EQ(u.keyframes.size(), 1u);
  for (size_t i = 0; i < u.keyframes[0].density.size(); ++i)
    ASSERT_FLOAT_EQ(u.keyframes[0].density[i],
                    std::min(1.0f, a.keyframes[0].density[i] + b.keyframes[0].density[i]));
  EXPECT_EQ(u.keyframes[0].source, "circle + circle");
  // Two keyframes at one frame would be two conflicting targets for one density.
  const Scene dup = scene_with(R"([{"frame": 4, "target": )" + one + R"(}, {"frame": 4, "target": )" + two + "}]");
  EXPECT_EQ(error_of(dup),
            "/control/keyframes/1/frame | frame 4 already has a keyframe; put several shapes in one keyframe's "
            "\"targets\"");
}

TEST(ControlCompile, FramePastTheEndNamesThePointer) {
  const Scene s = scene_with(R"([{"frame": 5, "target": {"type": "circle", "radius": 0.1}},
                                 {"frame": 11, "target": {"type": "circle", "radius": 0.1}}])");
  EXPECT_EQ(error_of(s), "/control/keyframes/1/frame | expected a frame in 1..10, got 11");
  const Scene z = scene_with(R"([{"frame": 0, "target": {"type": "circle", "radius": 0.1}}])");
  EXPECT_EQ(error_of(z), "/control/keyframes/0/frame | expected a frame in 1..10, got 0");
}

TEST(ControlCompile, EmptyMaskAndUnreadableImage) {
  const auto dir = std::filesystem::temp_directory_path();
  std::vector<unsigned char> black(16 * 16, 3);
  ASSERT_TRUE(stbi_write_png((dir / "pliant_black_mask.png").string().c_str(), 16, 16, 1, black.data(), 16));
  const Scene s = scene_with(R"([{"frame": 3, "target": {"type": "mask", "file": "pliant_black_mask.png"}}])");
  const std::string e = error_of(s);
  EXPECT_NE(e.find("/control/keyframes/0/target/file | pliant_black_mask.png: mask is empty after thresholding"),
            std::string::npos) << e;
  std::filesystem::remove(dir / "pliant_black_mask.png");
  std::ofstream(dir / "pliant_not_an_image.png") << "hello";
  const Scene u = scene_with(R"([{"frame": 3, "target": {"type": "image", "file": "pliant_not_an_image.png"}}])");
  const std::string eu = error_of(u);
  EXPECT_NE(eu.find("/control/keyframes/0/target/file | pliant_not_an_image.png: cannot read image"), std::string::npos)
      << eu;
  std::filesystem::remove(dir / "pliant_not_an_image.png");
}

TEST(ControlCompile, MeshErrors) {
  const Scene flat = scene_with(R"([{"frame": 3, "target": {"type": "mesh", "file": "bunny.obj"}}])");
  EXPECT_NE(error_of(flat).find("mesh targets need a 3D grid"), std::string::npos);
  const Scene missing = scene_with(R"([{"frame": 3, "target": {"type": "mesh", "file": "no_such_bunny.obj"}}])", true);
  EXPECT_NE(error_of(missing).find("/control/keyframes/0/target/file | no_such_bunny.obj: cannot load mesh"),
            std::string::npos)
      << error_of(missing);
}

TEST(ControlCompile, OtherBadInput) {
  EXPECT_EQ(error_of(scene_with("[]")), "/control/keyframes | expected at least one keyframe (\"keyframes\" or \"sequence\")");
  EXPECT_NE(error_of(scene_with(R"([{"frame": 3, "target": {"type": "text", "text": ""}}])")).find("empty text"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(R"([{"frame": 3, "target": {"type": "circle", "radius": 0.1, "center": [3, 3]}}])"))
                .find("target is empty"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(R"([{"frame": 3, "target": {"type": "circle", "radius": 0.1}}])", false,
                                R"(, "r": -1)"))
                .find("/control/r"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(R"([{"frame": 3, "target": {"type": "circle", "radius": 0.1, "colour": 1}}])"))
                .find("/control/keyframes/0/target/colour"),
            std::string::npos);
}

// rotation_axis (axis-angle with rotation_deg): any axis in 3D, +z only in 2D; a box
// turned 90 degrees about y has its long side along z. coarse_iterations and
// max_iterations 0 (ADMM with a polish only).
TEST(ControlCompile, RotationAxisAndIterationCounts) {
  const std::string rod = R"({"type": "box", "half_size": [0.3, 0.1, 0.1], "rotation_deg": 90, "rotation_axis": [0, 1, 0]})";
  const ControlModel m = control_compile(scene_with("[{\"frame\": 3, \"target\": " + rod + "}]", true));
  // Extent of the target along x and z (cells with density > 0.5).
  int lo[3] = {8, 8, 8}, hi[3] = {-1, -1, -1};
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i)
        if (m.keyframes[0].density[i + 8 * (j + 8 * k)] > 0.5f) {
          const int c[3] = {i, j, k};
          for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
        }
  EXPECT_GT(hi[2] - lo[2], 2 * (hi[0] - lo[0])) << "long side along z";
  EXPECT_NE(error_of(scene_with(R"([{"frame": 3, "target": {"type": "circle", "radius": 0.1, "rotation_axis": [1, 0, 0]}}])"))
                .find("/control/keyframes/0/target/rotation_axis | 2D targets turn about +z only"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(R"([{"frame": 3, "target": {"type": "sphere", "radius": 0.1, "rotation_axis": [0, 0, 0]}}])", true))
                .find("rotation_axis | expected a non-zero vector"),
            std::string::npos);
  const std::string kf = R"([{"frame": 3, "target": {"type": "circle", "radius": 0.1}}])";
  EXPECT_NE(error_of(scene_with(kf, false, R"(, "max_iterations": 0)")).find("/control/max_iterations"), std::string::npos);
  const ControlModel polish_only = control_compile(scene_with(
      kf, false, R"(, "method": "admm", "max_iterations": 0, "coarse_iterations": 7, "admm": {"polish_iterations": 5})"));
  EXPECT_EQ(polish_only.max_iterations, 0);
  EXPECT_EQ(polish_only.coarse_iterations, 7);
}

// A box keyframe turned 90 degrees about y (rotation_axis [0, 1, 0]) through the
// scene is voxel-exact the box with its x and z half sizes swapped (faces fall
// between the sub-samples); a zero turn about any axis is bitwise no turn; bad
// rotation fields name the field.
TEST(ControlCompile, PlacementTurnAboutYSwapsXAndZ) {
  auto density = [](const std::string& target) {
    return control_compile(scene_with("[{\"frame\": 3, \"target\": " + target + "}]", true)).keyframes[0].density;
  };
  const auto turned = density(R"({"type": "box", "half_size": [0.3, 0.1, 0.2], "rotation_deg": 90, "rotation_axis": [0, 1, 0]})");
  const auto swapped = density(R"({"type": "box", "half_size": [0.2, 0.1, 0.3]})");
  const auto plain = density(R"({"type": "box", "half_size": [0.3, 0.1, 0.2]})");
  const auto zero = density(R"({"type": "box", "half_size": [0.3, 0.1, 0.2], "rotation_deg": 0, "rotation_axis": [1, 2, 3]})");
  ASSERT_EQ(turned.size(), 512u);
  EXPECT_EQ(turned, swapped);
  EXPECT_NE(turned, plain);
  EXPECT_EQ(zero, plain);
  const std::string pre = R"([{"frame": 3, "target": {"type": "sphere", "radius": 0.1, )";
  EXPECT_NE(error_of(scene_with(pre + R"("rotation_axis": [0, 1]}}])", true)).find("/control/keyframes/0/target/rotation_axis"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(pre + R"("rotation_axis": [0, "y", 0]}}])", true))
                .find("/control/keyframes/0/target/rotation_axis/1 | expected a number"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(pre + R"("rotation_deg": "90"}}])", true))
                .find("/control/keyframes/0/target/rotation_deg | expected a number"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(pre + R"("rotation_deg": 1e301}}])", true)).find("/control/keyframes/0/target/rotation_deg"),
            std::string::npos);
}

TEST(ControlCompile, PaintedKeyframeFromTheEditor) {
  geom::PaintedGrid p;
  p.n = {16, 16, 1};
  p.value.assign(p.cells(), 0);
  for (int j = 2; j < 6; ++j)
    for (int i = 10; i < 14; ++i) p.value[i + 16 * j] = 255;
  const std::string kf =
      R"([{"frame": 4, "target": {"type": "painted", "size": [16, 16], "data": ")" + geom::encode_painted(p) + "\"}}]";
  const ControlModel m = control_compile(scene_with(kf));
  ASSERT_EQ(m.keyframes.size(), 1u);
  for (size_t c = 0; c < p.cells(); ++c) ASSERT_FLOAT_EQ(m.keyframes[0].density[c], p.value[c] / 255.0f) << c;
  EXPECT_NE(error_of(scene_with(R"([{"frame": 4, "target": {"type": "painted", "size": [16, 16], "data": "AAA="}}])"))
                .find("/control/keyframes/0/target/data | painted data: runs cover"),
            std::string::npos);
  EXPECT_NE(error_of(scene_with(R"([{"frame": 4, "target": {"type": "painted", "size": [16], "data": ""}}])"))
                .find("/control/keyframes/0/target/size"),
            std::string::npos);
}

TEST(ControlCompile, SequenceOfImages) {
  const auto dir = std::filesystem::temp_directory_path() / "pliant_seq";
  std::filesystem::create_directories(dir);
  std::vector<unsigned char> px(8 * 8, 0);
  for (int f = 2; f <= 6; f += 2) {
    px[size_t(f) * 8 + 3] = 255;
    px[size_t(f) * 8 + 4] = 255;
    char name[64];
    std::snprintf(name, sizeof name, "shape_%03d.png", f);
    ASSERT_TRUE(stbi_write_png((dir / name).string().c_str(), 8, 8, 1, px.data(), 8));
  }
  const Scene s = scene_with(R"([])", false,
                             R"(, "sequence": {"images": "pliant_seq/shape_%03d.png", "first_frame": 2, "every": 2,
                                 "height": 1.0, "weight": 0.5})");
  const ControlModel m = control_compile(s);
  ASSERT_EQ(m.keyframes.size(), 3u);  // frames 2, 4, 6 (8 is missing)
  EXPECT_EQ(m.keyframes[1].frame, 4);
  EXPECT_EQ(m.keyframes[1].weight, 0.5);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pliant::smoke
