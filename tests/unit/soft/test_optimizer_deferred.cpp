// Deferred sensitivities: with fused trials the optimizer asks for a
// trial's Jacobian half only once the trial is accepted (LM) or meets Armijo's
// condition (LBFGS++'s backtracking searches), so rejected trials cost a rollout
// only. The path must be exactly that of the one-pass fused evaluation, and the
// soft wiring's two halves must give the one pass's bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#include "optimizer_test_problems.h"

using namespace pliant;
using namespace pliant::soft;

namespace deferred_test {
struct DeferredRun {
  OptimizerState st;
  int one_pass = 0, rollouts = 0, halves = 0;
};

DeferredRun run_rosenbrock(OptimizerSettings s, bool deferred) {
  DeferredRun out;
  out.st.theta = Eigen::VectorXd::Constant(6, -1.2);
  ResidualJacobianFn f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    ++out.one_pass;
    r = test::rosenbrock_residuals(x);
    return test::rosenbrock_jacobian(x);
  };
  if (deferred)
    f.deferred = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) -> DeferredJacobian {
      ++out.rollouts;
      r = test::rosenbrock_residuals(x);
      return [&out, x] {
        ++out.halves;
        return test::rosenbrock_jacobian(x);
      };
    };
  const ResidualFn none = [](const Eigen::VectorXd&) -> Eigen::VectorXd {
    ADD_FAILURE() << "a plain rollout with fused trials";
    return {};
  };
  optimize(none, s, out.st, {}, {}, f);
  return out;
}
}  // namespace deferred_test
using namespace deferred_test;

TEST(OptimizerDeferred, SamePathAsOnePassWithJacobiansOnlyAtAcceptedPoints) {
  using LS = OptimizerSettings::LineSearch;
  struct Case {
    OptimizerKind kind;
    LS ls;
    const char* name;
  };
  for (const Case& c : {Case{OptimizerKind::LM, LS::Armijo, "lm"}, Case{OptimizerKind::Hybrid, LS::Armijo, "hybrid"},
                        Case{OptimizerKind::LBFGS, LS::Armijo, "lbfgs armijo"},
                        Case{OptimizerKind::LBFGS, LS::Wolfe, "lbfgs wolfe"},
                        Case{OptimizerKind::LBFGS, LS::StrongWolfe, "lbfgs strong wolfe"}}) {
    SCOPED_TRACE(c.name);
    OptimizerSettings s;
    s.kind = c.kind;
    s.max_iterations = 60;
    s.tolerance = 1e-10;
    s.fused_trials = true;
    s.lm_damping = OptimizerSettings::Damping::TrustRegion;
    s.lbfgs_line_search = c.ls;
    s.lbfgs_initial_step = 0;  // the raw gradient: long first steps, rejected trials
    const DeferredRun a = run_rosenbrock(s, false), b = run_rosenbrock(s, true);
    ASSERT_EQ(a.st.history.size(), b.st.history.size());
    for (size_t i = 0; i < a.st.history.size(); ++i) EXPECT_EQ(a.st.history[i], b.st.history[i]) << i;
    EXPECT_EQ((a.st.theta - b.st.theta).norm(), 0.0);
    EXPECT_EQ(a.st.step_kinds, b.st.step_kinds);
    EXPECT_EQ(a.st.evaluations, b.st.evaluations);  // a trial counts one rollout either way
    // Converged: the damping residual keeps the minimum above zero (0.1444...), so
    // the check is the gradient J^T r there against the start's.
    const auto gradient = [](const Eigen::VectorXd& x) {
      return Eigen::VectorXd(test::rosenbrock_jacobian(x).transpose() * test::rosenbrock_residuals(x));
    };
    EXPECT_LT(gradient(a.st.theta).norm(), 1e-5 * gradient(Eigen::VectorXd::Constant(6, -1.2)).norm());
    EXPECT_EQ(b.one_pass, 0);  // the deferred halves replace every one-pass evaluation
    EXPECT_EQ(b.rollouts, a.one_pass);
    // One Jacobian half per accepted iteration plus the start (Wolfe: plus trials
    // that met Armijo but not the curvature condition); some trials were rejected.
    const int accepted = int(std::count_if(b.st.step_kinds.begin(), b.st.step_kinds.end(), [](const std::string& k) {
      return k.find("rejected") == std::string::npos;
    }));
    if (c.ls == LS::Armijo) EXPECT_EQ(b.halves, accepted + 1);
    else EXPECT_GE(b.halves, accepted + 1);
    EXPECT_LT(b.halves, b.rollouts);
  }
}

TEST(OptimizerDeferred, SoftHalvesGiveTheOnePassBits) {
  Scene sc = load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/soft_t_jump_high.json");
  SoftModel m = soft_compile(sc);
  soft_bind(m);
  Problem p = m.problem;
  p.frames = 6;  // short: the comparison is exact at any length
  const Eigen::VectorXd theta = initial_theta(p) * 50;
  const ResidualJacobianFn f = problem_residual_jacobian(p, m.optimizer);
  ASSERT_TRUE(static_cast<bool>(f.deferred));
  Eigen::VectorXd r1, r2;
  const Eigen::MatrixXd J1 = f(theta, r1);
  const DeferredJacobian later = f.deferred(theta, r2);
  // Another rollout in between (the thread's buffers are reused): the trial's own
  // frames still give its Jacobian.
  Eigen::VectorXd r3;
  const DeferredJacobian other = f.deferred(initial_theta(p), r3);
  const Eigen::MatrixXd J2 = later();
  ASSERT_EQ(r1.size(), r2.size());
  EXPECT_EQ((r1 - r2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((r2 - residuals(p, theta)).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_EQ(J2.rows(), J1.rows());
  EXPECT_EQ((J1 - J2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(J1.norm(), 0);
  EXPECT_EQ((other() - sensitivity_jacobian(p, initial_theta(p))).cwiseAbs().maxCoeff(), 0.0);
}
