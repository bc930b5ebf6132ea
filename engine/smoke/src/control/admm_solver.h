// The ADMM outer loop of control_solve_admm (Pan & Manocha 2017; ALGORITHMS.md 2).
// Variables (frames 1..T): AO velocities u, NSO velocities z, scaled dual lambda.
//   AO:   u <- argmin keyframe error(rho(u)) + beta/2 ||u - (z - lambda)||^2   (ao_solver.h)
//   NSO:  z <- argmin r ||f(z)||^2 + beta/2 ||z - (u + lambda)||^2, div z = 0  (nso_solver.h)
//   dual: lambda += u - z
// Residuals (relative): primal ||u - z|| / max(||u||, ||z||), dual ||z - z_prev|| / ||lambda||
// (Boyd et al. 2011, Sec. 3.3); stop when both stored residuals are below tolerance, or
// when the re-simulated objective has stalled (admm_stalled).
// The state's forces are those of the best re-simulated objective so far (ADMM is not
// monotone in E). control_solve_admm then runs ControlModel::polish_iterations of the
// L-BFGS baseline from those forces (ControlState::phase 1).
// Progressive preview (control_coarse_to_fine.h): ADMM + polish at 1/4 and 1/2 resolution
// first; the fine ADMM starts from the trajectory of the prolonged forces.
// Exact resume: everything carried between outer iterations is in ControlState (u, z,
// lambda as float and the loop continues from those floats; the NSO damping); the AO's
// quasi-Newton memory and the NSO multipliers restart at every solve.
// Forces: a forward sweep re-simulates the plain model, f_i = P(z_{i+1} - A(z'_i))/dt with
// z' the re-simulated velocity, so P(A z'_i + dt f_i) = P z_{i+1}: control_forward
// reproduces the projected NSO velocities, and f is divergence-free (least norm).
// ControlState: velocity = u, split = z, dual = lambda, each T entries (frames 1..T).
#pragma once
#include <vector>

#include "pliant/smoke/control.h"

namespace pliant::smoke {

struct AdmmIterationStats {
  double objective = 0, primal = 0, dual = 0, ao_s = 0, nso_s = 0, forces_s = 0;
  double ao_keyframe_error = 0;  // keyframe term of the AO density (advected by u)
  int ao_steps = 0;
  int nso_lm_steps = 0, nso_rejected = 0;  // Levenberg-Marquardt steps accepted / rejected
  double beta = 0;  // penalty used in this iteration
  std::vector<double> vcycle_factors;
  double nso_start_gap = -1;  // NsoStats::start_gap
  bool nso_skipped = false;   // NsoStats::skipped (ControlModel::nso_skip_gap)
};

// Runs ADMM outer iterations on s until tolerance / max_iterations / cancellation.
// `stats` (optional) receives one entry per iteration.
void admm_run(const ControlModel& m, ControlState& s, Progress& progress, const ControlCallbacks& cb,
              std::vector<AdmmIterationStats>* stats);

// True when the objective history shows no progress over its last 3 iterations (0.1%):
// admm_run then stops (a function of the stored history, so resume decides the same).
bool admm_stalled(const std::vector<double>& objective_history);

// The adaptive switch to the polish (ControlModel::admm_switch_progress): true when, after
// at least 3 iterations, the last one lowered the best objective by less than `fraction`.
bool admm_progress_below(const std::vector<double>& objective_history, double fraction);

// Penalty continuation: beta_k = admm_penalty * min(1, 0.05 * 1.3^k) (deterministic in
// k, so a resumed run knows which beta its stored scaled dual belongs to).
double admm_penalty_at(const ControlModel& m, int iteration);

// The model at half resolution (keyframes and initial density restricted), for the
// progressive preview; false when the grid cannot be halved.
bool admm_coarsen_model(const ControlModel& m, ControlModel& coarse);

}  // namespace pliant::smoke
