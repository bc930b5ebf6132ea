// The optimizer's opt-in trial handling (tenth session): fused trials (residuals and
// Jacobian from one evaluation) follow exactly the path of separate evaluations
// without a second Jacobian pass; the trust-region damping halves the scaled step
// after a rejected trial; the soft wiring returns the rollout's residuals to the
// last bit; the high-jump scene compiles and a reduced high jump reaches 90% of
// its target in re-simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pliant/core/scene.h"
#include "pliant/core/error.h"
#include "pliant/soft/soft.h"
#include "optimizer_test_problems.h"
#include "soft_test_scenes.h"

using namespace pliant;
using namespace pliant::soft;

TEST(OptimizerTrials, FusedTrialsFollowTheSamePathWithoutASecondJacobianPass) {
  for (OptimizerKind k : {OptimizerKind::LM, OptimizerKind::LBFGS, OptimizerKind::Hybrid}) {
    SCOPED_TRACE(optimizer_name(k));
    OptimizerSettings s;
    s.kind = k;
    s.max_iterations = 60;
    s.tolerance = 1e-10;
    s.broyden_reuse = 0;  // the fused path never takes Broyden steps
    OptimizerState a, b;
    a.theta = b.theta = Eigen::VectorXd::Constant(6, -1.2);
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
    optimize(rf, s, a, {}, jf, ff);  // fused_trials off: ff unused
    EXPECT_EQ(fused_calls, 0);
    const int separate_r = r_calls, separate_j = j_calls;
    ASSERT_GT(separate_j, 3);
    s.fused_trials = true;
    optimize(rf, s, b, {}, jf, ff);
    EXPECT_EQ(r_calls, separate_r);  // no plain rollouts
    EXPECT_EQ(j_calls, separate_j);  // and no separate Jacobians
    // Same iterates: every Jacobian came from the evaluation at the accepted point.
    ASSERT_EQ(a.history.size(), b.history.size());
    for (size_t i = 0; i < a.history.size(); ++i) EXPECT_EQ(a.history[i], b.history[i]) << i;
    EXPECT_EQ((a.theta - b.theta).norm(), 0.0);
    // A Jacobian counted one rollout; fused, it rides on its point's evaluation.
    EXPECT_EQ(b.evaluations, a.evaluations - separate_j);
    EXPECT_EQ(fused_calls, b.evaluations);
  }
}

TEST(OptimizerTrials, TrustRegionHalvesTheScaledStepAfterARejectedTrial) {
  // r0 = x0^3 + x0 + x1 / 2 - 10, r1 = x1 (root x = (2, 0)): from 0 the Gauss-Newton
  // step x0 = 10 overshoots (r0 = 1000), and so does 5 (r0 = 120); 2.5 is accepted.
  const auto r = [](const Eigen::VectorXd& x) {
    Eigen::VectorXd v(2);
    v << x[0] * x[0] * x[0] + x[0] + 0.5 * x[1] - 10, x[1];
    return v;
  };
  const auto jac = [](const Eigen::VectorXd& x) {
    Eigen::MatrixXd J(2, 2);
    J << 3 * x[0] * x[0] + 1, 0.5, 0, 1;
    return J;
  };
  for (bool trust : {true, false}) {
    SCOPED_TRACE(trust ? "trust region" : "marquardt");
    OptimizerSettings s;
    s.kind = OptimizerKind::LM;
    s.max_iterations = 1;
    s.broyden_reuse = 0;
    if (trust) s.lm_damping = OptimizerSettings::Damping::TrustRegion;
    OptimizerState st;
    st.theta = Eigen::VectorXd::Zero(2);
    std::vector<Eigen::VectorXd> points;
    optimize([&](const Eigen::VectorXd& x) {
      points.push_back(x);
      return r(x);
    }, s, st, {}, [&](const Eigen::VectorXd& x, const Eigen::VectorXd&) { return jac(x); });
    ASSERT_GE(points.size(), 3u);  // the start, then trials
    // Step lengths in Marquardt's scaling, diag(J^T J) at the start.
    const Eigen::MatrixXd J0 = jac(points[0]);
    const Eigen::VectorXd D = (J0.transpose() * J0).diagonal().array() + 1e-9;
    const auto len = [&](size_t i) { return std::sqrt(D.dot((points[i] - points[0]).cwiseAbs2())); };
    EXPECT_NEAR(points[1][0], 10, 0.1);  // the first trial is the (nearly) undamped step
    EXPECT_EQ(st.iteration, 1);
    ASSERT_LT(st.history.back(), st.history.front());  // one step accepted in the end
    if (trust) {
      ASSERT_EQ(points.size(), 4u);  // 10 and 5 rejected, 2.5 accepted
      EXPECT_NEAR(len(2) / len(1), 0.5, 0.06);
      EXPECT_NEAR(len(3) / len(2), 0.5, 0.06);
    } else {
      // lambda x 4 per rejection: the step shrinks slowly, more trials are wasted.
      EXPECT_GT(points.size(), 4u);
      EXPECT_GT(len(2) / len(1), 0.9);
    }
  }
}

TEST(OptimizerTrials, FusedSensitivityGivesTheRolloutResidualsAndJacobian) {
  Scene sc = load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/soft_t_jump_high.json");
  SoftModel m = soft_compile(sc);
  soft_bind(m);
  // The shipped scene: the T-shape's own height, forward, the activation bound that
  // makes it reachable, and the opt-in trial handling.
  EXPECT_EQ(m.problem.obj.jump_height_m, 0.8);
  EXPECT_EQ(m.problem.obj.distance_m, 0.5);
  EXPECT_EQ(m.problem.dmp.max_activation_rel, 5.0);
  EXPECT_TRUE(m.optimizer.fused_trials);
  EXPECT_EQ(m.optimizer.lm_damping, OptimizerSettings::Damping::TrustRegion);
  // A short horizon keeps the test fast; the comparison is exact at any length.
  Problem p = m.problem;
  p.frames = 6;
  const Eigen::VectorXd theta = initial_theta(p) * 50;
  const ResidualJacobianFn fused = problem_residual_jacobian(p, m.optimizer);
  ASSERT_TRUE(static_cast<bool>(fused));
  Eigen::VectorXd r;
  const Eigen::MatrixXd J = fused(theta, r);
  const Eigen::VectorXd r_plain = residuals(p, theta);
  ASSERT_EQ(r.size(), r_plain.size());
  EXPECT_EQ((r - r_plain).cwiseAbs().maxCoeff(), 0.0);  // the same rollout, bit for bit
  EXPECT_EQ((J - sensitivity_jacobian(p, theta)).cwiseAbs().maxCoeff(), 0.0);
  OptimizerSettings off = m.optimizer;
  off.fused_trials = false;
  EXPECT_FALSE(static_cast<bool>(problem_residual_jacobian(p, off)));
}

TEST(OptimizerTrials, SmallTShapeHighJumpReachesNinetyPercentInResimulation) {
  // The high-jump scene at the unit tests' size (4 cells, 30 frames of 25 ms): 0.4 m
  // up and 0.2 m forward from rest, fused trials and the trust region.
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "t_shape.obj", "resolution": 4, "modes": 6},
    "material": {"density_kg_per_m3": 1000, "young_pa": 2e5, "poisson": 0.3},
    "environment": {"type": "ground", "friction": 0.8},
    "simulation": {"dt_s": 0.025, "frames": 30},
    "controller": {"modes": 6, "kernels": 3, "period_s": 0.6, "max_activation_rel": 5.0},
    "objectives": {"jump": {"height_m": 0.4, "weight": 100},
                   "distance": {"distance_m": 0.2, "direction": [1, 0, 0], "weight": 100},
                   "effort": {"weight": 1e-4}},
    "optimizer": {"method": "hybrid", "iterations": 6, "horizon_frames": 30,
                  "fused_trials": true, "lm_damping": "trust_region"}})";
  SoftModel m = soft_compile(parse_scene(text, "t.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
  soft_bind(m);
  OptimizerState st;
  st.theta = initial_theta(m.problem);
  const double before = max_height_gain(m.problem, st.theta, m.frames);
  soft_optimize(m, st, {});
  ASSERT_GE(st.history.size(), 4u);
  for (size_t i = 1; i < st.history.size(); ++i) EXPECT_LT(st.history[i], st.history[i - 1]) << i;
  // Independent re-simulation of the returned controller.
  const double after = max_height_gain(m.problem, st.theta, m.frames);
  EXPECT_LT(before, 0.05 * 0.4);
  EXPECT_GE(after, 0.9 * 0.4);
}

TEST(OptimizerTrials, SceneKeysReachTheSettingsAndBadValuesAreInputErrors) {
  const char* obj = pliant::soft::test::t_shape_jump_objectives();
  const SoftModel d = soft_compile(pliant::soft::test::t_shape_scene(obj, R"({"iterations": 0})"));
  EXPECT_FALSE(d.optimizer.fused_trials);  // opt-in: the shipped results stay as they were
  EXPECT_EQ(d.optimizer.lm_damping, OptimizerSettings::Damping::Marquardt);
  const SoftModel m = soft_compile(pliant::soft::test::t_shape_scene(
      obj, R"({"iterations": 0, "fused_trials": true, "lm_damping": "trust_region"})"));
  EXPECT_TRUE(m.optimizer.fused_trials);
  EXPECT_EQ(m.optimizer.lm_damping, OptimizerSettings::Damping::TrustRegion);
  auto pointer_of = [&](const std::string& optimizer) {
    try {
      soft_compile(pliant::soft::test::t_shape_scene(obj, optimizer));
    } catch (const InputError& e) {
      return e.pointer();
    }
    return std::string("no error");
  };
  EXPECT_EQ(pointer_of(R"({"lm_damping": "nielsen"})"), "/optimizer/lm_damping");
  EXPECT_EQ(pointer_of(R"({"fused_trials": 2})"), "/optimizer/fused_trials");
}
