// Smoke: forward simulation on a MAC grid (2D and 3D). The public entry points
// the CLI, the editor and the keyframe-control solver call. Model is the
// compiled, read-only scene; State is a plain copyable struct (MuJoCo style).
#pragma once
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"

namespace pliant::smoke {

enum class Boundary { Closed, Periodic };
enum class Advection { SemiLagrangian, Upwind };
enum class PressureSolver { MultigridPCG, JacobiPCG };

// A region for sources and initial density.
struct Shape {
  enum Type { Sphere, Box } type = Sphere;
  std::array<double, 3> center_m{0, 0, 0};
  std::array<double, 3> half_size_m{0, 0, 0};  // box
  double radius_m = 0;                         // sphere (circle in 2D)
};

struct Source {
  Shape shape;
  double density_per_s = 1;                   // density added per second inside
  std::array<double, 3> velocity_m_per_s{0, 0, 0};  // velocity imposed inside
  double start_s = 0, end_s = 1e30;
};

struct ForceField {
  enum Type { Uniform, Vortex } type = Uniform;
  std::array<double, 3> acceleration_m_per_s2{0, 0, 0};  // uniform
  std::array<double, 3> center_m{0, 0, 0};               // vortex
  double radius_m = 0, strength_per_s = 0;               // vortex (about z in 2D)
};

struct SmokeModel {
  int dim = 2;                          // 2 or 3
  std::array<int, 3> n{1, 1, 1};        // cells per axis (n[2] = 1 in 2D)
  double cell_size_m = 0.01;
  Boundary boundary = Boundary::Closed;
  double dt_s = 0.02;                   // one frame
  int substeps = 1;
  int frames = 100;
  Advection advection = Advection::SemiLagrangian;
  double buoyancy_m_per_s2 = 1.0;       // upward acceleration per unit density
  std::array<double, 3> gravity_m_per_s2{0, 0, 0};
  PressureSolver pressure_solver = PressureSolver::MultigridPCG;
  double pressure_tolerance = 1e-6;     // relative residual
  int pressure_max_iterations = 200;
  std::vector<Source> sources;
  std::vector<ForceField> forces;
  std::vector<Shape> initial_density;   // density 1 inside
  bool write_velocity = true;
  int write_every = 1;
};

// Cell-centred density; face-centred velocity (MAC): u has (nx+1)*ny*nz values
// for closed boundaries and nx*ny*nz for periodic (same for v, w).
struct SmokeState {
  int frame = 0;
  double time_s = 0;
  std::vector<float> density;
  std::vector<float> u, v, w;
  std::vector<float> pressure;  // warm start for the next solve
};

struct StepStats {
  int pressure_iterations = 0;
  double pressure_residual = 0;
  double max_divergence = 0;  // after projection, in 1/s
  double total_density = 0;
};

SmokeModel smoke_compile(const Scene& scene);       // throws InputError
SmokeState smoke_init(const SmokeModel& m);
void smoke_step(const SmokeModel& m, SmokeState& s, StepStats* stats = nullptr);  // one frame
// Take record for the current state: "density" [ny,nx] or [nz,ny,nx]; "velocity"
// cell-centred [ny,nx,2] or [nz,ny,nx,3] when model.write_velocity.
Record smoke_frame_record(const SmokeModel& m, const SmokeState& s);

// Job kind "smoke" (forward simulation until the keyframe-control issue adds
// a "control" section).
nlohmann::json smoke_run_job(JobContext& ctx);
int smoke_job_frames(const Scene& scene);

}  // namespace pliant::smoke
