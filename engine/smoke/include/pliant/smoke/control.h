// Keyframe control of smoke (Pan & Manocha, "Efficient solver for spacetime
// control of smoke", ACM TOG 2017; ALGORITHMS.md section 2). Public entry points.
//
// Model (per frame i = 0..T-1, grid units as in smoke.h):
//   u_{i+1}   = P( A_sl(u_i, u_i) + dt f_i )     velocity: self-advection, force, projection
//   rho_{i+1} = A_up(rho_i, u_{i+1})             density: conservative upwind (Eq. 3.2)
// Objective:
//   E(f) = sum_k w_k ||rho_{t_k} - rho*_k||^2 + r sum_i ||f_i||^2
// (plain sums over cells / faces, no cell-volume factor, so r means the same at
// every resolution only up to a factor h^dim; scenes state r for their grid).
// Two solvers minimise E: ADMM with a spacetime multigrid (the paper's method,
// `method: "admm"`) and L-BFGS with discrete-adjoint gradients (the baseline,
// `method: "lbfgs"`). Forces found by either are checked by control_evaluate,
// which re-simulates them with the plain forward model above.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pliant/core/progress.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/smoke.h"

namespace pliant::smoke {

// A face-velocity-shaped array per frame: u faces, then v faces, then w faces
// (counts as MacGrid::face_count), concatenated. Used for forces and velocities.
using FaceSeries = std::vector<std::vector<float>>;

struct Keyframe {
  int frame = 0;                 // 1..T
  double weight = 1.0;
  std::vector<float> density;    // target, one value per cell
  std::string source;            // what it came from ("text 'F'", "mask a.png", ...) for messages
};

// Resolution of a preview (a coarser level of the spacetime multigrid).
struct GridDims {
  int dim = 2;
  std::array<int, 3> n{1, 1, 1};
};

enum class ControlMethod { Admm, Lbfgs };

struct ControlModel {
  SmokeModel sim;                      // grid, boundary, dt_s (one frame), frames = T
  std::vector<float> initial_density;  // rho_0, one per cell
  std::vector<Keyframe> keyframes;     // sorted by frame
  std::vector<uint8_t> solid;          // obstacle cells (1 = solid); empty = none
  double r = 1e3;                      // ghost-force regularisation
  ControlMethod method = ControlMethod::Admm;
  int max_iterations = 50;             // ADMM outer loops or L-BFGS iterations
  double tolerance = 1e-4;             // relative stopping tolerance
  // ADMM specifics (ignored by L-BFGS).
  double admm_penalty = 1.0;           // beta of the augmented Lagrangian
  int ao_iterations = 10;              // fixed-point iterations per AO solve
  int nso_vcycles = 2;                 // FAS V-cycles per NSO solve (after the projected start)
  // Skip the NSO's multigrid when the projected start P d is provably within this
  // relative gap of the NSO optimum (its dynamics term r||f(Pd)||^2 is below nso_skip_gap
  // times its energy: no divergence-free z has a lower proximity term than P d). 0: never.
  // ADMM from rest with the scenes' r = 1e-5 (letter 64^2 x 40): gaps 3e-4..6e-4, skipping
  // made an iteration 3.5x cheaper (1.32 -> 0.375 s CPU) and 15 iterations reached E 720
  // instead of 740. On a fine level started from coarse forces the gaps are 0.01-0.6 (no skip).
  double nso_skip_gap = 0.01;
  // Penalty rule. 0 (default): continuation beta_k = admm_penalty * min(1, 0.05 * 1.3^k).
  // > 0: residual balancing (Boyd et al. 2011, Sec. 3.4.1) with this mu: beta starts at the
  // continuation's beta_0; after an iteration whose relative primal residual is mu times the
  // relative dual one beta grows by admm_balance_tau, in the reverse case it shrinks by it
  // (the scaled dual rescaled), clamped to [1e-3, 1e3] admm_penalty. beta is then state
  // (ControlState::admm_beta).
  double admm_balance_mu = 0;
  double admm_balance_tau = 2;
  // Over-relaxation (Boyd et al. 2011, Sec. 3.4.3): the NSO and the dual update see
  // alpha u + (1 - alpha) z_prev instead of the AO's u. 1 (default): plain ADMM.
  double admm_relaxation = 1.0;
  // Adaptive switch to the polish (0: off): after at least 3 outer iterations ADMM stops when
  // the best re-simulated objective fell by less than this fraction over the last iteration
  // (a function of the stored history, so a resumed run decides the same).
  double admm_switch_progress = 0;
  // L-BFGS iterations on E(f) after the ADMM loop, from its best forces (0 = none):
  // ADMM finds the transport path from rest (where plain L-BFGS stalls at once), the
  // polish makes the re-simulated keyframes exact up to what the discretisation allows.
  int polish_iterations = 0;
  // Polish iterations on each coarse level of the progressive preview (-1: polish_iterations),
  // so the fine level's polish can be longer than the coarse levels' (bench experiments).
  int coarse_polish_iterations = -1;
  // L-BFGS (baseline and polish) iterations per chunk: the quasi-Newton memory lives within
  // a chunk, the state is checkpointed after it and the next chunk starts a fresh memory
  // (LBFGS++ has no callback; exact resume repeats a killed chunk). Longer chunks converge
  // faster (see control_lbfgs.cpp); shorter ones lose less work to a kill.
  int lbfgs_chunk = 20;
  bool progressive_preview = true;     // write coarse-level previews first
  int coarse_iterations = -1;          // outer iterations per coarse level (-1: max_iterations)
  // ADMM: how many of the coarsest levels run ADMM (coarse_iterations each); the finer
  // coarse levels only polish (-1: every coarse level runs ADMM).
  int coarse_admm_levels = -1;
  std::string stage_label;             // progress stage suffix ("32x32" on coarse levels)
};

// Parses the scene's "control" section (kind "smoke"); keyframe targets come from
// engine/geom (masks, images, text, meshes). Throws InputError naming the field
// (frame past T, empty mask, unreadable image, ...).
ControlModel control_compile(const Scene& scene);

struct Trajectory {
  std::vector<std::vector<float>> density;  // T+1 frames, cells each
  FaceSeries velocity;                      // T+1 frames
};
// Plain forward simulation of the control model under forces f (T entries).
Trajectory control_forward(const ControlModel& m, const FaceSeries& f);
// E(f) and, when grad != nullptr, dE/df by the discrete adjoint of control_forward.
double control_objective(const ControlModel& m, const FaceSeries& f, FaceSeries* grad);

struct KeyframeMetrics {
  int frame = 0;
  double relative_l2 = 0;  // ||rho - rho*|| / ||rho*||
  double iou = 0;          // of rho and rho* thresholded at half of rho*'s max
};
struct ControlMetrics {
  double objective = 0, control_energy = 0, max_divergence = 0;
  std::vector<KeyframeMetrics> keyframes;
  double iou_min = 0;
};
// Re-simulates f with control_forward and measures it against the keyframes.
ControlMetrics control_evaluate(const ControlModel& m, const FaceSeries& f);

// The optimisation state: plain, copyable, checkpointed once per outer
// iteration so `pliant run --resume` continues a killed run.
struct ControlState {
  int iteration = 0;
  FaceSeries force;                  // current forces (T entries)
  FaceSeries velocity, split, dual;  // ADMM: AO velocities u, NSO velocities z, scaled dual
  std::vector<double> objective_history;
  std::vector<double> primal_residual_history, dual_residual_history;
  double wall_s = 0;
  // ADMM only: 0 = outer loop, 1 = L-BFGS polish (ControlModel::polish_iterations);
  // the NSO's Levenberg-Marquardt damping carried between outer iterations, so a
  // resumed run continues exactly where an uninterrupted one would be.
  int phase = 0;
  double nso_damping = 0;
  // Progressive preview: the coarse-to-fine level this state belongs to (0 = the scene's
  // grid, l = space coarsened l times), so a run killed during a coarse level resumes
  // there (control_coarse_to_fine.h).
  int level = 0;
  // L-BFGS (baseline or polish) stopped by its own rule (converged or stalled) before
  // its iteration cap: a run resumed from this state stops as the uninterrupted one did.
  bool lbfgs_stopped = false;
  // Best-so-far objective of this level, [seconds, E] at every evaluation that lowered it
  // (L-BFGS evaluations, ADMM outer iterations and the level's starting forces): seconds
  // on the solver clock (ControlCallbacks::clock) since the run started, coarse levels'
  // time included; the points themselves are this level's (a coarse level's E is on its
  // own grid). trace_s: solver-clock seconds spent up to this state (resume goes on there).
  std::vector<std::array<double, 2>> objective_trace;
  double trace_s = 0;
  // ADMM with residual balancing (ControlModel::admm_balance_mu > 0): the penalty the stored
  // scaled dual belongs to, for the next outer iteration (0: not set, the schedule's beta).
  double admm_beta = 0;
};
ControlState control_init(const ControlModel& m);  // zero forces, rest fluid
std::vector<uint8_t> control_state_serialize(const ControlState& s);
ControlState control_state_deserialize(const std::vector<uint8_t>& bytes);  // throws on bad data

// Called after every outer iteration with the state (to checkpoint and report);
// a coarse-level preview of the density (T+1 frames at reduced resolution, with
// its grid) may be passed during progressive preview.
struct ControlCallbacks {
  std::function<void(const ControlState&)> on_iteration;
  std::function<void(const GridDims&, const std::vector<std::vector<float>>&)> on_preview;
  // Seconds for ControlState::objective_trace (only differences are used); empty: the
  // steady clock (wall). The bench passes process CPU seconds.
  std::function<double()> clock;
};

// Both run until tolerance, max_iterations or cancellation (progress.check_cancelled()).
void control_solve_lbfgs(const ControlModel& m, ControlState& s, Progress& progress,
                         const ControlCallbacks& cb = {});
void control_solve_admm(const ControlModel& m, ControlState& s, Progress& progress,
                        const ControlCallbacks& cb = {});

// The job for smoke scenes with a "control" section (part A, control_job.cpp):
// solve, checkpoint per outer iteration (--resume continues), previews, then the
// re-simulated frames (density, velocity, force) and metrics.
bool scene_has_control(const Scene& scene);
nlohmann::json smoke_control_run_job(JobContext& ctx);
int smoke_control_job_frames(const Scene& scene);

}  // namespace pliant::smoke
