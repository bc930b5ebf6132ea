// `pliant validate SCENE [--json]`: loads the scene and compiles it with its
// kind's compiler, so every error a run would hit on input is reported here.
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "job_kinds.h"
#include "pliant/core/error.h"
#include "pliant/core/scene.h"

namespace pliant::cli {
namespace {

struct ValidateOptions {
  std::string scene;
  bool json = false;
};

int validate(const ValidateOptions& o) {
  try {
    const Scene scene = load_scene(o.scene);
    nlohmann::json s = compile_summary(scene);
    if (o.json) {
      s["file"] = o.scene;
      s["ok"] = true;
      std::printf("%s\n", s.dump().c_str());
    } else {
      std::string grid;
      if (s.contains("resolution")) {
        std::string res;
        for (const auto& n : s["resolution"]) {
          if (!res.empty()) res += 'x';
          res += std::to_string(int(n));
        }
        grid = std::to_string(int(s["dim"])) + "D " + res + ", ";
      }
      std::printf("%s: ok (%s, %s%d frames)\n", o.scene.c_str(), scene.kind.c_str(),
                  grid.c_str(), int(s["frames"]));
    }
    return kExitDone;
  } catch (const InputError& e) {
    if (o.json) {
      nlohmann::json j = {{"file", o.scene},       {"ok", false},
                          {"pointer", e.pointer()}, {"problem", e.problem()},
                          {"message", e.what()}};
      std::printf("%s\n", j.dump().c_str());
    } else {
      std::fprintf(stderr, "%s\n", e.what());
    }
    return kExitInvalid;
  }
}

}  // namespace

void add_validate_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<ValidateOptions>();
  CLI::App* sub = app.add_subcommand(
      "validate", "Check a scene: prints \"SCENE: ok (...)\" or the problem (file, JSON "
                  "pointer, what was expected) on stderr with exit 2");
  sub->add_option("scene", opt->scene, "Scene JSON file")->required();
  sub->add_flag("--json", opt->json, "One JSON object on stdout instead of text");
  sub->callback([opt, &action] { action = [opt] { return validate(*opt); }; });
}

}  // namespace pliant::cli
