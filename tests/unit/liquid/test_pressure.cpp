// The projection on hand-made grids: divergence-free afterwards, and a still
// column under gravity (hydrostatic) ends at rest.
#include <gtest/gtest.h>

#include <random>

#include "flip_grid.h"

namespace pliant::liquid {
namespace {

struct GridCase {
  FlipGrid g;
  LiquidModel m;
  FlipWorkspace w;
};

// 2D n x n box, closed walls except the top; fluid in rows below `fill`.
void make(GridCase& s, int n, int fill) {
  s.g.dim = 2, s.g.nx = n, s.g.ny = n, s.g.nz = 1, s.g.h = 0.01;
  s.m.pressure_tolerance = 1e-10;
  s.m.pressure_max_iterations = 1000;
  for (int c = 0; c < 2; ++c) {
    const auto d = s.g.face_dims(c);
    s.w.vel[c].assign(s.g.faces(c), 0.f);
    s.w.open[c].assign(s.g.faces(c), 1.f);
    s.w.solid_vel[c].assign(s.g.faces(c), 0.f);
    s.w.valid[c].assign(s.g.faces(c), 0);
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const int idx[2] = {i, j};
        if (idx[c] == 0 || idx[c] == d[c] - 1) s.w.open[c][i + d[0] * j] = 0;
      }
  }
  s.w.fluid.assign(s.g.cells(), 0);
  s.w.phi_liquid.assign(s.g.cells(), float(s.g.h));
  for (int j = 0; j < fill; ++j)
    for (int i = 0; i < n; ++i) {
      s.w.fluid[s.g.cell(i, j, 0)] = 1;
      s.w.phi_liquid[s.g.cell(i, j, 0)] = -0.5f * float(s.g.h);  // surface half a cell above row fill-1
    }
}

double max_fluid_divergence(const GridCase& s) {
  double worst = 0;
  for (int j = 0; j < s.g.ny; ++j)
    for (int i = 0; i < s.g.nx; ++i) {
      if (!s.w.fluid[s.g.cell(i, j, 0)]) continue;
      const int nu = s.g.nx + 1;
      const double div = s.w.vel[0][i + 1 + nu * j] - s.w.vel[0][i + nu * j] +
                         s.w.vel[1][i + s.g.nx * (j + 1)] - s.w.vel[1][i + s.g.nx * j];
      worst = std::max(worst, std::abs(div) / s.g.h);
    }
  return worst;
}

TEST(Pressure, ProjectionLeavesFluidDivergenceFree) {
  GridCase s;
  make(s, 24, 16);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> U(-1, 1);
  for (int c = 0; c < 2; ++c)
    for (size_t f = 0; f < s.w.vel[c].size(); ++f) s.w.vel[c][f] = s.w.open[c][f] > 0 ? U(rng) : 0.f;
  const double before = max_fluid_divergence(s);
  const int it = project_pressure(s.g, s.m, s.w, 0.01);
  EXPECT_GT(it, 0);
  EXPECT_LT(it, 200);  // MIC(0) on 384 unknowns
  EXPECT_LT(max_fluid_divergence(s), 1e-6 * before);
}

TEST(Pressure, HydrostaticColumnComesToRest) {
  GridCase s;
  make(s, 16, 10);
  const float dv = -9.81f * 0.01f;  // gravity's kick over dt = 0.01 s
  for (size_t f = 0; f < s.w.vel[1].size(); ++f)
    if (s.w.open[1][f] > 0) s.w.vel[1][f] = dv;
  project_pressure(s.g, s.m, s.w, 0.01);
  float worst = 0;
  for (int j = 0; j <= 10; ++j)  // faces of the liquid rows and the surface
    for (int i = 0; i < 16; ++i) worst = std::max(worst, std::abs(s.w.vel[1][i + 16 * j]));
  EXPECT_LT(worst, 1e-5f);
  for (float u : s.w.vel[0]) EXPECT_LT(std::abs(u), 1e-5f);
}

}  // namespace
}  // namespace pliant::liquid
