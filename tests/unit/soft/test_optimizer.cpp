// Optimizers: every accepted step lowers the objective (monotone history) for LM,
// L-BFGS and the hybrid; all reach 1% of the initial objective on a small
// nonlinear least-squares problem (extended Rosenbrock plus a damping residual).
#include <gtest/gtest.h>

#include "pliant/soft/optimizer.h"

using namespace pliant::soft;

namespace {
Eigen::VectorXd rosenbrock(const Eigen::VectorXd& x) {
  Eigen::VectorXd r(x.size() + 1);
  for (int i = 0; i + 1 < x.size(); i += 2) {
    r[i] = 10 * (x[i + 1] - x[i] * x[i]);
    r[i + 1] = 1 - x[i];
  }
  r[x.size()] = 0.1 * x.sum();
  return r;
}
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
