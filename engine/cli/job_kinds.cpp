// Job kinds: "smoke" runs the smoke simulator; the other schema kinds are
// accepted by load_scene but refused here until their solvers exist.
#include "job_kinds.h"

#include <string>

#include "pliant/core/error.h"
#include "pliant/smoke/smoke.h"

namespace pliant::cli {
namespace {

bool is_implemented(const std::string& kind) { return kind == "smoke"; }

nlohmann::json not_implemented_run(JobContext& ctx) {
  require_implemented(ctx.scene);
  return nlohmann::json::object();
}

int not_implemented_frames(const Scene& scene) {
  require_implemented(scene);
  return 0;
}

}  // namespace

void require_implemented(const Scene& scene) {
  if (is_implemented(scene.kind)) return;
  throw InputError(scene.file, "/kind",
                   "kind \"" + scene.kind + "\" is not implemented yet (implemented: smoke)");
}

const std::vector<JobKind>& job_kinds() {
  static const std::vector<JobKind> kinds = [] {
    std::vector<JobKind> k;
    for (const std::string& kind : scene_kinds()) {
      if (kind == "smoke") {
        k.push_back({kind, &smoke::smoke_run_job, &smoke::smoke_job_frames});
      } else {
        k.push_back({kind, &not_implemented_run, &not_implemented_frames});
      }
    }
    return k;
  }();
  return kinds;
}

}  // namespace pliant::cli
