#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "pliant/smoke/smoke.h"
#include "forces.h"
#include "smoke_test_util.h"
#include "smoke_workspace.h"

// Counts heap allocations while `g_count_allocations` is set (this test binary
// replaces the global operator new; everything else behaves as usual).
static std::atomic<bool> g_count_allocations{false};
static std::atomic<long> g_allocations{0};
void* operator new(std::size_t n) {
  if (g_count_allocations.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The nothrow form too (std::stable_sort's buffer): it is freed by the delete above,
// so it must come from malloc as well (ASan reports new/free mismatches).
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (g_count_allocations.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace pliant::smoke {
namespace {

SmokeModel small_model(int dim, Boundary b) {
  SmokeModel m;
  m.dim = dim;
  m.n = dim == 2 ? std::array<int, 3>{32, 24, 1} : std::array<int, 3>{12, 16, 10};
  m.cell_size_m = 0.02;
  m.boundary = b;
  m.dt_s = 0.02;
  m.buoyancy_m_per_s2 = 0;
  return m;
}

bool all_zero(const std::vector<float>& a) {
  for (float x : a)
    if (x != 0.0f) return false;
  return true;
}

// A fluid at rest with no forces stays exactly at rest; so does a dense blob with
// buoyancy and gravity off.
TEST(SmokeStep, QuiescentFluidStaysAtRest) {
  for (int dim : {2, 3})
    for (Boundary b : {Boundary::Closed, Boundary::Periodic})
      for (Advection adv : {Advection::SemiLagrangian, Advection::Upwind}) {
        SmokeModel m = small_model(dim, b);
        m.advection = adv;
        SmokeState s = smoke_init(m);
        for (int f = 0; f < 20; ++f) smoke_step(m, s);
        EXPECT_TRUE(all_zero(s.density) && all_zero(s.u) && all_zero(s.v) && all_zero(s.w));
        Shape blob;
        blob.center_m = {0.3, 0.2, 0.1};
        blob.radius_m = 0.1;
        m.initial_density = {blob};
        SmokeState d = smoke_init(m);
        const std::vector<float> rho0 = d.density;
        ASSERT_GT(test::sum(rho0), 10.0);
        for (int f = 0; f < 20; ++f) smoke_step(m, d);
        EXPECT_TRUE(all_zero(d.u) && all_zero(d.v) && all_zero(d.w));
        EXPECT_EQ(d.density, rho0);
        EXPECT_EQ(d.frame, 20);
        EXPECT_NEAR(d.time_s, 0.4, 1e-12);
      }
}

// Full pipeline with the conservative operator in a closed box: the density in the
// box is exactly what the source injected (nothing leaks through walls), the flow
// is divergence-free and the plume rises.
TEST(SmokeStep, UpwindPlumeConservesInjectedDensity) {
  for (int dim : {2, 3}) {
    SmokeModel m = small_model(dim, Boundary::Closed);
    m.advection = Advection::Upwind;
    m.buoyancy_m_per_s2 = 2.0;
    m.substeps = 2;
    Source src;
    src.shape.center_m = {0.12, 0.1, 0.1};
    src.shape.radius_m = 0.06;
    src.density_per_s = 5.0;
    src.velocity_m_per_s = {0.0, 0.3, 0.0};
    src.end_s = 0.2;  // active in the first 10 frames only
    m.sources = {src};
    SmokeState s = smoke_init(m);
    std::vector<float> inside(s.density.size(), 0.0f);
    fill_shape(model_grid(m), src.shape, inside.data());
    const double per_substep = test::sum(inside) * src.density_per_s * m.dt_s / m.substeps;
    StepStats st;
    for (int f = 0; f < 20; ++f) smoke_step(m, s, &st);
    EXPECT_NEAR(st.total_density / (per_substep * 10 * m.substeps), 1.0, 1e-5);
    EXPECT_NEAR(test::sum(s.density), st.total_density, 1e-6 * st.total_density);
    EXPECT_LT(st.max_divergence, 1e-3);
    EXPECT_GT(st.pressure_iterations, 0);
    for (float x : s.density) ASSERT_GE(x, 0.0f);
    double cy = 0;
    for (size_t c = 0; c < s.density.size(); ++c) cy += s.density[c] * double((c / m.n[0]) % m.n[1]);
    EXPECT_GT((cy / st.total_density + 0.5) * m.cell_size_m, 0.1 + 0.03);  // centroid rose
  }
}

// Both pressure solvers give the same simulation (second method).
TEST(SmokeStep, SolversGiveTheSameTrajectory) {
  SmokeModel m = small_model(2, Boundary::Closed);
  m.buoyancy_m_per_s2 = 3.0;
  m.pressure_tolerance = 1e-9;
  m.pressure_max_iterations = 2000;
  m.initial_density = {Shape{Shape::Box, {0.3, 0.15, 0}, {0.08, 0.05, 0}, 0}};
  ForceField vortex;
  vortex.type = ForceField::Vortex;
  vortex.center_m = {0.3, 0.3, 0};
  vortex.radius_m = 0.15;
  vortex.strength_per_s = 3;
  m.forces = {vortex};
  SmokeState a = smoke_init(m), b = a;
  SmokeModel mj = m;
  mj.pressure_solver = PressureSolver::JacobiPCG;
  StepStats sa, sb;
  for (int f = 0; f < 10; ++f) {
    smoke_step(m, a, &sa);
    smoke_step(mj, b, &sb);
  }
  double du = 0, umax = 0;
  for (size_t i = 0; i < a.v.size(); ++i) {
    du = std::max(du, double(std::abs(a.v[i] - b.v[i])));
    umax = std::max(umax, double(std::abs(a.v[i])));
  }
  EXPECT_GT(umax, 0.05);
  EXPECT_LT(du, 1e-4 * umax);
  EXPECT_LT(sa.pressure_iterations, sb.pressure_iterations);
}

// A copied state steps identically (the state is plain data; scratch lives elsewhere).
TEST(SmokeStep, CopiedStateStepsIdentically) {
  SmokeModel m = small_model(3, Boundary::Periodic);
  m.buoyancy_m_per_s2 = 1.0;
  m.initial_density = {Shape{Shape::Sphere, {0.12, 0.1, 0.1}, {0, 0, 0}, 0.06}};
  SmokeState s = smoke_init(m);
  for (int f = 0; f < 3; ++f) smoke_step(m, s);
  SmokeState copy = s;
  smoke_step(m, s);
  smoke_step(m, copy);
  EXPECT_EQ(s.u, copy.u);
  EXPECT_EQ(s.density, copy.density);
  EXPECT_GT(test::sum(s.v), 0.0);  // periodic: buoyancy adds net upward momentum
}

// Scratch lives in a per-thread workspace built on the first step: later steps of
// the same grid allocate nothing (semi-Lagrangian and upwind, both solvers).
TEST(SmokeStep, NoAllocationAfterTheFirstStep) {
  for (Advection adv : {Advection::SemiLagrangian, Advection::Upwind})
    for (PressureSolver ps : {PressureSolver::MultigridPCG, PressureSolver::JacobiPCG}) {
      SmokeModel m = small_model(3, Boundary::Closed);
      m.advection = adv;
      m.pressure_solver = ps;
      m.buoyancy_m_per_s2 = 1.0;
      Source src;
      src.shape.center_m = {0.12, 0.1, 0.1};
      src.shape.radius_m = 0.05;
      m.sources = {src};
      SmokeState s = smoke_init(m);
      StepStats st;
      smoke_step(m, s, &st);
      g_allocations = 0;
      g_count_allocations = true;
      for (int f = 0; f < 3; ++f) smoke_step(m, s, &st);
      g_count_allocations = false;
      EXPECT_EQ(g_allocations.load(), 0);
      EXPECT_GT(st.total_density, 0.0);
    }
}

}  // namespace
}  // namespace pliant::smoke
