// Job kinds: each engine module in this build registers its entry points
// (PLIANT_HAVE_<MODULE> is set by CMake when the module's target exists);
// schema kinds without a module are refused with exit 2 naming /kind.
#include "job_kinds.h"

#include <string>

#include "pliant/core/error.h"
#include "pliant/smoke/smoke.h"
#ifdef PLIANT_HAVE_ARTICULATED
#include "pliant/articulated/articulated.h"
#endif
#ifdef PLIANT_HAVE_LIQUID
#include "pliant/liquid/liquid.h"
#endif
#ifdef PLIANT_HAVE_SOFT
#include "pliant/soft/soft.h"
#endif

namespace pliant::cli {
namespace {

nlohmann::json smoke_summary(const Scene& scene) {
  const smoke::SmokeModel m = smoke::smoke_compile(scene);
  nlohmann::json res = nlohmann::json::array();
  for (int a = 0; a < m.dim; ++a) res.push_back(m.n[a]);
  return {{"dim", m.dim}, {"resolution", res}, {"frames", m.frames}};
}

const std::vector<JobKind>& implemented() {
  static const std::vector<JobKind> kinds = {
      {"smoke", &smoke::smoke_run_job, &smoke::smoke_job_frames, &smoke_summary},
#ifdef PLIANT_HAVE_ARTICULATED
      {"articulated", &articulated::articulated_run_job, &articulated::articulated_job_frames,
       &articulated::articulated_summary},
#endif
#ifdef PLIANT_HAVE_LIQUID
      {"liquid", &liquid::liquid_run_job, &liquid::liquid_job_frames, &liquid::liquid_summary},
#endif
#ifdef PLIANT_HAVE_SOFT
      {"soft", &soft::soft_run_job, &soft::soft_job_frames, &soft::soft_summary},
#endif
  };
  return kinds;
}

const JobKind* find_kind(const std::string& kind) {
  for (const JobKind& k : implemented())
    if (k.kind == kind) return &k;
  return nullptr;
}

std::string implemented_list() {
  std::string s;
  for (const JobKind& k : implemented()) s += (s.empty() ? "" : ", ") + k.kind;
  return s;
}

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
  if (find_kind(scene.kind)) return;
  throw InputError(scene.file, "/kind",
                   "kind \"" + scene.kind + "\" is not implemented yet (implemented: " +
                       implemented_list() + ")");
}

nlohmann::json compile_summary(const Scene& scene) {
  require_implemented(scene);
  const JobKind* k = find_kind(scene.kind);
  nlohmann::json s = k->summary ? k->summary(scene) : nlohmann::json{{"frames", k->frames(scene)}};
  s["kind"] = scene.kind;
  return s;
}

const std::vector<JobKind>& job_kinds() {
  static const std::vector<JobKind> kinds = [] {
    std::vector<JobKind> k;
    for (const std::string& kind : scene_kinds()) {
      if (const JobKind* impl = find_kind(kind)) {
        k.push_back(*impl);
      } else {
        k.push_back({kind, &not_implemented_run, &not_implemented_frames});
      }
    }
    return k;
  }();
  return kinds;
}

}  // namespace pliant::cli
