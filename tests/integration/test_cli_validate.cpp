// `pliant validate`, `--help`, `--version` and input errors of `run`.
#include <fstream>
#include <iterator>

#include "cli_fixture.h"
#include "pliant/core/version.h"

namespace pliant::test {
namespace {

using Validate = CliTest;

TEST_F(Validate, AcceptsASmallScene) {
  const fs::path scene = write_scene("ok.json", smoke_scene(32, 24, 30));
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, scene.string() + ": ok (smoke, 2D 32x24, 30 frames)\n");
  EXPECT_EQ(r.err, "");
}

TEST_F(Validate, JsonOutput) {
  const fs::path scene = write_scene("ok.json", smoke_scene(32, 24, 30));
  const ProcessResult r = pliant({"validate", "--json", scene.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ok"], true);
  EXPECT_EQ(j["kind"], "smoke");
  EXPECT_EQ(j["dim"], 2);
  EXPECT_EQ(j["resolution"], nlohmann::json({32, 24}));
  EXPECT_EQ(j["frames"], 30);
}

// Every shipped scene (assets/scenes/*.json) compiles with its kind's compiler, so an
// engine change that breaks one fails here rather than on a user's first run, and each
// is listed in assets/scenes/README.md. About 3 s in all.
TEST_F(Validate, EveryShippedSceneValidatesAndIsListed) {
  const fs::path dir = kRepo / "assets" / "scenes";
  std::ifstream readme_in(dir / "README.md");
  const std::string readme((std::istreambuf_iterator<char>(readme_in)), std::istreambuf_iterator<char>());
  int scenes = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    ++scenes;
    const std::string name = e.path().filename().string();
    const ProcessResult r = pliant({"validate", "--json", e.path().string()});
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.out << r.err;
    if (r.exit_code == 0) {
      EXPECT_EQ(nlohmann::json::parse(r.out)["ok"], true) << name;
    }
    EXPECT_NE(readme.find("`" + name + "`"), std::string::npos) << name << " is not in assets/scenes/README.md";
  }
  EXPECT_GE(scenes, 30);
}

TEST_F(Validate, BadValueNamesFileAndPointer) {
  auto doc = smoke_scene(32, 32, 30);
  doc["grid"]["resolution"][0] = -3;
  const fs::path scene = write_scene("bad_resolution.json", doc);
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(contains(r.err, scene.string())) << r.err;
  EXPECT_TRUE(contains(r.err, "/grid/resolution/0")) << r.err;
  EXPECT_TRUE(contains(r.err, "-3")) << r.err;

  const ProcessResult j = pliant({"validate", "--json", scene.string()});
  EXPECT_EQ(j.exit_code, 2);
  const auto parsed = nlohmann::json::parse(j.out);
  EXPECT_EQ(parsed["ok"], false);
  EXPECT_EQ(parsed["pointer"], "/grid/resolution/0");
}

TEST_F(Validate, UnknownFieldSuggestsNearestName) {
  auto doc = smoke_scene(32, 32, 30);
  doc.erase("buoyancy_m_per_s2");
  doc["buoyancy_m_per_s"] = 2.0;
  const fs::path scene = write_scene("typo.json", doc);
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, scene.string())) << r.err;
  EXPECT_TRUE(contains(r.err, "/buoyancy_m_per_s")) << r.err;
  EXPECT_TRUE(contains(r.err, "did you mean \"buoyancy_m_per_s2\"")) << r.err;
}

TEST_F(Validate, SyntaxErrorNamesLine) {
  const fs::path scene = write_text("syntax.json", "{\"pliant\": 1,\n \"kind\": \"smoke\",,}");
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, scene.string())) << r.err;
  EXPECT_TRUE(contains(r.err, "line 2")) << r.err;
}

TEST_F(Validate, UnimplementedKindNamesKindPointer) {
  // "liquid" is implemented now: a bare liquid scene is refused for its first
  // missing field, named by its JSON pointer, by validate and by run alike.
  const fs::path scene = write_text("liquid.json", R"({"pliant": 1, "kind": "liquid"})");
  const ProcessResult r = pliant({"validate", scene.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, scene.string())) << r.err;
  EXPECT_TRUE(contains(r.err, "/domain")) << r.err;
  EXPECT_FALSE(contains(r.err, "not implemented yet")) << r.err;

  const ProcessResult run = pliant({"run", scene.string(), "--take", (dir_ / "take").string()});
  EXPECT_EQ(run.exit_code, 2);
  const auto events = parse_json_lines(run.out);
  ASSERT_EQ(events.size(), 1u) << run.out;
  EXPECT_EQ(events[0]["event"], "error");
  EXPECT_TRUE(contains(events[0]["message"], "/domain"));
  EXPECT_FALSE(fs::exists(dir_ / "take"));  // invalid input leaves no take
}

TEST_F(Validate, RunRefusesInvalidSceneWithExit2AndJsonError) {
  auto doc = smoke_scene(32, 32, 30);
  doc["time"]["dt_s"] = "fast";
  const fs::path scene = write_scene("bad_dt.json", doc);
  const ProcessResult r = pliant({"run", scene.string(), "--take", (dir_ / "take").string()});
  EXPECT_EQ(r.exit_code, 2);
  const auto events = parse_json_lines(r.out);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back()["event"], "error");
  const std::string message = events.back()["message"];
  EXPECT_TRUE(contains(message, "/time/dt_s")) << message;
  EXPECT_TRUE(contains(message, scene.string())) << message;
}

TEST_F(Validate, HelpOnEverySubcommandAndVersion) {
  for (const char* sub : {"run", "validate", "info", "export", "plugins", "sweep"}) {
    const ProcessResult r = pliant({sub, "--help"});
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_TRUE(contains(r.out, "Usage:")) << sub << ": " << r.out;
    EXPECT_TRUE(contains(r.out, sub)) << r.out;
  }
  const ProcessResult v = pliant({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_TRUE(contains(v.out, kEngineVersion)) << v.out;
  const ProcessResult none = pliant({});
  EXPECT_EQ(none.exit_code, 2);  // a subcommand is required
  const ProcessResult missing = pliant({"run", "x.json"});  // --take is required
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(contains(missing.err, "--take")) << missing.err;
}

}  // namespace
}  // namespace pliant::test
