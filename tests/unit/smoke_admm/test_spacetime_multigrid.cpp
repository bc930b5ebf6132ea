// FAS V-cycle of the NSO KKT system: residual reduction per cycle and its
// independence of the grid size (the point of multigrid).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "spacetime_multigrid.h"

namespace pliant::smoke {
namespace {

// A swirl (divergence-free, from a stream function) as linearisation point, CFL
// about 0.5 per frame, and a noisy target d; returns the mean residual factor of
// `cycles` V-cycles (after one warm-up cycle).
double vcycle_factor(int n, int T, double r, double beta, int cycles, bool periodic = false, int dim = 2) {
  MacGrid g;
  g.dim = dim;
  g.n = {n, n, dim == 3 ? n : 1};
  g.h = 0.64 / n;
  g.periodic = periodic;
  // Peak Courant number 0.5 per frame at every n (the swirl in cells per frame is the same).
  const double dt = 0.02, speed = 0.5 * g.h / dt;
  SpacetimeGrid sg(g, T);
  SpacetimeMultigrid mg(sg);
  mg.pre_sweeps = mg.post_sweeps = 2;  // as NsoSolver uses it
  NsoLevel& L = mg.fine();
  const size_t F = sg.faces();
  const double pi = 3.14159265358979;
  auto psi = [&](double x, double y) { return std::sin(pi * x / n) * std::sin(pi * y / n) * n / pi; };
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0, 1);
  for (int t = 0; t < T; ++t) {
    const double s = speed * (0.5 + 0.5 * t / T);
    double* z = L.zbar.data() + t * F;
    for (int a = 0; a < 2; ++a) {  // swirl in xy (uniform along z in 3D, w = 0)
      const FieldLayout l = g.face_layout(a);
      for (int k = 0; k < l.size[2]; ++k)
        for (int j = 0; j < l.size[1]; ++j)
          for (int i = 0; i < l.size[0]; ++i) {
            const double x = i + l.offset[0], y = j + l.offset[1];
            // u = d psi/dy, v = -d psi/dx (discretely divergence-free via corner psi).
            const double v = a == 0 ? psi(x, y + 0.5) - psi(x, y - 0.5) : -(psi(x + 0.5, y) - psi(x - 0.5, y));
            z[sg.off[a] + l.index(i, j, k)] = s * v;
          }
    }
    for (size_t f = 0; f < F; ++f) L.F[t * F + f] = beta * (z[f] + 0.3 * speed * N(rng));
  }
  mg.setup(dt, 2 * r / (dt * dt), beta);
  double prev = L.residual();
  double prod = 1;
  for (int c = 0; c <= cycles; ++c) {
    const double res = mg.vcycle();
    if (c > 0) prod *= res / prev;
    prev = res;
  }
  return std::pow(prod, 1.0 / cycles);
}

TEST(SpacetimeMultigrid, VcycleReducesResidualThreefold64x20) {
  const double rho = vcycle_factor(64, 20, 1e-3, 1.0, 3);
  RecordProperty("factor", std::to_string(rho));
  EXPECT_LT(rho, 1.0 / 3.0);
}

TEST(SpacetimeMultigrid, FactorDoesNotDegradeWithResolution16to64) {
  const double r16 = vcycle_factor(16, 10, 1e-3, 1.0, 3), r64 = vcycle_factor(64, 10, 1e-3, 1.0, 3);
  EXPECT_LT(r64, 1.0 / 3.0);
  EXPECT_LT(r64, 1.25 * r16 + 0.02) << "16^2: " << r16 << " 64^2: " << r64;
}

TEST(SpacetimeMultigrid, StrongTimeCouplingStillConverges) {
  // r large against beta (w = 2r/dt^2 = 5000 beta): the regime LM + FAS is for.
  EXPECT_LT(vcycle_factor(32, 10, 1.0, 1.0, 3), 0.5);
}

TEST(SpacetimeMultigrid, ConvergesIn3DAndOnPeriodicGrids) {
  EXPECT_LT(vcycle_factor(16, 4, 1e-3, 1.0, 2, false, 3), 1.0 / 3.0);
  EXPECT_LT(vcycle_factor(32, 6, 1e-3, 1.0, 2, true), 1.0 / 3.0);
}

// Label `slow` (see CMakeLists.txt): 32^2 -> 128^2 at T = 20.
TEST(SpacetimeMultigridSlow, FactorDoesNotDegradeWithResolution32to128) {
  const double r32 = vcycle_factor(32, 20, 1e-3, 1.0, 3), r128 = vcycle_factor(128, 20, 1e-3, 1.0, 3);
  EXPECT_LT(r128, 1.0 / 3.0);
  EXPECT_LT(r128, 1.25 * r32 + 0.02) << "32^2: " << r32 << " 128^2: " << r128;
}

}  // namespace
}  // namespace pliant::smoke
