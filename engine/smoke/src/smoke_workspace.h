// Scratch memory of smoke_step, kept out of SmokeState so the state stays a plain
// copyable struct (MuJoCo's mjData holds its own arena; we keep ours beside it).
// Choice: one workspace per calling thread (thread_local cache), rebuilt only when
// the grid changes. So step() allocates on the first call for a grid and never
// again, and two threads stepping different states never share scratch.
#pragma once
#include <vector>

#include "mac_grid.h"
#include "pressure_projection.h"

namespace pliant::smoke {

// Seconds spent per phase by smoke_step on this thread, summed since the last
// reset (the benchmark's profile; perf is not available everywhere).
struct StepTimings {
  double forces_s = 0, advect_velocity_s = 0, project_s = 0, advect_density_s = 0;
  long long substeps = 0;
};

struct SmokeWorkspace {
  explicit SmokeWorkspace(const MacGrid& g);
  bool fits(const MacGrid& g) const;

  MacGrid grid;
  PoissonSolver poisson;
  std::vector<float> u0, v0, w0;      // frozen copy of the velocity being advected
  std::vector<float> density_tmp;     // advected density / upwind scratch
  std::vector<float> face_tmp;        // upwind scratch for one velocity component
  std::vector<double> phi, rhs;       // projection potential and right-hand side
  StepTimings timings;
};

// The calling thread's workspace for grid g (created or rebuilt when g changes).
SmokeWorkspace& smoke_workspace(const MacGrid& g);
// The MAC grid of a model.
MacGrid model_grid(const SmokeModel& m);

}  // namespace pliant::smoke
