// NsoSolver's skip rule (control/nso_solver.h, ControlModel::nso_skip_gap): the projected
// start P d is within start_gap (relative) of the NSO optimum, checked against a
// converged multigrid solve; the multigrid is skipped only below the threshold; the
// scene key is parsed and range-checked. (The multigrid itself: tests/unit/smoke_admm.)
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "control/control_forward_model.h"
#include "control/nso_solver.h"
#include "pliant/core/error.h"
#include "../smoke_admm/control_test_util.h"
#include "pliant/core/scene.h"

namespace pliant::smoke {
namespace {

using control_detail::Vec;

ControlModel circle_to_square(double r) {
  ControlModel m = control_compile(load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json"));
  m.r = r;
  return m;
}

// A smooth swirl drifting in time plus a little noise (ADMM's d = u + lambda looks so).
std::vector<Vec> smooth_velocity(control_detail::ForwardOps& ops, int T, unsigned seed) {
  std::vector<Vec> d = test::random_velocity_series(ops, T, 0.01, seed);
  const int n = ops.grid().n[0], dim = ops.grid().dim;
  for (int t = 0; t < T; ++t) {
    for (int a = 0; a < dim; ++a) {
      const FieldLayout& l = ops.layout(a);
      for (int j = 0; j < l.size[1]; ++j)
        for (int i = 0; i < l.size[0]; ++i) {
          const double x = (i + l.offset[0]) / n, y = (j + l.offset[1]) / n;
          const double s = 0.3 * std::sin(3.14159 * (x + 0.02 * t)) * std::sin(3.14159 * y);
          d[t][ops.face_offset(a) + l.index(i, j, 0)] += a == 0 ? s : -0.7 * s;
        }
    }
    ops.mask(d[t]);
  }
  return d;
}

TEST(NsoSkipGap, ProjectedStartIsWithinItsGapOfTheConvergedOptimum) {
  for (double r : {1e-3}) {  // 100x the scenes' r: a gap far from zero, so the bound has teeth
    const ControlModel m = circle_to_square(r);
    control_detail::ForwardOps ops(m, 1e-10);
    const int T = m.sim.frames;
    const auto d = smooth_velocity(ops, T, 3);
    std::vector<Vec> pd = d;
    for (auto& v : pd) ops.project(v);
    NsoSolver nso(m, ops);
    const double beta = 1.0;
    const double ep = nso.energy(pd, d, beta);
    std::vector<Vec> z(T, Vec(ops.faces(), 0.0));
    const NsoStats st = nso.solve(z, d, beta, 6, 2);  // converged: 6 V-cycles per step
    ASSERT_TRUE(st.projected_start);
    ASSERT_GT(st.start_gap, 0.0);
    ASSERT_LT(st.start_gap, 1.0);
    EXPECT_LE(st.e_after, ep * (1 + 1e-12)) << "r " << r;
    // No divergence-free z beats P d by more than the dynamics term of P d.
    EXPECT_GE(st.e_after, ep * (1 - st.start_gap) - 1e-6 * ep) << "r " << r;
    // The bound is not vacuous: the multigrid gains a real part of it.
    EXPECT_LT(st.e_after, ep * (1 - 0.05 * st.start_gap)) << "r " << r;
  }
}

TEST(NsoSkipGap, SkipsTheMultigridOnlyBelowTheThreshold) {
  const ControlModel m = circle_to_square(1e-6);
  control_detail::ForwardOps ops(m, 1e-10);
  const int T = m.sim.frames;
  const auto d = test::random_velocity_series(ops, T, 0.1, 4);
  std::vector<Vec> pd = d;
  for (auto& v : pd) ops.project(v);
  NsoSolver skip(m, ops), full(m, ops);
  std::vector<Vec> z(T, Vec(ops.faces(), 0.0)), z2 = z;
  const NsoStats s0 = full.solve(z2, d, 1.0, 2);
  ASSERT_GT(s0.start_gap, 0.0);
  skip.skip_gap = 2 * s0.start_gap;
  const NsoStats s1 = skip.solve(z, d, 1.0, 2);
  EXPECT_TRUE(s1.skipped);
  EXPECT_EQ(s1.lm_steps + s1.rejected, 0);
  EXPECT_TRUE(s1.vcycle_factors.empty());
  // The skip returns its own projection of d: equal to P d up to the pressure
  // solve's tolerance (1e-10 relative; the two solves need not match bit for bit).
  for (int t = 0; t < T; ++t)
    for (size_t f = 0; f < z[t].size(); ++f) ASSERT_NEAR(z[t][f], pd[t][f], 1e-8) << "frame " << t << " face " << f;
  EXPECT_FALSE(s0.skipped);
  EXPECT_GT(s0.lm_steps + s0.rejected, 0);
  // Just above the gap: the multigrid runs.
  NsoSolver near(m, ops);
  near.skip_gap = 0.5 * s0.start_gap;
  std::vector<Vec> z3(T, Vec(ops.faces(), 0.0));
  EXPECT_FALSE(near.solve(z3, d, 1.0, 2).skipped);
}

TEST(NsoSkipGap, SceneKeyIsParsedAndRangeChecked) {
  const std::string base = R"({"pliant": 1, "kind": "smoke",
    "grid": {"resolution": [16, 16], "cell_size_m": 0.0625}, "time": {"dt_s": 0.05, "frames": 4},
    "advection": "upwind",
    "control": {"r": 1e-5, "max_iterations": 2, "admm": {"nso_skip_gap": GAP},
      "initial_density": [{"type": "circle", "center": [0.5, 0.5], "radius": 0.2}],
      "keyframes": [{"frame": 4, "target": {"type": "circle", "center": [0.5, 0.5], "radius": 0.2}}]}})";
  auto with = [&](const std::string& gap) {
    std::string t = base;
    t.replace(t.find("GAP"), 3, gap);
    return parse_scene(t, "gap.json");
  };
  EXPECT_DOUBLE_EQ(control_compile(with("0.05")).nso_skip_gap, 0.05);
  EXPECT_THROW(control_compile(with("1.5")), InputError);
  EXPECT_THROW(control_compile(with("-0.1")), InputError);
}

}  // namespace
}  // namespace pliant::smoke
