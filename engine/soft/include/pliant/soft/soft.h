// Soft characters that walk, jump and swim (dissertation chapter 4; Pan & Manocha,
// "Active animations of reduced deformable models with environment interactions",
// ACM TOG 37(3) 2018). Numerical choices (each file's header says why):
//   body       any triangle mesh -> hexahedral lattice (winding number + surface
//              cells), surface embedded by trilinear weights (body.h)
//   material   stable neo-Hookean, 2x2x2 Gauss points per hexahedron (fem.h)
//   reduction  linear modes in a floating frame x = R (Xbar + U q) + c; modes by a
//              dense eigensolver or CHOLMOD shift-invert subspace iteration (modes.h)
//   cubature   greedy non-negative least squares over training poses (cubature.h)
//   stepping   optimization-based implicit Euler, Gauss-Newton + line search (simulator.h)
//   environment penalty contact, lagged smoothed Coulomb friction, C1 drag (environment.h)
//   control    periodic DMP per controlled mode (dmp.h)
//   planning   shooting over DMP parameters; LM, L-BFGS or hybrid (objective.h, optimizer.h)
// Entry points for the CLI and the editor: soft_compile, soft_run_job, soft_job_frames,
// soft_summary. SoftModel is read-only after compile; SoftState is plain data.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "pliant/soft/body.h"
#include "pliant/soft/cubature.h"
#include "pliant/soft/objective.h"
#include "pliant/soft/optimizer.h"
#include "pliant/soft/simulator.h"

namespace pliant::soft {

struct SoftModel {
  Character character;
  RepairReport repair;
  Problem problem;             // optimization problem (horizon = problem.frames)
  OptimizerSettings optimizer;
  int frames = 100;            // frames written to the take (frame 0 = rest)
  CubatureReport cubature;     // cells == 0 when cubature is off
};

// problem.character points into the model: call after copying or moving a model.
inline void soft_bind(SoftModel& m) { m.problem.character = &m.character; }

// Compiles a "soft" scene (loads the mesh, builds lattice, modes and cubature).
// Throws InputError naming the file, JSON pointer and problem.
SoftModel soft_compile(const Scene& scene);

// Take record of a state: "vertices" [nverts, 3] (m), "com" [3] (m), and with
// with_triangles also "triangles" [ntris, 3] (vertex indices as f32).
Record soft_frame_record(const SoftModel& m, const SoftState& s, int index, bool with_triangles);

// Job kind "soft": optimizes the DMP parameters (checkpoints every iteration,
// --resume continues from the last), then re-simulates `frames` frames.
nlohmann::json soft_run_job(JobContext& ctx);
int soft_job_frames(const Scene& scene);
nlohmann::json soft_summary(const Scene& scene);

}  // namespace pliant::soft
