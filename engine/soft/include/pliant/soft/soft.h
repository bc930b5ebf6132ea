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
//   planning   shooting over DMP parameters; LM, L-BFGS or hybrid (objective.h, optimizer.h),
//              or spacetime LM over states, controls and theta (spacetime.h)
// Entry points for the CLI and the editor: soft_compile, soft_run_job, soft_job_frames,
// soft_summary; editor: soft_mode_shape, soft_optimize, soft_playback_start/step. SoftModel is read-only after compile; SoftState is plain data.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "pliant/soft/body.h"
#include "pliant/soft/cubature.h"
#include "pliant/soft/navigation.h"
#include "pliant/soft/objective.h"
#include "pliant/soft/optimizer.h"
#include "pliant/soft/simulator.h"
#include "pliant/soft/spacetime.h"

namespace pliant::soft {

struct SoftModel {
  Character character;
  RepairReport repair;
  Problem problem;             // optimization problem (horizon = problem.frames)
  OptimizerSettings optimizer;
  SpacetimeSettings spacetime; // optimizer.kind == Spacetime (iterations from optimizer)
  int frames = 100;            // frames written to the take (frame 0 = rest)
  CubatureReport cubature;     // cells == 0 when cubature is off
  NavSettings navigation;      // enabled: the job plans gait sequences to a goal
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

// ---- Editor-facing API (compile once, then preview, optimize and play back) ----
// After soft_compile + soft_bind: lattice cells m.character.lattice (rest nodes,
// cells, boundary_faces), surface m.character.surface (vertices, triangles), modes
// m.character.basis (U, omega2), m.character.mode_scale.

// Surface vertices of the body deformed by modal coordinates q (r values, in the
// rest frame: x = X + U q); lattice node positions (3N) too when nodes is given.
void soft_mode_shape(const SoftModel& m, const Eigen::VectorXd& q, std::vector<Eigen::Vector3d>& surface,
                     Eigen::VectorXd* nodes = nullptr);
// q for slider amplitudes in metres (largest node displacement of each mode):
// q_k = amplitude_k / mode_scale_k.
Eigen::VectorXd soft_q_from_amplitudes(const SoftModel& m, const Eigen::VectorXd& amplitude_m);

// Surface vertices of a simulated state (world frame).
void soft_state_surface(const SoftModel& m, const SoftState& s, std::vector<Eigen::Vector3d>& surface);

// Runs the scene's optimizer (shooting kinds, or spacetime_optimize; report filled
// for spacetime) from st (st.theta empty: initial_theta); on_iteration as in optimize
// (return false to stop). Returns the final objective.
double soft_optimize(const SoftModel& m, OptimizerState& st, const IterationFn& on_iteration = {},
                     SpacetimeReport* report = nullptr);

// theta from the latest checkpoint of a take written by the "soft" job; false when
// there is none or its size does not match the model's controller.
bool soft_take_theta(const std::string& take_dir, const SoftModel& m, Eigen::VectorXd* theta);

// Realtime playback of a controller: one call per frame (dt = problem.sim.dt_s).
struct SoftPlayback {
  Eigen::VectorXd theta;   // DMP parameters
  SoftState state;         // current body state (frame = state.frame)
  DmpState dmp;
  StepStats last;          // Newton statistics of the last step
  // Optional push for the next step (world force in N on every lattice node,
  // scaled by node mass / total mass); cleared after each step.
  Eigen::Vector3d push_n = Eigen::Vector3d::Zero();
  // Optional local push for the next step: force in N on each lattice node (3N,
  // sized to zeros by soft_playback_start; fill it with add_vertex_force to push at
  // a surface point). Added to push_n's share and handed to reduced_step's nodal
  // force, which projects it exactly (U^T R^T f on the modes, sum f on the COM,
  // sum y x f on the rotation). Zeroed after each step (size kept: no allocation).
  Eigen::VectorXd push_nodal;
  // Tracking feedback (0: open loop): PD on the controlled modal coordinates toward
  // q_ref (per frame, from soft_reference_q), added to the DMP force:
  //   u_k += omega_k^2 (kp (q_ref_k - q_k) + kd dt (qdot_ref_k - qdot_k)) at frame f.
  double track_kp = 0, track_kd = 0;
  std::vector<Eigen::VectorXd> q_ref;
};

// Modal coordinates q of frames 0..frames of the open-loop playback of theta (the
// trajectory the tracking controller follows).
std::vector<Eigen::VectorXd> soft_reference_q(const SoftModel& m, const Eigen::VectorXd& theta, int frames);
SoftPlayback soft_playback_start(const SoftModel& m, const Eigen::VectorXd& theta);
// Advances one frame (open loop DMP). Throws std::runtime_error naming the frame on NaN.
void soft_playback_step(const SoftModel& m, SoftPlayback& pb);

}  // namespace pliant::soft
