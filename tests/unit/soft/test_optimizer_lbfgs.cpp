// L-BFGS variants for a strong baseline (eleventh session): restarts after a failed
// line search, LBFGS++'s Wolfe line searches, the memory and the raw first step.
// Also the hybrid's L-BFGS phase with a Wolfe search (hybrid_lbfgs_line_search).
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "pliant/soft/optimizer.h"
#include "optimizer_test_problems.h"

using namespace pliant::soft;

namespace {

// Extended Rosenbrock with the exact Jacobian, except that the Jacobian of the
// `bad_call`-th call (1-based) is corrupted so its gradient is the previous call's
// plus 1e-6 x the step between them: the curvature pair (s, y = 1e-6 s) that L-BFGS
// stores then claims a curvature of 1e-6, its next direction is ~1e6 times too long
// and 20 halvings of the Armijo search cannot shorten it enough. A stale-memory
// failure such as a kink in a rollout (contact) produces; the gradient itself is
// still a descent direction.
struct LbfgsStaleMemoryProblem {
  int bad_call = 5;
  int calls = 0;
  Eigen::VectorXd x_prev, g_prev;
  Eigen::MatrixXd operator()(const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
    ++calls;
    Eigen::MatrixXd J = test::rosenbrock_jacobian(x);
    if (calls == bad_call && x_prev.size()) {
      const Eigen::VectorXd target = g_prev + 1e-6 * (x - x_prev);
      J += r * ((target - J.transpose() * r) / r.squaredNorm()).transpose();
    }
    x_prev = x, g_prev = J.transpose() * r;
    return J;
  }
};

OptimizerState lbfgs_run_stale(int restarts) {
  OptimizerSettings s;
  s.kind = OptimizerKind::LBFGS;
  s.max_iterations = 300;
  s.tolerance = 1e-12;
  s.lbfgs_restarts = restarts;
  OptimizerState st;
  st.theta = Eigen::VectorXd::Constant(6, -1.2);
  LbfgsStaleMemoryProblem prob;
  const JacobianFn jf = [&prob](const Eigen::VectorXd& x, const Eigen::VectorXd& r) { return prob(x, r); };
  optimize(test::rosenbrock_residuals, s, st, {}, jf);
  return st;
}

}  // namespace

TEST(OptimizerLbfgs, RestartAfterAFailedLineSearchContinuesAndLowersTheObjective) {
  const OptimizerState plain = lbfgs_run_stale(0), restarted = lbfgs_run_stale(3);
  // Without restarts the corrupted memory ends the run at its failed line search.
  ASSERT_FALSE(plain.step_kinds.empty());
  EXPECT_EQ(plain.step_kinds.back(), "lbfgs-rejected");
  EXPECT_EQ(plain.lbfgs_restarts_used, 0);
  // The same path up to the failure, then a restart from the same (best) point.
  EXPECT_GE(restarted.lbfgs_restarts_used, 1);
  ASSERT_GT(restarted.history.size(), plain.history.size());
  const size_t k = plain.history.size() - 1;  // the rejected iteration's entry
  for (size_t i = 0; i < k; ++i) EXPECT_EQ(plain.history[i], restarted.history[i]) << i;
  EXPECT_EQ(restarted.step_kinds[k - 1], "lbfgs-restart");
  // Monotone, and on to the minimum (gradient J^T r ~ 0), which the plain run is far from.
  for (size_t i = 1; i < restarted.history.size(); ++i) EXPECT_LE(restarted.history[i], restarted.history[i - 1]);
  auto grad_norm = [](const Eigen::VectorXd& x) {
    return (test::rosenbrock_jacobian(x).transpose() * test::rosenbrock_residuals(x)).norm();
  };
  EXPECT_LT(grad_norm(restarted.theta), 1e-5);
  EXPECT_GT(grad_norm(plain.theta), 1e-2);
  EXPECT_LT(restarted.history.back(), plain.history.back() - 1e-3);
}

TEST(OptimizerLbfgs, WolfeLineSearchesConvergeAndReuseTheAcceptedPointsJacobian) {
  using L = OptimizerSettings::LineSearch;
  for (L ls : {L::Wolfe, L::StrongWolfe, L::Bracketing, L::NocedalWright}) {
    SCOPED_TRACE(line_search_name(ls));
    EXPECT_EQ(parse_line_search(line_search_name(ls)), ls);
    OptimizerSettings s;
    s.kind = OptimizerKind::LBFGS;
    s.max_iterations = 300;
    s.tolerance = 1e-12;
    s.lbfgs_line_search = ls;
    s.lbfgs_memory = 20;
    OptimizerState st;
    st.theta = Eigen::VectorXd::Constant(6, -1.2);
    int r_calls = 0, j_calls = 0, fused_calls = 0;
    const ResidualFn rf = [&](const Eigen::VectorXd& x) {
      ++r_calls;
      return test::rosenbrock_residuals(x);
    };
    const JacobianFn jf = [&](const Eigen::VectorXd& x, const Eigen::VectorXd&) {
      ++j_calls;
      return test::rosenbrock_jacobian(x);
    };
    const ResidualJacobianFn ff = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
      ++fused_calls;
      r = test::rosenbrock_residuals(x);
      return test::rosenbrock_jacobian(x);
    };
    optimize(rf, s, st, {}, jf, ff);
    // Every trial is one fused evaluation (f and gradient together); the iteration
    // after an accepted search takes that point's Jacobian, so only the start has a
    // plain rollout and a separate Jacobian.
    EXPECT_EQ(j_calls, 1);
    EXPECT_EQ(r_calls, 1);
    EXPECT_EQ(fused_calls + 2, st.evaluations);
    EXPECT_GT(st.iteration, 5);
    for (size_t i = 1; i < st.history.size(); ++i) EXPECT_LE(st.history[i], st.history[i - 1]);
    // Converged to the minimum: the gradient J^T r vanishes there.
    const Eigen::VectorXd r = test::rosenbrock_residuals(st.theta);
    EXPECT_LT((test::rosenbrock_jacobian(st.theta).transpose() * r).norm(), 1e-5);
  }
  EXPECT_THROW(parse_line_search("more_thuente"), std::invalid_argument);
}

TEST(OptimizerLbfgs, RawGradientFirstStepAndMemory) {
  // lbfgs_initial_step 0: the first trial is theta - g (alpha 1 on the raw gradient).
  OptimizerSettings s;
  s.kind = OptimizerKind::LBFGS;
  s.max_iterations = 1;
  s.lbfgs_initial_step = 0;
  OptimizerState st;
  st.theta = Eigen::VectorXd::Constant(4, 0.5);
  std::vector<Eigen::VectorXd> trials;
  const ResidualFn rf = [&](const Eigen::VectorXd& x) {
    trials.push_back(x);
    return test::rosenbrock_residuals(x);
  };
  const JacobianFn jf = [](const Eigen::VectorXd& x, const Eigen::VectorXd&) { return test::rosenbrock_jacobian(x); };
  const Eigen::VectorXd x0 = st.theta;
  const Eigen::VectorXd g = test::rosenbrock_jacobian(x0).transpose() * test::rosenbrock_residuals(x0);
  optimize(rf, s, st, {}, jf);
  ASSERT_GE(trials.size(), 2u);
  EXPECT_LT((trials[1] - (x0 - g)).norm(), 1e-14);
  // Memory 1 and 20 both converge on the damped Rosenbrock (memory 1 more slowly).
  for (int m : {1, 20}) {
    OptimizerSettings sm;
    sm.kind = OptimizerKind::LBFGS;
    sm.max_iterations = 2000;
    sm.tolerance = 1e-12;
    sm.lbfgs_memory = m;
    OptimizerState sst;
    sst.theta = Eigen::VectorXd::Constant(6, -1.2);
    optimize(test::rosenbrock_residuals, sm, sst, {}, jf);
    const Eigen::VectorXd r = test::rosenbrock_residuals(sst.theta);
    EXPECT_LT((test::rosenbrock_jacobian(sst.theta).transpose() * r).norm(), 1e-4) << m;
  }
}

namespace {
struct HybridWolfeRun {
  OptimizerState st;
  std::vector<Eigen::VectorXd> thetas;  // theta after each iteration (first: the start)
  int fused_calls = 0;
};

// The hybrid on the damped Rosenbrock, started in its L-BFGS phase (state.in_lbfgs,
// as a resumed run) with stall = 0 so that phase goes on while it gains (LM alone
// solves this problem without ever stalling).
HybridWolfeRun hybrid_wolfe_run(OptimizerSettings::LineSearch hybrid_ls, OptimizerSettings::LineSearch pure_ls) {
  OptimizerSettings s;
  s.kind = OptimizerKind::Hybrid;
  s.max_iterations = 200;
  s.tolerance = 1e-14;
  s.stall = 0;
  s.hybrid_lbfgs_line_search = hybrid_ls;
  s.lbfgs_line_search = pure_ls;  // the pure L-BFGS's: must not reach the hybrid
  HybridWolfeRun run;
  run.st.theta = Eigen::VectorXd::Constant(6, -1.2);
  run.st.in_lbfgs = true;
  run.thetas.push_back(run.st.theta);
  const JacobianFn jf = [](const Eigen::VectorXd& x, const Eigen::VectorXd&) { return test::rosenbrock_jacobian(x); };
  // Not fused_trials: only an LBFGS++ search (f and gradient at every trial) calls it.
  const ResidualJacobianFn ff = [&run](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    ++run.fused_calls;
    r = test::rosenbrock_residuals(x);
    return test::rosenbrock_jacobian(x);
  };
  const IterationFn on_it = [&run](const OptimizerState& st) {
    run.thetas.push_back(st.theta);
    return true;
  };
  optimize(test::rosenbrock_residuals, s, run.st, on_it, jf, ff);
  return run;
}
}  // namespace

TEST(OptimizerLbfgs, HybridWolfePhaseMeetsTheWolfeConditionsAndLowersEveryAcceptedStep) {
  using L = OptimizerSettings::LineSearch;
  const HybridWolfeRun w = hybrid_wolfe_run(L::Wolfe, L::Armijo);
  const auto grad = [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    return test::rosenbrock_jacobian(x).transpose() * test::rosenbrock_residuals(x);
  };
  const auto f = [](const Eigen::VectorXd& x) { return 0.5 * test::rosenbrock_residuals(x).squaredNorm(); };
  int lbfgs_steps = 0;
  ASSERT_EQ(w.thetas.size(), w.st.history.size());
  for (size_t i = 0; i < w.st.step_kinds.size(); ++i) {
    const std::string& k = w.st.step_kinds[i];
    const Eigen::VectorXd &x0 = w.thetas[i], &x1 = w.thetas[i + 1];
    if (k.find("rejected") != std::string::npos) {
      EXPECT_EQ(w.st.history[i + 1], w.st.history[i]) << i;
      continue;
    }
    EXPECT_LT(w.st.history[i + 1], w.st.history[i]) << i << " " << k;  // every accepted step lowers it
    if (k != "lbfgs") continue;
    ++lbfgs_steps;
    // Wolfe conditions along the accepted step s = x1 - x0 (c1 = 1e-4, c2 = 0.9):
    // sufficient decrease and curvature g(x1).s >= c2 g(x0).s.
    const Eigen::VectorXd sv = x1 - x0;
    EXPECT_LE(f(x1), f(x0) + 1e-4 * grad(x0).dot(sv) + 1e-12) << i;
    EXPECT_GE(grad(x1).dot(sv), 0.9 * grad(x0).dot(sv) - 1e-12) << i;
  }
  EXPECT_GE(lbfgs_steps, 5);
  EXPECT_GT(w.fused_calls, 0);
  EXPECT_LT(grad(w.st.theta).norm(), 1e-5);  // at the minimum
  // The default phase (Armijo, no gradient at trials) even when the pure L-BFGS is set to Wolfe.
  const HybridWolfeRun a = hybrid_wolfe_run(L::Armijo, L::Wolfe);
  EXPECT_EQ(a.fused_calls, 0);
  EXPECT_NE(std::count(a.st.step_kinds.begin(), a.st.step_kinds.end(), "lbfgs"), 0);
}
