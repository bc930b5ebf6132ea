// Implicit viscosity: one very long backward-Euler step reaches the steady
// Couette profile between a still floor and a moving lid (linear in height).
#include <gtest/gtest.h>

#include "flip_grid.h"

namespace pliant::liquid {
namespace {

TEST(Viscosity, LongStepGivesCouetteProfile) {
  FlipGrid g;
  g.dim = 2, g.nx = 40, g.ny = 10, g.nz = 1, g.h = 0.01;  // wide: the side walls do not reach the middle
  LiquidModel m;
  m.viscosity_pa_s = 1.0;
  FlipWorkspace w;
  for (int c = 0; c < 2; ++c) {
    w.vel[c].assign(g.faces(c), 0.f);
    w.open[c].assign(g.faces(c), 1.f);
    w.solid_vel[c].assign(g.faces(c), 0.f);
  }
  w.fluid.assign(g.cells(), 1);
  const int nu = g.nx + 1;
  const float U = 0.5f;
  for (int i = 1; i < nu - 1; ++i) {  // the top row of u faces is the moving lid
    const int f = i + nu * (g.ny - 1);
    w.open[0][f] = 0, w.solid_vel[0][f] = U;
  }
  for (int i : {0, g.nx}) {  // side walls: normal faces closed
    for (int j = 0; j < g.ny; ++j) w.open[0][i + nu * j] = 0;
  }
  const int iters = apply_viscosity(g, m, w, 1e3);  // alpha = 1e4: steady state
  EXPECT_GT(iters, 0);
  // Dirichlet 0 at the ghost row below (j = -1), U at the lid row (j = ny - 1).
  for (int j = 0; j + 1 < g.ny; ++j)
    for (int i = 18; i <= 22; ++i) EXPECT_NEAR(w.vel[0][i + nu * j], U * (j + 1) / g.ny, 2e-3) << i << "," << j;
}

TEST(Viscosity, ZeroViscosityIsANoOp) {
  FlipGrid g;
  g.dim = 2, g.nx = 4, g.ny = 4;
  LiquidModel m;
  FlipWorkspace w;
  w.vel[0].assign(g.faces(0), 1.f);
  EXPECT_EQ(apply_viscosity(g, m, w, 0.01), 0);
  EXPECT_EQ(w.vel[0][3], 1.f);
}

}  // namespace
}  // namespace pliant::liquid
