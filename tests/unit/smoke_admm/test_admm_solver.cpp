// ADMM keyframe control end to end on the shipped circle-to-square scene (32^2 x 20),
// and the pieces it is built from against the control model's own operators.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "admm_solver.h"
#include "ao_solver.h"
#include "control_forward_model.h"
#include "nso_advection_stencil.h"
#include "nso_solver.h"
#include "pliant/core/scene.h"

namespace pliant::smoke {
namespace {

using control_detail::Vec;

ControlModel circle_to_square() {
  return control_compile(load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json"));
}

// A random smooth-ish velocity series (T frames) on the model's grid.
std::vector<Vec> random_velocity(control_detail::ForwardOps& ops, int T, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0, scale);
  std::vector<Vec> u(T, Vec(ops.faces()));
  for (auto& v : u) {
    for (double& x : v) x = N(rng);
    ops.mask(v);
  }
  return u;
}

TEST(AdmmPieces, PicardStencilReproducesTheForwardSelfAdvection) {
  const ControlModel m = circle_to_square();
  control_detail::ForwardOps ops(m, 1e-10);
  const auto z = random_velocity(ops, 1, 0.3, 5);
  const SpacetimeGrid sg(ops.grid(), 1);
  SlStencil s;
  std::vector<float> scratch(sg.faces());
  build_sl_stencil(sg, z[0].data(), ops.dt(), scratch.data(), s);
  Vec a(ops.faces()), b(ops.faces());
  sl_apply(sg, s, z[0].data(), a.data());
  ops.advect_velocity(z[0], b);
  // Weights are stored as float: agreement to float precision.
  for (size_t f = 0; f < a.size(); ++f) ASSERT_NEAR(a[f], b[f], 1e-6 * 0.3 * 5) << "face " << f;
}

TEST(AdmmPieces, AoGradientMatchesFiniteDifferences) {
  const ControlModel m = circle_to_square();
  control_detail::ForwardOps ops(m, 1e-10);
  const int T = m.sim.frames;
  auto u = random_velocity(ops, T, 0.05, 1), c = random_velocity(ops, T, 0.05, 2);
  AoSolver ao(m, ops);
  std::vector<Vec> g(T, Vec(ops.faces()));
  ao.evaluate(u, c, 0.7, &g);
  std::mt19937 rng(3);
  for (int probe = 0; probe < 6; ++probe) {
    const int t = int(rng() % T);
    size_t f = rng() % ops.faces();
    while (std::abs(g[t][f]) < 1e-6) f = rng() % ops.faces();
    const double h = 1e-6, u0 = u[t][f];
    u[t][f] = u0 + h;
    const double jp = ao.evaluate(u, c, 0.7, nullptr);
    u[t][f] = u0 - h;
    const double jm = ao.evaluate(u, c, 0.7, nullptr);
    u[t][f] = u0;
    const double fd = (jp - jm) / (2 * h);
    EXPECT_NEAR(g[t][f], fd, 1e-5 * std::max(1.0, std::abs(fd))) << "frame " << t << " face " << f;
  }
}

TEST(AdmmPieces, NsoLevenbergMarquardtDecreasesItsEnergy) {
  ControlModel m = circle_to_square();
  m.r = 1e-2;  // strong coupling in time
  control_detail::ForwardOps ops(m, 1e-10);
  const int T = m.sim.frames;
  auto d = random_velocity(ops, T, 0.1, 9);
  std::vector<Vec> z(T, Vec(ops.faces(), 0.0));
  NsoSolver nso(m, ops);
  const NsoStats st = nso.solve(z, d, 1.0, 4, 2);
  EXPECT_LT(st.e_after, st.e_before);
  ASSERT_FALSE(st.vcycle_factors.empty());
  double reduction = 1;
  for (double f : st.vcycle_factors) reduction *= f;
  EXPECT_LT(reduction, 0.05);
  // z is divergence-free to the multigrid's accuracy.
  double dmax = 0, umax = 0;
  for (const auto& zt : z) {
    dmax = std::max(dmax, ops.max_divergence(zt));
    for (double v : zt) umax = std::max(umax, std::abs(v));
  }
  EXPECT_LT(dmax * ops.grid().h, 1e-2 * umax);
}

TEST(Admm, DecreasesTheObjectiveAndReachesIoU09OnCircleToSquare) {
  ControlModel m = circle_to_square();
  m.progressive_preview = false;
  m.max_iterations = 12;
  ControlState s = control_init(m);
  Progress progress;
  std::vector<AdmmIterationStats> stats;
  admm_run(m, s, progress, {}, &stats);
  ASSERT_GE(stats.size(), 3u);
  for (size_t i = 0; i < stats.size(); ++i)
    std::printf("iter %zu E %.5g primal %.3g dual %.3g ao %.3fs nso %.3fs vcycle %.3f\n", i, stats[i].objective,
                stats[i].primal, stats[i].dual, stats[i].ao_s, stats[i].nso_s,
                stats[i].vcycle_factors.empty() ? 0.0 : stats[i].vcycle_factors.back());
  const double e0 = control_objective(m, FaceSeries(m.sim.frames, std::vector<float>(s.force[0].size(), 0.0f)), nullptr);
  EXPECT_LT(s.objective_history.back(), 0.2 * e0);
  EXPECT_LT(s.objective_history.back(), s.objective_history.front());
  const ControlMetrics cm = control_evaluate(m, s.force);
  std::printf("iou_min %.3f rel_l2 %.3f\n", cm.iou_min, cm.keyframes.empty() ? -1.0 : cm.keyframes[0].relative_l2);
  EXPECT_GE(cm.iou_min, 0.9);
}

}  // namespace
}  // namespace pliant::smoke
