// Forward model properties: the upwind density step conserves mass in a closed box
// to round-off, projection leaves a divergence-free field, the float API matches.
#include <gtest/gtest.h>

#include <numeric>
#include <random>

#include "control/control_forward_model.h"
#include "control_test_util.h"

namespace pliant::smoke {
namespace {

using control_detail::Vec;

TEST(ControlForward, UpwindConservesMassInClosedBox) {
  const ControlModel m = test::tiny_model(24, 20, 12);
  control_detail::ForwardOps ops(m, 1e-10);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 30.0);
  std::vector<Vec> f(12, Vec(ops.faces()));
  for (Vec& fi : f)
    for (double& x : fi) x = n(rng);
  control_detail::TrajectoryD t;
  control_detail::forward_d(m, ops, f, t);
  const double m0 = std::accumulate(t.rho[0].begin(), t.rho[0].end(), 0.0);
  int max_sub = 0;
  for (int i = 1; i <= 12; ++i) {
    const double mi = std::accumulate(t.rho[i].begin(), t.rho[i].end(), 0.0);
    EXPECT_NEAR(mi, m0, 1e-12 * m0) << "frame " << i;
    EXPECT_LT(ops.max_divergence(t.u[i]), 1e-7 * 30.0 / 0.01) << "frame " << i;
    for (double r : t.rho[i]) EXPECT_GE(r, -1e-12);  // positivity from the sub-step bound
    max_sub = std::max(max_sub, t.substeps[i - 1]);
  }
  EXPECT_GT(max_sub, 1);  // the forces are strong enough to need sub-steps
}

TEST(ControlForward, ObstaclesStayEmptyAndMassIsKept) {
  ControlModel m = test::tiny_model(20, 20, 8);
  m.solid.assign(400, 0);
  for (int j = 5; j < 15; ++j) m.solid[12 + 20 * j] = 1;  // a wall segment right of the blob
  for (size_t c = 0; c < 400; ++c)
    if (m.solid[c]) m.initial_density[c] = 0.0f;
  control_detail::ForwardOps ops(m, 1e-10);
  std::vector<Vec> f(8, Vec(ops.faces(), 0.0));
  for (size_t e = 0; e < ops.layout(0).count(); ++e) f[0][e] = 20.0;  // push everything towards +x
  control_detail::TrajectoryD t;
  control_detail::forward_d(m, ops, f, t);
  const double m0 = std::accumulate(t.rho[0].begin(), t.rho[0].end(), 0.0);
  for (int i = 1; i <= 8; ++i) {
    EXPECT_NEAR(std::accumulate(t.rho[i].begin(), t.rho[i].end(), 0.0), m0, 1e-12 * m0);
    for (size_t c = 0; c < 400; ++c)
      if (m.solid[c]) {
        EXPECT_EQ(t.rho[i][c], 0.0) << "frame " << i << " cell " << c;
      }
  }
}

TEST(ControlForward, ZeroForceKeepsDensityStill) {
  const ControlModel m = test::tiny_model(10, 10, 3);
  const Trajectory t = control_forward(m, FaceSeries(3, std::vector<float>(test::face_count(m), 0.0f)));
  ASSERT_EQ(t.density.size(), 4u);
  for (size_t c = 0; c < m.initial_density.size(); ++c) EXPECT_EQ(t.density[3][c], m.initial_density[c]);
  const double E = control_objective(m, FaceSeries(3, std::vector<float>(test::face_count(m), 0.0f)), nullptr);
  double expect = 0;
  for (size_t c = 0; c < m.initial_density.size(); ++c)
    expect += std::pow(double(m.initial_density[c]) - m.keyframes[0].density[c], 2);
  EXPECT_NEAR(E, expect, 1e-9 * expect);
}

TEST(ControlForward, UniformFlowTranslatesPeriodicDensity) {
  // A uniform force on a periodic grid: projection keeps it (divergence-free), and
  // the upwind step moves the density's centre of mass by u*T*dt.
  ControlModel m = test::tiny_model(16, 8, 4, true);
  control_detail::ForwardOps ops(m, 1e-10);
  std::vector<Vec> f(4, Vec(ops.faces(), 0.0));
  const double u = 0.1;  // m/s after frame 1: f0 = u / dt on every u face
  for (size_t e = 0; e < ops.layout(0).count(); ++e) f[0][e] = u / m.sim.dt_s;
  control_detail::TrajectoryD t;
  control_detail::forward_d(m, ops, f, t);
  for (size_t e = 0; e < ops.layout(0).count(); ++e) EXPECT_NEAR(t.u[4][e], u, 1e-12);
  auto cx = [&](const Vec& r) {  // centre of mass along x via the circular mean
    double s = 0, c = 0;
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 16; ++i) {
        const double a = 2 * M_PI * (i + 0.5) / 16;
        s += r[i + 16 * j] * std::sin(a);
        c += r[i + 16 * j] * std::cos(a);
      }
    return std::atan2(s, c) / (2 * M_PI) * 16;
  };
  const double moved = cx(t.rho[4]) - cx(t.rho[0]);
  EXPECT_NEAR(moved, u * 4 * m.sim.dt_s / m.sim.cell_size_m, 0.05);
}

}  // namespace
}  // namespace pliant::smoke
