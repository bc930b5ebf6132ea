// Locomotion objectives (Pan & Manocha TOG 2018 section 6) as a residual vector
// r(theta) so that the objective is |r|^2 / 2 and Levenberg-Marquardt can use its
// Gauss-Newton structure. theta are the DMP parameters; r comes from a forward
// simulation of `frames` steps (shooting: physics holds exactly on every rollout, so
// the dissertation's physics-violation term is identically zero here).
// Terms, each scaled by sqrt(weight):
//   velocity   mean COM velocity over the horizon minus target (3)
//   position   final COM minus target (3)
//   heading    mean over frames of R a - d (body axis a, world direction d) (3)
//   jump       smooth max over frames of COM height gain minus target height (1)
//   distance   final COM displacement along a direction minus target distance (1)
//   shuffle    per frame, RMS tangential speed of nodes touching an obstacle (frames)
//   course     per frame, horizontal offset of the COM from the straight line
//              through the start COM along a direction, scaled by sqrt(dt / T) so
//              that its sum is the time average (frames); holds a walk's course
//              (heading alone lets the path veer)
//   upright    per frame, R a - y for a body axis a that points up at rest, scaled
//              by sqrt(weight / frames): the mean squared tilt over the horizon (3
//              frames); heading holds one axis only, so a swimmer could roll about it
//   keyframes  surface vertices minus (rest position + offset) at chosen frames
//   turn       mean yaw rate of a body axis about +y minus target (rad/s), and COM
//              progress along the initial heading per second minus target speed
//              (the gaits of navigation.h)
//   steady     over the last `periods` controller periods of the horizon: yaw rate
//              of a body axis (rad/s) and COM velocity normal to a ground direction
//              (m/s) (2); with a periodicity weight also the change of the horizontal
//              COM displacement (2) and of the yaw (1) from the period before, per
//              second (3). turn at rate 0 holds only the horizon's NET yaw, so a gait
//              may turn out and back or still be turning at its end; an open-loop
//              replay repeats the last period, so that is the one to hold straight
//   effort     theta itself (keeps the problem well posed)
#pragma once
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "pliant/soft/dmp.h"
#include "pliant/soft/optimizer.h"
#include "pliant/soft/simulator.h"

namespace pliant::soft {

struct Keyframe {
  int frame = 0;
  std::vector<int> vertices;  // surface vertex ids
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
};

struct Objectives {
  double w_velocity = 0;
  Eigen::Vector3d velocity_m_per_s = Eigen::Vector3d::Zero();
  double w_position = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double w_heading = 0;
  Eigen::Vector3d heading_axis = Eigen::Vector3d::UnitX(), heading_direction = Eigen::Vector3d::UnitX();
  double w_jump = 0;
  double jump_height_m = 0;
  double w_distance = 0;
  double distance_m = 0;
  Eigen::Vector3d distance_direction = Eigen::Vector3d::UnitX();
  double w_shuffle = 0;
  double w_course = 0;
  Eigen::Vector3d course_direction = Eigen::Vector3d::UnitX();  // its horizontal part is used
  double w_upright = 0;
  Eigen::Vector3d upright_axis = Eigen::Vector3d::UnitY();
  double w_keyframes = 0;
  std::vector<Keyframe> keyframes;
  double w_turn = 0;
  Eigen::Vector3d turn_axis = Eigen::Vector3d::UnitX();
  double turn_rate_rad_per_s = 0, turn_speed_m_per_s = 0;
  double w_steady = 0, w_steady_periodic = 0;
  Eigen::Vector3d steady_axis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d steady_direction = Eigen::Vector3d::UnitX();  // its horizontal part is used
  int steady_periods = 1;
  double w_effort = 1e-4;
};

// Frames in one steady window: periods x the controller period, rounded, >= 1.
int steady_window_frames(const Objectives& o, double period_s, double dt_s);

// Yaw of the body axis a in the ground plane: atan2((R a)_z, (R a)_x), radians.
double heading_yaw(const SoftState& s, const Eigen::Vector3d& axis);
// Angle between the body axis a turned by the state's frame (R a) and +y, degrees
// (the job's tilt metrics, with the upright term's axis).
double tilt_from_up_deg(const SoftState& s, const Eigen::Vector3d& axis);

struct Problem {
  const Character* character = nullptr;
  Environment env;
  SimParams sim;
  DmpSpec dmp;
  Objectives obj;
  int frames = 30;  // rollout horizon of the optimization
  Eigen::Vector3d start_offset_m = Eigen::Vector3d::Zero();
};

// Modal control force for DMP activations y (controlled modes; others zero):
// u_k = omega_k^2 a tanh(y_k / a) / s_k with a = a_max.
Eigen::VectorXd control_force(const Character& ch, const Eigen::VectorXd& y, double a_max);
// The same into u (resized to r; no allocation once it has that size).
void control_force(const Character& ch, const Eigen::VectorXd& y, double a_max, Eigen::VectorXd& u);

// Forward simulation of n frames under theta; calls on_frame(state) after every
// step (frame 1..n) when given. Returns the final state.
// Counts steps whose Newton solve did not converge in *unconverged when given.
SoftState simulate(const Problem& p, const Eigen::VectorXd& theta, int n,
                   const std::function<void(const SoftState&)>& on_frame = {}, int* unconverged = nullptr);

// Activations saturate at +-a_max = max_activation_rel x the body's radius (tanh).
double max_activation_m(const Character& ch, const DmpSpec& spec);

// Residual vector (fixed size for a given problem).
Eigen::VectorXd residuals(const Problem& p, const Eigen::VectorXd& theta);
// Objective residuals of a given trajectory: frames[f] is the state after step f+1
// (f = 0..p.frames-1); residuals(p, theta) equals this on the simulated frames
// (residuals() alone turns an unconverged rollout into NaN). Throws
// std::invalid_argument when frames.size() != p.frames.
Eigen::VectorXd trajectory_residuals(const Problem& p, const std::vector<SoftState>& frames,
                                     const Eigen::VectorXd& theta);
// Starting point of the optimizers: small deterministic weights (2% of the
// activation bound) next to the symmetric rest state.
Eigen::VectorXd initial_theta(const Problem& p);

// Exact Jacobian dr/dtheta of residuals(p, theta) by forward sensitivities
// (sensitivity.cpp: implicit function theorem on every converged step, all columns
// from one rollout and one LDLT per step). Linear, POD and rotation-strain bases
// (the map's Jacobian and curvature in the step's Hessian). Buffers are per thread
// and reused (no allocation per step once sized); Eigen's own threading is off inside.
// r_out (optional): the rollout's residuals (NaN when a step did not converge).
Eigen::MatrixXd sensitivity_jacobian(const Problem& p, const Eigen::VectorXd& theta, Eigen::VectorXd* r_out = nullptr);

// Derivatives of one converged reduced_step from `start` (its q, R, c: z_{f-1}; its
// *_prev: z_{f-2}) to `end` (sensitivity.cpp, implicit function theorem): X1, X2
// (3N x k) are the derivatives of the start's and previous node positions, Q1 (r x k)
// of the start's q and dU (r x k) of the control force with respect to k parameters.
// Returns dz_f/d(parameters) ((r + 6) x k) in reduced_step's tangent (dq, dc, dw),
// R = exp([dw]) R_f; dx_dz (optional): dx_f/dz_f (3N x (r + 6)). Used by
// sensitivity_jacobian and spacetime_jacobian (linear and POD bases only there).
Eigen::MatrixXd step_sensitivity(const Character& ch, const Environment& env, const SimParams& sim,
                                 const SoftState& start, const SoftState& end, const Eigen::MatrixXd& X1,
                                 const Eigen::MatrixXd& X2, const Eigen::MatrixXd& Q1, const Eigen::MatrixXd& dU,
                                 Eigen::MatrixXd* dx_dz = nullptr);

// The optimizer's Jacobian for s.jacobian: sensitivity_jacobian where it applies
// (falls back to finite differences otherwise), empty (= finite differences) for FD.
JacobianFn problem_jacobian(const Problem& p, const OptimizerSettings& s);
// r and J from one sensitivity pass (s.fused_trials with the sensitivity Jacobian),
// empty otherwise; r is residuals(p, theta) to the last bit.
ResidualJacobianFn problem_residual_jacobian(const Problem& p, const OptimizerSettings& s);

// Largest COM height gain over a rollout of n frames (for checks and metrics).
double max_height_gain(const Problem& p, const Eigen::VectorXd& theta, int n);

}  // namespace pliant::soft
