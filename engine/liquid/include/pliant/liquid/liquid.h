// Liquid transfer (dissertation chapter 2; ALGORITHMS.md section 1).
//
// Simulator (Algorithm 1 of the seed), numerical choices:
// - FLIP/PIC blend (flip_ratio, default 0.95) on a MAC grid, linear (tent)
//   transfer kernels, 2 particles per cell per axis seeded with jitter.
// - Particle-to-grid scatter without atomics: particles are counting-sorted by
//   cell every substep and the grid is cut into slabs of >= 3 cells along the
//   slowest axis; even slabs are splatted in parallel, then odd ones.
// - Free surface: ghost-fluid Dirichlet p = 0 at the liquid level set built from
//   the particles (Gibou et al. 2002); solid walls by cut-face fractions from
//   the solids' signed distance (Batty et al. 2007), so a moving container
//   drives the liquid through its boundary velocity (u = q on its walls).
// - Pressure: PCG with MIC(0) (Bridson's book, ch. 5), relative tolerance.
// - Viscosity: implicit backward-Euler diffusion per velocity component,
//   (I - dt mu/rho L) u* = u, Jacobi-PCG (components decoupled: exact for
//   constant mu away from the free surface).
// - Substeps: CFL on the largest particle/grid speed (cfl cells per substep).
// - Containers: analytic signed distance fields (cylinder, oval, box, cup with
//   handle, long bottle) or a closed triangle mesh (assimp) sampled into a
//   signed distance grid (ray-parity sign, exact distance in a band) in the
//   container's frame; the source moves along a
//   key-pose trajectory (translation + tilt about z, Catmull-Rom in time); the
//   target moves at a constant velocity (TRANSFER+FOLLOW; zero = static), its
//   walls impose that velocity on the liquid like the source's do.
#pragma once
#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"

namespace pliant::liquid {

using Vec3 = std::array<double, 3>;

struct MeshContainerField;  // a mesh container's sampled SDF and cavity (container_mesh.h)

// A container in its own frame: open top at y = height, floor at y = 0, axis +y.
// The solid wall is the shell between the cavity and the cavity grown by wall_m.
struct ContainerShape {
  enum Type { Cylinder, Oval, Box, Cup, Bottle, Mesh } type = Cylinder;
  double radius_m = 0.05;       // cavity radius (oval/box: half width along x)
  double depth_m = 0.05;        // oval/box: half width along z (3D only)
  double height_m = 0.12;
  double wall_m = 0.02;
  double neck_radius_m = 0.02;  // bottle: neck cavity radius
  double body_height_m = 0.12;  // bottle: height where the neck starts
  // Mesh: the sampled field (shared, read-only) and the file it came from. For a
  // mesh, radius_m / depth_m are the opening's half widths along x / z, wall_m
  // the wall at the rim, height_m the rim above the cavity floor.
  std::shared_ptr<const MeshContainerField> mesh;
  std::string mesh_file;
  // Signed distance to the solid wall (negative inside the wall material).
  double wall_sdf(const Vec3& local, int dim) const;
  // Inside the cavity (below the opening)?
  bool in_cavity(const Vec3& local, int dim) const;
  // Inside the cavity continued above the opening (the walls extended upward).
  bool in_extended_cavity(const Vec3& local, int dim) const;
  // Opening radius (bottle: neck) and the cavity's bounding half-widths.
  double opening_radius() const { return type == Bottle ? neck_radius_m : radius_m; }
  double cavity_volume(int dim) const;  // m^3 (2D: m^2 of the cross-section)
};

// Pose: position of the container origin and tilt about z (radians); positive
// tilt pours toward +x. Quaternion = rotation by -tilt about z.
struct Pose {
  Vec3 position_m{0, 0, 0};
  double tilt_rad = 0;
  Vec3 to_local(const Vec3& world) const;
  Vec3 to_world(const Vec3& local) const;
  std::array<float, 7> as_array() const;  // pos xyz + quat wxyz
};

struct KeyPose {
  double time_s = 0;
  Pose pose;
};

// Piecewise cubic (Catmull-Rom) in time through key poses; constant outside.
struct Trajectory {
  std::vector<KeyPose> keys;
  Pose at(double t) const;
  // Linear velocity (m/s) and tilt rate (rad/s) at t.
  void velocity(double t, Vec3* linear, double* tilt_rate) const;
};

struct Container {
  ContainerShape shape;
  Pose pose;              // static pose (target) or initial pose (source)
};

enum class Planner { None, Correction, Simplified, Feedback };

struct PlannerSettings {
  Planner planner = Planner::None;
  int iterations = 10;            // correction: MaxIterations of Algorithm 2
  int generations = 100;          // simplified: CMA-ES generations
  int population = 12;            // CMA-ES lambda
  int keys = 6;                   // trajectory key poses after the start
  bool fit_discharge = true;      // simplified: fit Cd to one full simulation
  int refine_iterations = 3;      // simplified: Algorithm 2 rounds on the CMA-ES plan (0 = none)
  double discharge_coefficient = 0.6;  // Cd when not fitted
  double pour_time_s = 1.5;       // duration of the planned pour
  double max_tilt_rad = 2.4;
  uint64_t seed = 1;
  // Feedback planner (feedback.h): predictor file ("" = the shipped default),
  // control interval and MPC horizon (intervals).
  std::string network;
  double interval_s = 0.1;
  int horizon = 4;
  // Dataset jobs: write the validation run's samples (and those of
  // `sample_rollouts` random monotone pours) into the metrics as "samples".
  bool record_samples = false;
  int sample_rollouts = 0;
};

struct LiquidModel {
  int dim = 2;
  Vec3 domain_min_m{0, 0, 0}, domain_max_m{1, 1, 1};
  std::array<int, 3> n{1, 1, 1};  // cells (n[2] = 1 in 2D)
  double cell_size_m = 0.02;
  Vec3 gravity_m_per_s2{0, -9.81, 0};
  double density_kg_per_m3 = 1000;
  double viscosity_pa_s = 0;      // dynamic viscosity mu
  double flip_ratio = 0.95;
  double cfl = 1.0;               // cells per substep
  int max_substeps = 64;
  double dt_s = 0.02;             // one frame
  int frames = 100;
  double pressure_tolerance = 1e-5;
  int pressure_max_iterations = 300;
  bool reseed = true;             // refill under-populated fluid cells
  Container source, target;
  bool has_source = true, has_target = true;
  Vec3 target_velocity_mps{0, 0, 0};  // constant; target.pose is its pose at t = 0
  Trajectory source_path;         // empty: the source stays at source.pose
  double fill_fraction = 0.6;     // source filled to this fraction of its height
  std::vector<std::pair<Vec3, Vec3>> liquid_boxes;  // extra liquid (min, max), e.g. dam break
  int particles_per_axis = 2;     // per cell per axis
  uint64_t seed = 1;
  PlannerSettings planner;
};

struct LiquidState {
  int frame = 0;
  double time_s = 0;
  std::vector<float> x, v;        // 3 floats per particle (z = 0 in 2D)
  long long substeps = 0;         // substeps taken so far
  size_t count() const { return x.size() / 3; }
};

struct StepStats {
  int substeps = 0;
  int pressure_iterations = 0;
  double max_speed = 0;
  // Wall seconds per phase (profiling; summed over substeps).
  double solids_s = 0, transfer_s = 0, pressure_s = 0, viscosity_s = 0, advect_s = 0;
};

LiquidModel liquid_compile(const Scene& scene);  // throws InputError
LiquidState liquid_init(const LiquidModel& m);
// Source pose at time t (the trajectory, or the static pose when it is empty).
Pose source_pose_at(const LiquidModel& m, double t);
// Target pose at time t: target.pose moved by target_velocity_mps * t.
Pose target_pose_at(const LiquidModel& m, double t);
inline bool target_moves(const LiquidModel& m) {
  return m.target_velocity_mps[0] != 0 || m.target_velocity_mps[1] != 0 || m.target_velocity_mps[2] != 0;
}
// Advances one frame (m.dt_s) with CFL substeps; throws std::runtime_error naming
// frame and field on NaN.
void liquid_step(const LiquidModel& m, LiquidState& s, StepStats* stats = nullptr);
// Advances by exactly dt (one substep, no CFL split): building block and tests.
void liquid_substep(const LiquidModel& m, LiquidState& s, double dt, StepStats* stats = nullptr);

// Fractions of particles in the target cavity, spilled, in the source cavity.
std::array<double, 3> liquid_fractions(const LiquidModel& m, const LiquidState& s);

// Take record: "particles" [n, dim], "speed" [n], "source_pose" [7],
// "target_pose" [7], "fractions" [3].
Record liquid_frame_record(const LiquidModel& m, const LiquidState& s);

nlohmann::json liquid_run_job(JobContext& ctx);
int liquid_job_frames(const Scene& scene);
nlohmann::json liquid_summary(const Scene& scene);

}  // namespace pliant::liquid
