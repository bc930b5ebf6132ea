// The discrete adjoint of control_forward against central finite differences of
// the same double-precision forward model (issue 3: relative error < 1e-5).
#include <gtest/gtest.h>

#include <omp.h>

#include <atomic>
#include <cstddef>
#include <cstring>
#include <random>

#include "control/control_forward_model.h"
#include "control_test_util.h"
#include "../malloc_counter.h"

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

// A ForwardOps reused across evaluations (as the L-BFGS polish uses it, with its
// buffers kept) gives the same objective and gradient bits as a fresh one: nothing of
// an earlier evaluation leaks into the next (sub-step pool, adjoint accumulators).
TEST(ControlAdjoint, ReusedWorkspaceGivesTheFreshGradient) {
  for (const bool periodic : {false, true}) {
    const ControlModel m = test::tiny_model(16, 16, 6, periodic);
    control_detail::ForwardOps reused(m, control_detail::kControlPressureTolerance);
    const std::vector<Vec> a = random_forces(m, reused.faces(), 8.0, 5), b = random_forces(m, reused.faces(), 0.5, 6);
    std::vector<Vec> g_reused, g_fresh;
    control_detail::objective_d(m, reused, a, &g_reused);  // larger forces: more sub-steps
    const double e_reused = control_detail::objective_d(m, reused, b, &g_reused);
    control_detail::ForwardOps fresh(m, control_detail::kControlPressureTolerance);
    const double e_fresh = control_detail::objective_d(m, fresh, b, &g_fresh);
    EXPECT_EQ(e_reused, e_fresh) << "periodic " << periodic;
    ASSERT_EQ(g_reused.size(), g_fresh.size());
    for (size_t i = 0; i < g_fresh.size(); ++i)
      for (size_t e = 0; e < g_fresh[i].size(); ++e)
        ASSERT_EQ(g_reused[i][e], g_fresh[i][e]) << "periodic " << periodic << " frame " << i << " face " << e;
  }
}

// Evaluations 2 and 3 of objective + gradient on one ForwardOps (as the L-BFGS polish
// calls it) allocate nothing: trajectory, adjoint vectors, sub-step states and the
// scatter chunks live in ForwardOps. The first evaluation runs at larger forces so it
// sees at least as many density sub-steps as the later ones (that pool only grows).
long allocations_of_evaluations_2_and_3(const ControlModel& m) {
  control_detail::ForwardOps ops(m, control_detail::kControlPressureTolerance);
  const std::vector<Vec> f = random_forces(m, ops.faces(), 8.0, 31);
  std::vector<Vec> big = f, small = f, g;
  for (size_t i = 0; i < f.size(); ++i)
    for (size_t e = 0; e < f[i].size(); ++e) big[i][e] *= 2.0, small[i][e] *= 0.5;
  control_detail::objective_d(m, ops, big, &g);
  double e2 = 0, e3 = 0;
  const long n = pliant::test::count_allocations([&] {
    e2 = control_detail::objective_d(m, ops, f, &g);
    e3 = control_detail::objective_d(m, ops, small, &g);
  });
  EXPECT_NE(e2, e3);
  return n;
}

TEST(ControlAdjoint, SecondAndThirdEvaluationsAllocateNothing) {
  const long n2 = allocations_of_evaluations_2_and_3(test::tiny_model(16, 12, 5));
  ControlModel m = test::tiny_model(6, 6, 3);  // 3D, with an obstacle
  m.sim.dim = 3;
  m.sim.n = {6, 6, 5};
  m.initial_density.assign(180, 0.0f);
  m.initial_density[2 + 6 * (2 + 6 * 2)] = 1.0f;
  m.keyframes[0].density.assign(180, 0.0f);
  m.keyframes[0].density[3 + 6 * (3 + 6 * 2)] = 1.0f;
  m.solid.assign(180, 0);
  m.solid[4 + 6 * (1 + 6 * 1)] = 1;
  const long n3 = allocations_of_evaluations_2_and_3(m);
#ifdef PLIANT_MALLOC_COUNT
  EXPECT_EQ(n2, 0);
  EXPECT_EQ(n3, 0);
#else
  (void)n2, (void)n3;
#endif
}

// The parts of an evaluation that run in parallel give the same bits on 1 and 2
// threads: the self-advection adjoint scatters into fixed chunks (no float atomics)
// and the projection's CG sums in a fixed order (no OpenMP reductions). 256^2 cells:
// above the 16384-face thresholds of their loops. (Whole evaluations of 48^3 x 40:
// bench_smoke_control --evaluations prints "bits" per thread count.)
TEST(ControlAdjoint, ParallelPartsGiveTheSameBitsOnOneAndTwoThreads) {
  const ControlModel m = test::tiny_model(256, 256, 2);
  control_detail::ForwardOps ops(m, 1e-4);  // the tolerance does not matter here; time does
  const size_t nf = ops.faces();
  const std::vector<Vec> r = random_forces(m, nf, 1.0, 21);  // two random face fields
  const int before = omp_get_max_threads();
  std::vector<Vec> adjoint(2, Vec(nf, 0.0)), projected(2, r[1]);
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    ops.advect_velocity_adjoint(r[0], r[1], adjoint[size_t(t - 1)]);
    ops.project(projected[size_t(t - 1)]);
  }
  omp_set_num_threads(before);
  size_t differ = 0;
  double amax = 0;
  for (size_t e = 0; e < nf; ++e) {
    differ += std::memcmp(&adjoint[0][e], &adjoint[1][e], sizeof(double)) != 0;
    differ += std::memcmp(&projected[0][e], &projected[1][e], sizeof(double)) != 0;
    amax = std::max(amax, std::abs(adjoint[0][e]));
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(amax, 0.0);
  EXPECT_LT(ops.max_divergence(projected[0]), 0.01 * ops.max_divergence(r[1]));
}

}  // namespace
}  // namespace pliant::smoke
