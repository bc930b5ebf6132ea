// Optimizers: every accepted step lowers the objective (monotone history) for LM,
// L-BFGS and the hybrid; all reach 1% of the initial objective on a small
// nonlinear least-squares problem (extended Rosenbrock plus a damping residual).
#include <gtest/gtest.h>

#include <algorithm>

#include "optimizer_test_problems.h"
#include "pliant/soft/optimizer.h"

using namespace pliant::soft;

namespace {
const auto rosenbrock = test::rosenbrock_residuals;
}  // namespace

TEST(Optimizer, MonotoneAndConvergentForEveryKind) {
  for (OptimizerKind k : {OptimizerKind::LM, OptimizerKind::LBFGS, OptimizerKind::Hybrid}) {
    SCOPED_TRACE(optimizer_name(k));
    OptimizerSettings s;
    s.kind = k;
    s.max_iterations = 400;
    s.fd_step = 1e-7;
    s.tolerance = 0.01;
    OptimizerState st;
    st.theta = Eigen::VectorXd::Constant(6, -1.2);
    int calls = 0;
    optimize(rosenbrock, s, st, [&](const OptimizerState& o) {
      ++calls;
      return true;
    });
    ASSERT_GE(st.history.size(), 2u);
    for (size_t i = 1; i < st.history.size(); ++i) EXPECT_LE(st.history[i], st.history[i - 1]);
    EXPECT_LE(st.history.back(), 0.01 * st.history.front());
    EXPECT_EQ(calls, st.iteration);
  }
}

TEST(Optimizer, FiniteDifferenceJacobianMatchesAnalytic) {
  Eigen::VectorXd x(4);
  x << 0.3, -0.7, 1.1, 0.4;
  const Eigen::MatrixXd J = fd_jacobian(rosenbrock, x, rosenbrock(x), 1e-7);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(5, 4);
  for (int i = 0; i < 4; i += 2) {
    A(i, i) = -20 * x[i];
    A(i, i + 1) = 10;
    A(i + 1, i) = -1;
  }
  A.row(4).setConstant(0.1);
  EXPECT_LT((J - A).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(Optimizer, BroydenUpdateMeetsTheSecantEquationAndNothingElse) {
  Eigen::MatrixXd J(5, 3);
  J << 1, 2, 3, -1, 0.5, 2, 0, 1, -2, 4, 1, 1, 0.3, -0.7, 2;
  const Eigen::MatrixXd J0 = J;
  Eigen::VectorXd d(3), dr(5);
  d << 0.2, -0.1, 0.4;
  dr << 1, -2, 0.5, 0.3, 0.9;
  broyden_update(J, d, dr);
  EXPECT_LT((J * d - dr).norm(), 1e-12);  // secant: J_new d = r(x + d) - r(x)
  Eigen::VectorXd v(3);
  v << 1, 2, 0;  // orthogonal to d
  ASSERT_NEAR(v.dot(d), 0, 1e-15);
  EXPECT_LT((J * v - J0 * v).norm(), 1e-12);
  // Residuals linear in x: the exact Jacobian stays exact under the update.
  Eigen::MatrixXd A = J0;
  broyden_update(A, d, J0 * d);
  EXPECT_LT((A - J0).norm(), 1e-12);
}

TEST(Optimizer, BroydenReuseReachesRosenbrockMinimumWithFewerRollouts) {
  // The same LM with and without Broyden-updated Jacobians: both monotone and at
  // the minimum x = 1; the updated Jacobian must
  // make accepted one-rollout steps, so the reuse run needs fewer rollouts. A wrong
  // update gives rejected reuse steps (each costs a rollout) and fails the count.
  int evals[2];
  for (int reuse : {0, 4}) {
    OptimizerSettings s;
    s.kind = OptimizerKind::LM;
    s.max_iterations = 400;
    s.fd_step = 1e-7;
    s.tolerance = 1e-12;
    s.broyden_reuse = reuse;
    OptimizerState st;
    st.theta = Eigen::VectorXd::Constant(6, -1.2);
    // Extended Rosenbrock without the damping residual: minimum 0 at x = 1.
    optimize([](const Eigen::VectorXd& x) { return Eigen::VectorXd(rosenbrock(x).head(x.size())); }, s, st);
    for (size_t i = 1; i < st.history.size(); ++i) EXPECT_LE(st.history[i], st.history[i - 1]);
    EXPECT_LE(st.history.back(), 1e-12 * st.history.front()) << "reuse " << reuse;
    EXPECT_LT((st.theta - Eigen::VectorXd::Ones(6)).norm(), 1e-3) << "reuse " << reuse;
    const int broyden_steps = int(std::count(st.step_kinds.begin(), st.step_kinds.end(), "lm-broyden"));
    if (reuse) EXPECT_GE(broyden_steps, 3);
    else EXPECT_EQ(broyden_steps, 0);
    evals[reuse ? 1 : 0] = st.evaluations;
  }
  EXPECT_LT(evals[1], evals[0]);
}

// The hybrid at a minimum it cannot improve on (the damping residual keeps it above
// zero, so the tolerance is never met) stops after three wholly rejected iterations:
// LM, L-BFGS and LM again from a fresh damping at the same theta, after which each
// iteration would repeat one of the last two (before: up to 12 + 20 rollouts per
// iteration until max_iterations). Called again on its state it does nothing more.
TEST(Optimizer, HybridStopsOnceItOnlyRepeatsRejectedIterations) {
  for (const auto damping : {OptimizerSettings::Damping::Marquardt, OptimizerSettings::Damping::TrustRegion}) {
    SCOPED_TRACE(damping == OptimizerSettings::Damping::Marquardt ? "marquardt" : "trust region");
    OptimizerSettings s;
    s.kind = OptimizerKind::Hybrid;
    s.max_iterations = 200;
    s.tolerance = 1e-12;
    s.lm_damping = damping;
    OptimizerState st;
    st.theta = Eigen::VectorXd::Constant(6, -1.2);
    const JacobianFn exact = [](const Eigen::VectorXd& x, const Eigen::VectorXd&) {
      return test::rosenbrock_jacobian(x);
    };
    optimize(rosenbrock, s, st, {}, exact);
    EXPECT_LT(st.iteration, 60);
    ASSERT_GE(st.step_kinds.size(), 4u);
    const size_t k = st.step_kinds.size();
    for (size_t i = k - 3; i < k; ++i) EXPECT_TRUE(st.step_kinds[i].ends_with("-rejected")) << st.step_kinds[i];
    EXPECT_FALSE(st.step_kinds[k - 4].ends_with("-rejected")) << st.step_kinds[k - 4];
    const Eigen::VectorXd g = test::rosenbrock_jacobian(st.theta).transpose() * rosenbrock(st.theta);
    EXPECT_LT(g.norm(), 1e-6);  // a stationary point: nothing left to gain
    const int evaluations = st.evaluations, iterations = st.iteration;
    optimize(rosenbrock, s, st, {}, exact);  // a resume of the finished run
    EXPECT_EQ(st.iteration, iterations);
    EXPECT_EQ(st.evaluations, evaluations);
  }
}
