// The discrete adjoint of control_forward against central finite differences of
// the same double-precision forward model (issue 3: relative error < 1e-5).
#include <gtest/gtest.h>

#include <random>

#include "control/control_forward_model.h"
#include "control_test_util.h"

namespace pliant::smoke {
namespace {

using control_detail::Vec;

std::vector<Vec> random_forces(const ControlModel& m, size_t nf, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, scale);
  std::vector<Vec> f(m.sim.frames, Vec(nf));
  for (Vec& fi : f)
    for (double& x : fi) x = n(rng);
  return f;
}

// Directional derivative check: g.d vs (E(f + eps d) - E(f - eps d)) / (2 eps).
double directional_error(const ControlModel& m, unsigned seed) {
  control_detail::ForwardOps ops(m, 1e-12);
  const size_t nf = ops.faces();
  const std::vector<Vec> f = random_forces(m, nf, 8.0, seed);
  const std::vector<Vec> d = random_forces(m, nf, 1.0, seed + 100);
  std::vector<Vec> g;
  control_detail::objective_d(m, ops, f, &g);
  double gd = 0;
  for (size_t i = 0; i < f.size(); ++i)
    for (size_t e = 0; e < nf; ++e) gd += g[i][e] * d[i][e];
  const double eps = 1e-6;
  auto shifted = [&](double s) {
    std::vector<Vec> x = f;
    for (size_t i = 0; i < f.size(); ++i)
      for (size_t e = 0; e < nf; ++e) x[i][e] += s * d[i][e];
    return control_detail::objective_d(m, ops, x, nullptr);
  };
  const double fd = (shifted(eps) - shifted(-eps)) / (2 * eps);
  return std::abs(fd - gd) / std::max(std::abs(fd), 1e-300);
}

TEST(ControlAdjoint, MatchesFiniteDifferencesClosed) {
  const ControlModel m = test::tiny_model(16, 12, 5);
  EXPECT_LT(directional_error(m, 1), 1e-5);
  EXPECT_LT(directional_error(m, 2), 1e-5);
}

TEST(ControlAdjoint, MatchesFiniteDifferencesPeriodic) {
  const ControlModel m = test::tiny_model(12, 8, 4, true);
  EXPECT_LT(directional_error(m, 3), 1e-5);
}

TEST(ControlAdjoint, MatchesFiniteDifferencesWithObstacle) {
  ControlModel m = test::tiny_model(12, 10, 4);
  m.solid.assign(120, 0);
  m.solid[5 + 12 * 7] = m.solid[6 + 12 * 7] = 1;
  EXPECT_LT(directional_error(m, 4), 1e-5);
}

TEST(ControlAdjoint, MatchesFiniteDifferences3D) {
  ControlModel m = test::tiny_model(6, 6, 3);
  m.sim.dim = 3;
  m.sim.n = {6, 6, 5};
  m.initial_density.assign(180, 0.0f);
  m.initial_density[2 + 6 * (2 + 6 * 2)] = 1.0f;
  m.initial_density[3 + 6 * (2 + 6 * 2)] = 0.5f;
  m.keyframes[0].density.assign(180, 0.0f);
  m.keyframes[0].density[3 + 6 * (3 + 6 * 2)] = 1.0f;
  EXPECT_LT(directional_error(m, 5), 1e-5);
}

// Single components too (the directional test could hide cancelling errors).
TEST(ControlAdjoint, ComponentsMatchFiniteDifferences) {
  const ControlModel m = test::tiny_model(10, 10, 4);
  control_detail::ForwardOps ops(m, 1e-12);
  const size_t nf = ops.faces();
  const std::vector<Vec> f = random_forces(m, nf, 8.0, 9);
  std::vector<Vec> g;
  control_detail::objective_d(m, ops, f, &g);
  int checked = 0;
  for (int i : {0, 2, 3})
    for (size_t e : {size_t(23), size_t(57), nf - 31}) {
      if (std::abs(g[i][e]) < 1e-8) continue;
      std::vector<Vec> p = f, q = f;
      const double eps = 1e-6;
      p[i][e] += eps;
      q[i][e] -= eps;
      const double fd = (control_detail::objective_d(m, ops, p, nullptr) -
                         control_detail::objective_d(m, ops, q, nullptr)) / (2 * eps);
      EXPECT_NEAR(g[i][e], fd, 1e-5 * std::abs(fd) + 1e-9) << "frame " << i << " face " << e;
      ++checked;
    }
  EXPECT_GE(checked, 5);
}

}  // namespace
}  // namespace pliant::smoke
