// The job kinds this build of `pliant` can run, and a uniform refusal (exit 2,
// naming /kind) for scene kinds that exist in the schema but have no job yet.
#pragma once
#include <vector>

#include "pliant/core/job.h"
#include "pliant/core/scene.h"

namespace pliant::cli {

// One entry per kind of scene_kinds(); unimplemented ones throw InputError.
const std::vector<JobKind>& job_kinds();
// Throws InputError(scene.file, "/kind", "... not implemented yet ...") unless implemented.
void require_implemented(const Scene& scene);
// Compiles the scene with its kind's compiler (throws InputError) and returns
// {"kind", "frames", and where the kind has a grid "dim", "resolution"}.
nlohmann::json compile_summary(const Scene& scene);

}  // namespace pliant::cli
