#include "pliant/core/scene.h"

#include <gtest/gtest.h>

#include "input_error_of.h"
#include "pliant/core/error.h"
#include "temp_dir.h"

namespace pliant {
namespace {

using test::error_of;

TEST(Scene, LoadsTheSampleScenes) {
  Scene s = load_scene(std::filesystem::path(PLIANT_ASSETS_DIR) / "scenes/plume_2d.json");
  EXPECT_EQ(s.kind, "smoke");
  EXPECT_EQ(s.name, "Rising plume (2D)");
  EXPECT_EQ(s.dir, std::filesystem::path(PLIANT_ASSETS_DIR) / "scenes");
  EXPECT_TRUE(s.doc.contains("grid"));
  EXPECT_EQ(load_scene(std::filesystem::path(PLIANT_ASSETS_DIR) / "scenes/plume_3d.json").kind, "smoke");
}

TEST(Scene, SyntaxErrorsGiveLineAndColumn) {
  const std::string text = "{\n  \"pliant\": 1,\n  \"kind\": smoke\n}\n";
  const std::string msg = error_of([&] { parse_scene(text, "a.json"); });
  EXPECT_EQ(msg.rfind("a.json: invalid JSON at line 3, column 11: ", 0), 0u) << msg;
  const std::string msg2 = error_of([&] { parse_scene("{\"pliant\": 1,", "b.json"); });
  EXPECT_EQ(msg2.rfind("b.json: invalid JSON at line 1, column ", 0), 0u) << msg2;
  // Found by fuzz_scene: nlohmann reports overflow as out_of_range, not parse_error.
  EXPECT_EQ(error_of([&] { parse_scene(R"({"pliant": 1, "x": 2e308})", "c.json"); }),
            "c.json: invalid JSON: number overflow parsing '2e308'");
}

TEST(Scene, EnvelopeChecks) {
  EXPECT_EQ(error_of([] { parse_scene("[1]", "a.json"); }), "a.json: expected a JSON object at the top level");
  EXPECT_EQ(error_of([] { parse_scene(R"({"kind": "smoke"})", "a.json"); }),
            "a.json: /pliant: missing required field; expected schema version 1");
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": 2, "kind": "smoke"})", "a.json"); }),
            "a.json: /pliant: expected schema version 1, got 2");
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": "1", "kind": "smoke"})", "a.json"); }),
            "a.json: /pliant: expected schema version 1, got \"1\"");
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": 1, "kind": "smok"})", "a.json"); }),
            "a.json: /kind: expected one of \"smoke\", \"liquid\", \"soft\", \"articulated\", got \"smok\"; "
            "did you mean \"smoke\"?");
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": 1})", "a.json"); }).rfind("a.json: /kind: missing required field", 0), 0u);
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": 1, "kind": "soft", "name": 3})", "a.json"); }),
            "a.json: /name: expected a string, got 3");
}

// The editor runs unsaved documents from a copy beside the take; "asset_dir"
// keeps their relative asset paths meaning the document's folder.
TEST(Scene, AssetDirMovesWhereRelativeAssetsStart) {
  Scene abs = parse_scene(R"({"pliant": 1, "kind": "soft", "asset_dir": "/work/scenes"})", "a.json", "/tmp/takes");
  EXPECT_EQ(abs.asset_path("../characters/spider.obj"), std::filesystem::path("/work/scenes/../characters/spider.obj"));
  Scene rel = parse_scene(R"({"pliant": 1, "kind": "soft", "asset_dir": "up"})", "a.json", "/data");
  EXPECT_EQ(rel.asset_path("m.obj"), std::filesystem::path("/data/up/m.obj"));
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": 1, "kind": "soft", "asset_dir": ""})", "a.json"); }),
            "a.json: /asset_dir: expected a folder path, got an empty string");
  EXPECT_EQ(error_of([] { parse_scene(R"({"pliant": 1, "kind": "soft", "asset_dir": 4})", "a.json"); }),
            "a.json: /asset_dir: expected a string, got 4");
}

TEST(Scene, OtherTopLevelKeysAreLeftToTheKind) {
  Scene s = parse_scene(R"({"pliant": 1, "kind": "liquid", "anything": [1, 2]})", "a.json", "/data");
  EXPECT_EQ(s.kind, "liquid");
  EXPECT_EQ(s.name, "");
  EXPECT_EQ(s.asset_path("meshes/cup.obj"), std::filesystem::path("/data/meshes/cup.obj"));
  EXPECT_EQ(s.asset_path("/abs/cup.obj"), std::filesystem::path("/abs/cup.obj"));
}

TEST(Scene, MissingFileNamesIt) {
  test::TempDir dir;
  const auto path = dir / "nope.json";
  EXPECT_EQ(error_of([&] { load_scene(path); }), path.string() + ": cannot read file: No such file or directory");
}

TEST(Scene, SaveJsonAtomicRoundTripsAndLeavesNoTempFiles) {
  test::TempDir dir;
  const auto path = dir / "s.json";
  nlohmann::json doc = {{"pliant", 1}, {"kind", "smoke"}, {"name", "x"}, {"v", {1.5, 2.5}}};
  save_json_atomic(path, doc);
  save_json_atomic(path, doc);  // replacing an existing file
  Scene s = load_scene(path);
  EXPECT_EQ(s.doc, doc);
  EXPECT_EQ(s.dir, dir.path());
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    ++files;
    EXPECT_EQ(e.path().filename(), "s.json");
  }
  EXPECT_EQ(files, 1u);
  EXPECT_THROW(save_json_atomic(dir / "missing-dir/s.json", doc), std::runtime_error);
}

}  // namespace
}  // namespace pliant
