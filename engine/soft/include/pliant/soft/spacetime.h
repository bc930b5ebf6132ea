// Spacetime optimization of a DMP controller (Pan & Manocha TOG 2018, section 6 and
// Algorithm 6; dissertation chapter 4): the unknowns are every frame's reduced state
// z_f = (q_f, R_f, c_f), every frame's activations a_f (metres, the controlled modes'
// saturated DMP output) and the DMP parameters theta. The merit is |r|^2 / 2 with
//   physics  sqrt(w_phys) (z_f - step(z_{f-1}, z_{f-2}, a_f))   per frame (direct
//            multiple shooting with one-frame intervals; `reduced_step` is the step,
//            differences in metres: q scaled by mode_scale, rotation log by the body
//            radius, translation as is)
//   DMP      sqrt(w_dmp) (a_f - a_max tanh(y_f(theta) / a_max))  per frame
//   task     trajectory_residuals(p, frames, theta) (objective.h)
// The activation a drives the step through the modal force omega^2 a / s (the same
// force control_force gives when the DMP's activation saturates to a).
// Levenberg-Marquardt on the block-banded Jacobian: physics blocks from the exact
// derivatives of each converged step (implicit function theorem, sensitivity.cpp
// step_sensitivity; one step + one solve per frame, frames in parallel) or, with
// jacobian = FiniteDifference, by forward differences of single steps; DMP blocks
// analytic in a and by differences of DMP rollouts in theta; task blocks by differences of
// trajectory_residuals; normal equations J^T J + lambda (diag + eps) solved by
// Eigen's SimplicialLDLT. Accepted steps lower the merit at fixed weights (monotone).
// Feasibility projection (`project`, default on): each trial point's states are
// re-simulated under its activations before the merit is evaluated, so the physics
// rows shape the step (how states follow controls, frame by frame) and every
// accepted point is a rollout. Without it the penalty form barely moves: on the
// T-shape jump the undamped GN step's one-step linearization of contact is so poor
// that trials violate physics by 1e5x the merit, LM damps to |dz| ~ 0.03 and gains
// < 1% per iteration (0.609 -> 0.607 in 3 iterations at w_phys 1e6; 1e8 the same).
// Adaptive DMP penalty: w_dmp starts small (the controls may leave the DMP's span
// to reach the task) and is raised x10 whenever LM stalls, until the DMP alone
// reproduces the activations (RMS below dmp_tolerance of a_max).
// The controller reported is theta; its objective is always that of the DMP
// open-loop re-simulation (shooting, residuals()), so the take is physical.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pliant/soft/objective.h"
#include "pliant/soft/optimizer.h"

namespace pliant::soft {

struct SpacetimeSettings {
  int max_iterations = 30;       // LM iterations over all penalty weights (st.iteration counts)
  double w_physics = 1e8;        // per metre^2 of physics violation
  double w_dmp_initial = 1;      // per metre^2 of activation mismatch
  double w_dmp_factor = 10;
  double w_dmp_max = 1e8;
  double lambda_initial = 1e-8;  // LM damping (x diag(J^T J)); physics rows dominate the
                                 // diagonal, so moves along the physical manifold need it small
  // Feasibility projection: after each LM step the states are re-simulated under the
  // stepped activations (the step's state part only shapes the direction), so every
  // accepted point is physical; off, the states move freely under the penalty.
  bool project = true;
  double stall = 0.005;          // relative merit decrease that counts as stalled
  double fd_step_m = 1e-6;       // finite-difference step, metres (or metre-equivalents)
  // Physics blocks: exact step derivatives (step_sensitivity, one step + one solve per
  // frame) or forward differences (one step per column). Set from optimizer.jacobian.
  JacobianKind jacobian = JacobianKind::Sensitivity;
  double dmp_tolerance = 1e-3;   // DMP RMS mismatch, fraction of a_max, to stop raising w_dmp
  double tolerance = 1e-6;       // stop when the re-simulated objective <= tolerance x initial
};

// The unknowns. frames[f] is the state after step f + 1 (its *_prev fields are kept
// equal to frame f's values); act is (controlled modes) x frames.
struct SpacetimeVars {
  std::vector<SoftState> frames;
  Eigen::MatrixXd act;
  Eigen::VectorXd theta;
};

struct SpacetimeReport {
  std::vector<double> merit;              // after each iteration (first: initial)
  std::vector<double> physics_violation;  // RMS over frames, metres
  std::vector<double> dmp_mismatch;       // RMS over frames, metres
  std::vector<double> w_dmp;
  std::vector<double> resimulated;        // residuals(p, theta) objective per iteration
  int steps = 0;                          // reduced_step calls
};

// What spacetime_optimize carries from one iteration to the next besides
// OptimizerState (whose theta is the best re-simulated one, not the trajectory's) and
// the report: with both restored (spacetime_state.h) a run continues bit for bit.
struct SpacetimeCarry {
  SpacetimeVars vars;      // the current point; no frames: start from st.theta's rollout
  Eigen::VectorXd res;     // spacetime_residuals at vars and the weights below
  double merit = 0;        // |res|^2 / 2
  double w_dmp = 0;        // the adaptive DMP weight
  double lambda = 0;       // LM damping
  bool stopped = false;    // the last iteration ended the run (rejected at w_dmp_max)
};

// Trajectory and activations of the open-loop rollout of theta (zero violation, zero
// DMP mismatch).
SpacetimeVars spacetime_from_rollout(const Problem& p, const Eigen::VectorXd& theta);

// Block sizes: per frame state (r + 6), activations per frame (controlled modes).
int spacetime_state_size(const Problem& p);
int spacetime_unknowns(const Problem& p);

// New unknowns from a step dz (metre-equivalent units, layout: frame states,
// activations frame by frame, theta); rotations by R <- exp([dw / L]) R.
SpacetimeVars spacetime_apply(const Problem& p, const SpacetimeVars& v, const Eigen::VectorXd& dz);

// Physics violation of frame f (r + 6 values, metres, unweighted).
Eigen::VectorXd physics_violation(const Problem& p, const SpacetimeVars& v, int f);

// Whole residual [physics (frames x (r+6)), DMP (frames x modes), task] at weights.
Eigen::VectorXd spacetime_residuals(const Problem& p, const SpacetimeVars& v, double w_physics, double w_dmp);

// Jacobian of spacetime_residuals with respect to spacetime_apply's dz (dense; the
// physics and DMP blocks are banded).
// kind: physics blocks from the exact step derivatives (Sensitivity; finite
// differences where a step has none, e.g. rotation-strain coordinates) or by forward
// differences of single steps.
Eigen::MatrixXd spacetime_jacobian(const Problem& p, const SpacetimeVars& v, double w_physics, double w_dmp,
                                   double fd_step_m, JacobianKind kind = JacobianKind::Sensitivity);

// Continues from st.theta (empty: initial_theta) until st.iteration reaches
// s.max_iterations; st.history holds the best
// re-simulated objective so far (first: the initial theta's), st.theta the theta that
// reached it, st.evaluations counts rollout equivalents (steps / frames).
// carry (optional) is the state between iterations, kept current before every
// on_iteration call (a checkpoint's): given with frames (a restored checkpoint, with
// its report in *report and its OptimizerState in st) the run continues from it
// exactly; without frames it starts from the rollout of st.theta at w_dmp_initial.
void spacetime_optimize(const Problem& p, const SpacetimeSettings& s, OptimizerState& st,
                        const IterationFn& on_iteration = {}, SpacetimeReport* report = nullptr,
                        SpacetimeCarry* carry = nullptr);

}  // namespace pliant::soft
