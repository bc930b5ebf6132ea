// Optimizers for min |r(theta)|^2 / 2 (Pan & Manocha TOG 2018, Algorithm 6 in spirit):
//   LM      Levenberg-Marquardt on the Gauss-Newton structure of r, damping
//           lambda diag(J^T J) + lambda I, lambda / 3 on success, x 4 on failure;
//   LBFGS   limited-memory BFGS (memory 8) with an Armijo backtracking line search
//           (halving, c1 = 1e-4, first step of unit length: LBFGS++'s defaults; the
//           gradient J^T r only at accepted points);
//   Hybrid  LM while it makes progress; when LM stalls (twice in a row a step that
//           needed a larger lambda and gained less than `stall`, or a wholly rejected
//           step) it switches to L-BFGS steps from the same gradient until those
//           stall, then back to LM.
// LM starts with lambda = 1e-3 and, after an accepted step, Broyden-updates its
// Jacobian and first tries one step on that (one rollout, not n + 1); the finite-
// difference Jacobian is recomputed when that step fails its gain-ratio test.
// The Jacobian is by forward finite differences of whole rollouts (one column per
// parameter, columns in parallel with OpenMP), or, with settings.jacobian =
// Sensitivity, from the caller's JacobianFn (exact forward sensitivities of the
// rollout, objective.h). Every accepted step lowers the objective
// (steps that do not are rejected), so the history is monotone.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace pliant::soft {

// Spacetime is spacetime.h's method (states, controls and theta as unknowns); it
// needs the Problem, so optimize() given only r(theta) runs the hybrid for it.
enum class OptimizerKind { Hybrid, LM, LBFGS, Spacetime };
// How LM / L-BFGS / the hybrid get J = dr/dtheta: forward differences of whole
// rollouts (n + 1 rollouts), or exact forward sensitivities (objective.h:
// sensitivity_jacobian; one rollout plus one small solve per step).
enum class JacobianKind { FiniteDifference, Sensitivity };

struct OptimizerSettings {
  OptimizerKind kind = OptimizerKind::Hybrid;
  int max_iterations = 30;
  double fd_step = 1e-3;     // relative to max(1, |theta_i|); above the friction smoothing scale
  double tolerance = 1e-6;   // stop when the objective falls below tolerance * initial
  double stall = 0.05;       // hybrid: see the header comment
  double target = -1;        // stop when the objective <= target (if >= 0)
  // LM steps (LM and the hybrid's LM phase): after an accepted step the Jacobian is
  // Broyden-updated and the next iteration first tries one step on it (one rollout
  // instead of n + 1); at most this many such iterations in a row, 0 = always fresh.
  int broyden_reuse = 4;
  // LM damping at the start (and when the hybrid returns to LM), times diag(J^T J):
  // small, as in Madsen, Nielsen, Tingleff (2004) (tau = 1e-3); a rejected trial costs
  // one rollout, an over-damped accepted step a whole Jacobian.
  double lambda_initial = 1e-3;
  // L-BFGS: the first step (no curvature pairs yet) is -g / |g| x this length, as
  // LBFGS++ does (1 / |g|). Until the fifth session it was 0.01 max(1, |theta|),
  // which slowed pure L-BFGS down 2-5x (T-shape jump: 9 iterations to 1% instead of
  // 2). The hybrid's first L-BFGS step instead has its last LM step's length.
  double lbfgs_initial_step = 1.0;
  JacobianKind jacobian = JacobianKind::Sensitivity;
  // Fused trials (tenth session): every trial point (LM trial, L-BFGS line-search
  // point) is evaluated together with its exact Jacobian (the caller's
  // ResidualJacobianFn: the forward-sensitivity pass is itself a rollout), so an
  // accepted trial hands the next iteration its Jacobian without a second rollout of
  // the same point. A trial then costs ~1.2-1.6 rollouts instead of 1 but an accepted
  // one saves a whole Jacobian pass; L-BFGS gets the same (LBFGS++ evaluates f and
  // the gradient together at every line-search point). Broyden reuse is off then
  // (its only purpose is saving a Jacobian). Needs the sensitivity Jacobian.
  bool fused_trials = false;
  // LM damping schedule: Marquardt's (lambda / 3 after an accepted step, x 4 after a
  // rejected one), or a trust region in Marquardt's scaling (Moré 1978): lambda is
  // chosen so the step's scaled length meets the radius, which is halved after a
  // rejected trial or a gain ratio < 1/4 and at least doubled above 3/4.
  enum class Damping { Marquardt, TrustRegion };
  Damping lm_damping = Damping::Marquardt;
  // L-BFGS variants (eleventh session, for a strong baseline; defaults = the behaviour
  // before). Memory: curvature pairs kept. lbfgs_initial_step <= 0: the first step is
  // -g itself (alpha 1 on the raw gradient) instead of a step of that length.
  int lbfgs_memory = 8;
  // Restarts (pure L-BFGS only; the hybrid returns to LM instead): when the line search
  // fails, the curvature pairs are dropped and the iteration retries from the current
  // point (the best so far: steps are monotone) along -g, with the last accepted
  // step's length; at most this many in a run, and a restart whose own line search
  // fails ends the run (it no longer gains).
  int lbfgs_restarts = 0;
  // Line search: the own Armijo backtracking (halving, c1 = 1e-4, no gradient at
  // trials), or LBFGS++'s (liblbfgspp 0.1.0, LBFGSpp/LineSearch*.h; c1 = 1e-4,
  // c2 = 0.9, 20 trials), which need the gradient at every trial point (the fused
  // residual + Jacobian evaluation when given, else a rollout plus a Jacobian):
  // Wolfe / StrongWolfe = LineSearchBacktracking (x 0.5 / x 2.1), Bracketing =
  // LineSearchBracketing (bisection, strong Wolfe), NocedalWright =
  // LineSearchNocedalWright (strong Wolfe, zoom with cubic interpolation; Nocedal &
  // Wright 2006, Alg. 3.5-3.6). LBFGS++ 0.1.0's Moré-Thuente search is written for
  // L-BFGS-B only (its signature takes LBFGSBParam and a step bound).
  enum class LineSearch { Armijo, Wolfe, StrongWolfe, Bracketing, NocedalWright };
  LineSearch lbfgs_line_search = LineSearch::Armijo;
  // The hybrid's L-BFGS phase uses this one instead (lbfgs_line_search is the pure
  // L-BFGS's); scene key optimizer.hybrid_lbfgs_line_search (eleventh session).
  // Armijo = the behaviour before.
  LineSearch hybrid_lbfgs_line_search = LineSearch::Armijo;
};

// "armijo", "wolfe", "strong_wolfe", "bracketing", "nocedal_wright"; parse throws
// std::invalid_argument on another name.
const char* line_search_name(OptimizerSettings::LineSearch l);
OptimizerSettings::LineSearch parse_line_search(const std::string& name);

// What optimize() carries from one iteration to the next besides OptimizerState's
// own fields, so that a state checkpointed after an iteration and restored
// (optimizer_state_serialize / _deserialize) continues bit for bit. Kept in the state
// rather than in optimize()'s locals (the same allocations, plus one m x n copy per
// iteration with fused trials, whose dead J is dropped at the iteration's end).
// Sizes: m residuals, n parameters; J and J_at are m x n, usually only one of them kept
// between iterations (J without fused trials, J_at with them). spider_walk.json:
// m = 30, n = 20, J_at 4.8 kB, the whole serialized state 5.9 kB per checkpoint.
struct OptimizerMemory {
  Eigen::VectorXd theta;  // the point r belongs to; empty: optimize() starts afresh
  Eigen::VectorXd r;      // residuals at theta (m)
  Eigen::MatrixXd J;      // LM's Jacobian for the next iteration (Broyden-updated), m x n or empty
  int reused = 0;         // iterations in a row that used a Broyden-updated J
  Eigen::MatrixXd J_at;   // exact Jacobian at theta from the evaluation that gave r (fused trials,
                          // LBFGS++ line searches), m x n or empty
  int lm_stalls = 0;      // hybrid: stalled LM steps in a row
  double last_lm_step = 0;     // length of the last accepted LM step
  double last_lbfgs_step = 0;  // length of the last accepted L-BFGS step
  double radius = -1;          // trust region radius in Marquardt's scaling (< 0: unset)
  std::deque<Eigen::VectorXd> S, Y;  // L-BFGS curvature pairs (n each)
  Eigen::VectorXd g_prev, theta_prev;  // L-BFGS: gradient and point of the last L-BFGS iteration
};

struct OptimizerState {
  Eigen::VectorXd theta;
  double objective = 0;
  double lambda = 1.0;
  int iteration = 0;
  int evaluations = 0;      // rollouts, Jacobian columns included
  bool in_lbfgs = false;
  int lbfgs_restarts_used = 0;  // L-BFGS restarts after failed line searches
  std::vector<double> history;  // objective after each accepted iteration (first: initial)
  std::vector<std::string> step_kinds;  // "lm" or "lbfgs" per iteration
  // Continued by optimize() when memory.theta == theta (a state it left, or one
  // restored from a checkpoint); otherwise optimize() evaluates r(theta) and starts
  // with empty memory (a new run, or a resume from a theta-only checkpoint).
  OptimizerMemory memory;
};

// Versioned little-endian binary form of a state, all doubles (optimizer_state.cpp):
// what a checkpoint needs to continue exactly. `tag` is the caller's (e.g. a hash of
// the scene the run belongs to), returned by deserialize. deserialize throws
// std::runtime_error naming the problem (bad magic, version, CRC, a size that does
// not fit, truncation, trailing bytes); zero bytes after the end (padding) are allowed.
std::vector<uint8_t> optimizer_state_serialize(const OptimizerState& s, uint32_t tag = 0);
OptimizerState optimizer_state_deserialize(const std::vector<uint8_t>& bytes, uint32_t* tag = nullptr);

using ResidualFn = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;
// Called after every iteration; return false to stop (cancellation, checkpoints).
using IterationFn = std::function<bool(const OptimizerState&)>;
// J(theta) given r0 = r(theta); an empty result means "use finite differences".
using JacobianFn = std::function<Eigen::MatrixXd(const Eigen::VectorXd& theta, const Eigen::VectorXd& r0)>;
// J at the point of an evaluation already made, computed when called (deferred).
using DeferredJacobian = std::function<Eigen::MatrixXd()>;
// r(theta) and J(theta) from one pass (settings.fused_trials): writes r, returns J.
// Optionally `deferred`: the same pass in two halves, r now (writes r) and J from the
// returned function (empty J: none), with the same bits as the one-pass J; optimize()
// then pays for J only at accepted points (an LM trial that lowers the objective, a
// line-search point that meets Armijo's condition).
struct ResidualJacobianFn {
  using Fused = std::function<Eigen::MatrixXd(const Eigen::VectorXd& theta, Eigen::VectorXd& r)>;
  Fused fused;
  std::function<DeferredJacobian(const Eigen::VectorXd& theta, Eigen::VectorXd& r)> deferred;
  ResidualJacobianFn() = default;
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, ResidualJacobianFn> &&
                                              std::is_constructible_v<Fused, F>>>
  ResidualJacobianFn(F f) : fused(std::move(f)) {}  // NOLINT: a lambda converts, as before
  Eigen::MatrixXd operator()(const Eigen::VectorXd& theta, Eigen::VectorXd& r) const { return fused(theta, r); }
  explicit operator bool() const { return static_cast<bool>(fused); }
};

// Continues from `state` (theta set; history may hold a resumed run). jacobian
// (optional) replaces the finite-difference Jacobian; it counts as one rollout.
// fused (optional) is used when s.fused_trials is set; a fused evaluation counts as
// one rollout. Stops at s.max_iterations, at s.tolerance x the initial objective or
// s.target, after a wholly rejected iteration (LM, L-BFGS) or three in a row (hybrid:
// from there it would only repeat itself).
void optimize(const ResidualFn& r, const OptimizerSettings& s, OptimizerState& state,
              const IterationFn& on_iteration = {}, const JacobianFn& jacobian = {},
              const ResidualJacobianFn& fused = {});

// Broyden's rank-1 secant update: J += (dr - J d) d^T / |d|^2, so J d = dr after it
// and J is unchanged on vectors orthogonal to d.
void broyden_update(Eigen::MatrixXd& J, const Eigen::VectorXd& d, const Eigen::VectorXd& dr);

// Forward-difference Jacobian (columns in parallel).
Eigen::MatrixXd fd_jacobian(const ResidualFn& r, const Eigen::VectorXd& theta, const Eigen::VectorXd& r0,
                            double step);

const char* optimizer_name(OptimizerKind k);

}  // namespace pliant::soft
