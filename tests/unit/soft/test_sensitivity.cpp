// Forward-sensitivity rollout Jacobians (sensitivity.cpp) against central differences
// of whole rollouts: in the air (rigid coordinates free), on the ground with contact
// and friction, in water with drag; the optimizer with them lowers the objective.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#include "soft_test_scenes.h"

using namespace pliant;
using namespace pliant::soft;

namespace {

// The small T-shape (4 cells, 6 modes), `frames` steps of 25 ms.
SoftModel t_model(const std::string& environment, const std::string& start, int frames, bool turn = false) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "t_shape.obj", "resolution": 4, "modes": 6},
    "material": {"density_kg_per_m3": 1000, "young_pa": 1e5, "poisson": 0.3},
    "environment": )" + environment + R"(,
    "simulation": {"dt_s": 0.025, "frames": 30, "start_offset_m": )" + start + R"(},
    "controller": {"modes": 6, "kernels": 3, "period_s": 0.3, "max_activation_rel": 1.0},
    "objectives": {"velocity": {"target_m_per_s": [0.3, 0, 0.1], "weight": 1},
                   "heading": {"body_axis": [1, 0, 0], "direction": [0, 0, 1], "weight": 1},
                   "jump": {"height_m": 0.03, "weight": 10},
                   "upright": {"weight": 2},
                   )" + std::string(turn ? R"("turn": {"body_axis": [1, 0, 0], "rate_rad_per_s": 0.5, "speed_m_per_s": 0.1, "weight": 1},)" : "") + R"(
                   "effort": {"weight": 1e-3}},
    "optimizer": {"method": "hybrid", "horizon_frames": )" + std::to_string(frames) + "}}";
  SoftModel m = soft_compile(parse_scene(text, "t.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
  soft_bind(m);
  return m;
}

// Largest |J_sens - J_central| over the largest |J_central| entry.
double relative_jacobian_error(const Problem& p, const Eigen::VectorXd& theta, double h) {
  const Eigen::MatrixXd Js = sensitivity_jacobian(p, theta);
  Eigen::MatrixXd Jc(Js.rows(), Js.cols());
  for (int i = 0; i < theta.size(); ++i) {
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += h, tm[i] -= h;
    Jc.col(i) = (residuals(p, tp) - residuals(p, tm)) / (2 * h);
  }
  EXPECT_TRUE(Jc.allFinite());
  return (Js - Jc).cwiseAbs().maxCoeff() / Jc.cwiseAbs().maxCoeff();
}

Eigen::VectorXd active_theta(const Problem& p) { return 10 * initial_theta(p); }

}  // namespace

// Central-difference steps: the rollouts carry ~1e-8 of Newton noise in R (the
// reference's error ~3e-8 / h), their truncation error is ~1e-4 at h = 1e-3 with the
// stiff ground contact (3e-5 in the air): h = 1e-3 in the air and in water, 1e-4 on
// the ground. The sensitivity Jacobian itself has no step.
TEST(Sensitivity, MatchesCentralDifferencesInTheAir) {
  // Falling and tumbling: translation, rotation (heading term) and modes all move.
  SoftModel m = t_model(R"({"type": "ground", "ground": false})", "[0, 1, 0]", 6);
  const double err = relative_jacobian_error(m.problem, active_theta(m.problem), 1e-3);
  EXPECT_LT(err, 1e-4);
  // (Without the floating frame's curvature terms in H, i.e. the Gauss-Newton
  // Hessian, the error is 68% here, 7.5% on the ground and 59% in water.)
}

TEST(Sensitivity, MatchesCentralDifferencesWithGroundContactAndFriction) {
  // Standing, pushing and sliding on the ground; the turn term reads the yaw.
  SoftModel m = t_model(R"({"type": "ground", "friction": 0.8})", "[0, 0, 0]", 6, true);
  const double err = relative_jacobian_error(m.problem, active_theta(m.problem), 1e-4);
  EXPECT_LT(err, 1e-4);
}

TEST(Sensitivity, MatchesCentralDifferencesWithDrag) {
  SoftModel m = t_model(R"({"type": "water"})", "[0, 0, 0]", 6);
  const double err = relative_jacobian_error(m.problem, active_theta(m.problem), 1e-3);
  EXPECT_LT(err, 1e-4);
}

TEST(Sensitivity, OptimizerWithSensitivityJacobianLowersTheObjective) {
  // The T-shape jump of test_objective.cpp, a short horizon.
  SoftModel m = soft_compile(test::t_shape_scene(test::t_shape_jump_objectives(), R"({"horizon_frames": 16})"));
  soft_bind(m);
  m.optimizer.jacobian = JacobianKind::Sensitivity;
  m.optimizer.max_iterations = 3;
  for (OptimizerKind k : {OptimizerKind::Hybrid, OptimizerKind::LBFGS}) {
    m.optimizer.kind = k;
    OptimizerState st;
    st.theta = initial_theta(m.problem);
    int calls = 0;
    const JacobianFn jf = problem_jacobian(m.problem, m.optimizer);
    ASSERT_TRUE(bool(jf));
    optimize([&](const Eigen::VectorXd& th) { return residuals(m.problem, th); }, m.optimizer, st, {},
             [&](const Eigen::VectorXd& th, const Eigen::VectorXd& r0) {
               ++calls;
               return jf(th, r0);
             });
    EXPECT_GE(calls, 1);
    // 0.075 -> 9.4e-4 (hybrid), 1.5e-4 (L-BFGS) in 3 iterations.
    EXPECT_LT(st.history.back(), 0.05 * st.history.front()) << optimizer_name(k);
    // A Jacobian counts one rollout: far fewer than n + 1 per iteration.
    EXPECT_LT(st.evaluations, st.iteration * (1 + int(st.theta.size())));
  }
}

// Rotation-strain coordinates: the map's Jacobian Jq(q) in place of U and its
// curvature (contracted with the elastic and node forces) in the Hessian. The
// rollouts' Newton noise is larger here (lagged map Jacobian), so h = 1e-3 (error
// 1.5e-5; 1.3e-4 at h = 1e-4, 1/h noise). Without the curvature: 6.1% error. The
// reduced map (cubature remainder, difference curvature) gives 5.0e-5 at h = 3e-4;
// not checked here (0.37 s more: its reconstruction's training).
TEST(Sensitivity, RotationStrainMatchesCentralDifferences) {
  SoftModel m = t_model(R"({"type": "ground", "friction": 0.8})", "[0, 0, 0]", 6, true);
  enable_rotation_strain(m.character);
  m.optimizer.jacobian = JacobianKind::Sensitivity;
  EXPECT_TRUE(bool(problem_jacobian(m.problem, m.optimizer)));
  EXPECT_LT(relative_jacobian_error(m.problem, active_theta(m.problem), 1e-3), 1e-4);
}

TEST(Sensitivity, SceneKeySelectsTheJacobian) {
  const auto compile = [](const std::string& jac) {
    return soft_compile(test::t_shape_scene(test::t_shape_jump_objectives(), R"({"jacobian": ")" + jac + R"("})"));
  };
  EXPECT_EQ(compile("sensitivity").optimizer.jacobian, JacobianKind::Sensitivity);
  EXPECT_EQ(compile("finite_difference").optimizer.jacobian, JacobianKind::FiniteDifference);
  EXPECT_EQ(compile("sensitivity").spacetime.jacobian, JacobianKind::Sensitivity);  // both optimizers
  EXPECT_EQ(compile("finite_difference").spacetime.jacobian, JacobianKind::FiniteDifference);
  EXPECT_THROW(compile("exact"), InputError);
}
