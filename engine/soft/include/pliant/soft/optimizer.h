// Optimizers for min |r(theta)|^2 / 2 (Pan & Manocha TOG 2018, Algorithm 6 in spirit):
//   LM      Levenberg-Marquardt on the Gauss-Newton structure of r, damping
//           lambda diag(J^T J) + lambda I, lambda / 3 on success, x 4 on failure;
//   LBFGS   limited-memory BFGS (memory 8) with an Armijo backtracking line search;
//   Hybrid  LM while it makes progress; when LM stalls (twice in a row a step that
//           needed a larger lambda and gained less than `stall`, or a wholly rejected
//           step) it switches to L-BFGS steps from the same gradient until those
//           stall, then back to LM.
// The Jacobian is by forward finite differences of whole rollouts (one column per
// parameter, columns in parallel with OpenMP): theta has tens of entries and every
// rollout is cheap in the reduced space. Every accepted step lowers the objective
// (steps that do not are rejected), so the history is monotone.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace pliant::soft {

// Spacetime is spacetime.h's method (states, controls and theta as unknowns); it
// needs the Problem, so optimize() given only r(theta) runs the hybrid for it.
enum class OptimizerKind { Hybrid, LM, LBFGS, Spacetime };

struct OptimizerSettings {
  OptimizerKind kind = OptimizerKind::Hybrid;
  int max_iterations = 30;
  double fd_step = 1e-3;     // relative to max(1, |theta_i|); above the friction smoothing scale
  double tolerance = 1e-6;   // stop when the objective falls below tolerance * initial
  double stall = 0.05;       // hybrid: see the header comment
  double target = -1;        // stop when the objective <= target (if >= 0)
};

struct OptimizerState {
  Eigen::VectorXd theta;
  double objective = 0;
  double lambda = 1.0;
  int iteration = 0;
  int evaluations = 0;      // rollouts, Jacobian columns included
  bool in_lbfgs = false;
  std::vector<double> history;  // objective after each accepted iteration (first: initial)
  std::vector<std::string> step_kinds;  // "lm" or "lbfgs" per iteration
};

using ResidualFn = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;
// Called after every iteration; return false to stop (cancellation, checkpoints).
using IterationFn = std::function<bool(const OptimizerState&)>;

// Continues from `state` (theta set; history may hold a resumed run).
void optimize(const ResidualFn& r, const OptimizerSettings& s, OptimizerState& state,
              const IterationFn& on_iteration = {});

// Forward-difference Jacobian (columns in parallel).
Eigen::MatrixXd fd_jacobian(const ResidualFn& r, const Eigen::VectorXd& theta, const Eigen::VectorXd& r0,
                            double step);

const char* optimizer_name(OptimizerKind k);

}  // namespace pliant::soft
