// The steady objective (objective.h): yaw rate and lateral COM velocity over the last
// controller period of the horizon, and the periodicity of the last two periods.
// Checked on given trajectories (zero when straight and periodic, exact values when
// veering or turning out and back, where the turn term at rate 0 is blind), its
// Jacobian through the sensitivity path against central differences of rollouts,
// and the scene keys with their InputErrors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <vector>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;
using namespace pliant::soft;

namespace {

// The small T-shape on the ground: dt 25 ms, a controller period of 75 ms (three
// frames per steady window), `horizon` frames, `steady` an objectives entry.
Scene steady_t_scene(const std::string& steady, int horizon) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "t_shape.obj", "resolution": 4, "modes": 6},
    "material": {"density_kg_per_m3": 1000, "young_pa": 1e5, "poisson": 0.3},
    "environment": {"type": "ground", "friction": 0.8},
    "simulation": {"dt_s": 0.025, "frames": 30},
    "controller": {"modes": 6, "kernels": 3, "period_s": 0.075, "max_activation_rel": 1.0},
    "objectives": {"velocity": {"target_m_per_s": [0.3, 0, 0.1], "weight": 1},
                   "steady": )" + steady + R"(, "effort": {"weight": 1e-3}},
    "optimizer": {"method": "none", "horizon_frames": )" + std::to_string(horizon) + "}}";
  return parse_scene(text, "steady.json", std::string(PLIANT_ASSETS_DIR) + "/characters");
}

std::string steady_error(const std::string& steady, int horizon) {
  try {
    soft_compile(steady_t_scene(steady, horizon));
  } catch (const InputError& e) {
    return e.pointer();
  }
  return "no error";
}

}  // namespace

TEST(ObjectiveSteady, ZeroWhenStraightAndPeriodicNonZeroWhenVeeringOrTurningBack) {
  SoftModel m = soft_compile(steady_t_scene(R"({"weight": 4, "periodicity_weight": 9})", 6));
  soft_bind(m);
  Problem& p = m.problem;
  p.obj.w_velocity = 0;
  p.obj.w_effort = 0;
  p.obj.w_turn = 1;  // rate 0, speed 0: the horizon's net yaw
  ASSERT_EQ(steady_window_frames(p.obj, p.dmp.period_s, p.sim.dt_s), 3);
  const int N = p.frames;  // windows [3, 6] and [0, 3]
  const double dt = p.sim.dt_s, t = 3 * dt;
  const Eigen::VectorXd theta = Eigen::VectorXd::Zero(p.dmp.parameters());
  const SoftState s0 = initial_state(*p.character, p.start_offset_m, Eigen::Vector3d::Zero(), dt);
  auto yawed = [&](double a) { return Eigen::Matrix3d(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()) * s0.R); };
  std::vector<SoftState> straight, veer, back;
  for (int f = 1; f <= N; ++f) {
    straight.push_back(s0), veer.push_back(s0), back.push_back(s0);
    // Straight and periodic: steady progress along +x, a bob and a wobble of the
    // period's length (three frames), so only their changes could show.
    const double bob = 0.004 * (f % 3), wob = 0.02 * (f % 3);
    straight.back().c += Eigen::Vector3d(0.01 * f, bob, 0);
    straight.back().R = yawed(wob);
    veer.back().c += Eigen::Vector3d(0.01 * f, 0, 0.002 * f * f);
    back.back().R = yawed(0.05 * std::min(f, N - f));  // out and back: net yaw 0
  }
  const Eigen::VectorXd rs = trajectory_residuals(p, straight, theta);
  const Eigen::VectorXd rv = trajectory_residuals(p, veer, theta);
  const Eigen::VectorXd rb = trajectory_residuals(p, back, theta);
  ASSERT_EQ(rs.size(), 2 + 2 + 3 + theta.size());
  // Residuals 2..6: yaw rate, lateral velocity, d(vx), d(vz), d(yaw rate).
  for (int i = 2; i < 7; ++i) EXPECT_NEAR(rs[i], 0.0, 1e-12) << "residual " << i;
  // Veering z = 0.002 f^2: the lateral normal is y x (+x) = -z.
  const double vz1 = 0.002 * (36 - 9) / t, vz2 = 0.002 * 9 / t;
  EXPECT_NEAR(rv[2], 0.0, 1e-12);
  EXPECT_NEAR(rv[3], 2 * -vz1, 1e-12);
  EXPECT_NEAR(rv[4], 0.0, 1e-12);
  EXPECT_NEAR(rv[5], 3 * (vz1 - vz2), 1e-12);
  // Out and back: the turn term sees no net yaw, the steady window does (a yaw of
  // +a about +y is heading_yaw -a: -0.15 at frame 3, 0 at frame 6).
  EXPECT_NEAR(rb[0], 0.0, 1e-12);
  EXPECT_NEAR(rb[2], 2 * (0.15 / t), 1e-9);
  EXPECT_NEAR(rb[6], 3 * (0.15 / t - (-0.15 / t)), 1e-9);
}

// Central differences of whole rollouts (h = 1e-4 on the ground, as in
// test_sensitivity.cpp) against the forward-sensitivity Jacobian, on the steady rows.
TEST(ObjectiveSteady, SensitivityJacobianMatchesCentralDifferences) {
  SoftModel m = soft_compile(
      steady_t_scene(R"({"body_axis": [1, 0, 0], "direction": [1, 0, 1], "weight": 3, "periodicity_weight": 2})", 7));
  soft_bind(m);
  const Problem& p = m.problem;
  const Eigen::VectorXd theta = 10 * initial_theta(p);
  const Eigen::MatrixXd Js = sensitivity_jacobian(p, theta);
  const double h = 1e-4;
  Eigen::MatrixXd Jc(Js.rows(), Js.cols());
  for (int i = 0; i < theta.size(); ++i) {
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += h, tm[i] -= h;
    Jc.col(i) = (residuals(p, tp) - residuals(p, tm)) / (2 * h);
  }
  ASSERT_TRUE(Jc.allFinite());
  // Rows 3..7 are the steady block (after the velocity's three).
  const Eigen::MatrixXd Bs = Js.middleRows(3, 5), Bc = Jc.middleRows(3, 5);
  ASSERT_GT(Bc.cwiseAbs().maxCoeff(), 1e-3);  // the block really depends on theta
  for (int k = 0; k < 5; ++k)
    EXPECT_LT((Bs.row(k) - Bc.row(k)).cwiseAbs().maxCoeff(), 1e-4 * Bc.cwiseAbs().maxCoeff() + 1e-9) << "row " << k;
}

TEST(ObjectiveSteady, SceneKeysAndInputErrors) {
  const SoftModel m =
      soft_compile(steady_t_scene(R"({"body_axis": [0, 0, 1], "direction": [0, 0, 2], "periods": 2, "weight": 5})", 6));
  EXPECT_DOUBLE_EQ(m.problem.obj.w_steady, 5.0);
  EXPECT_DOUBLE_EQ(m.problem.obj.w_steady_periodic, 0.0);
  EXPECT_EQ(m.problem.obj.steady_periods, 2);
  EXPECT_NEAR(m.problem.obj.steady_direction.z(), 1.0, 1e-12);
  EXPECT_NEAR(m.problem.obj.steady_axis.z(), 1.0, 1e-12);
  EXPECT_EQ(steady_error(R"({"weight": -1})", 6), "/objectives/steady/weight");
  EXPECT_EQ(steady_error(R"({"periodicity_weight": -1})", 6), "/objectives/steady/periodicity_weight");
  EXPECT_EQ(steady_error(R"({"direction": [0, 1, 0]})", 6), "/objectives/steady/direction");
  EXPECT_EQ(steady_error(R"({"periods": 0})", 6), "/objectives/steady/periods");
  EXPECT_EQ(steady_error(R"({"wieght": 1})", 6), "/objectives/steady/wieght");
  // The windows must fit in the horizon: 3 frames each, two with periodicity.
  EXPECT_EQ(steady_error(R"({"weight": 1})", 2), "/objectives/steady/periods");
  EXPECT_EQ(steady_error(R"({"weight": 1})", 3), "no error");
  EXPECT_EQ(steady_error(R"({"weight": 1, "periodicity_weight": 1})", 5), "/objectives/steady/periods");
  EXPECT_EQ(steady_error(R"({"weight": 1, "periodicity_weight": 1})", 6), "no error");
}
