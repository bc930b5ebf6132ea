// Small control problems built directly (no scene file) for the unit tests.
#pragma once
#include <cmath>
#include <random>

#include "pliant/smoke/control.h"

namespace pliant::smoke::test {

// nx x ny closed (or periodic) grid, T frames, a disc of density as rho_0 and a
// square keyframe at frame T.
inline ControlModel tiny_model(int nx, int ny, int T, bool periodic = false) {
  ControlModel m;
  m.sim.dim = 2;
  m.sim.n = {nx, ny, 1};
  m.sim.cell_size_m = 0.01;
  m.sim.dt_s = 0.02;
  m.sim.frames = T;
  m.sim.boundary = periodic ? Boundary::Periodic : Boundary::Closed;
  const size_t cells = size_t(nx) * ny;
  m.initial_density.assign(cells, 0.0f);
  Keyframe k;
  k.frame = T;
  k.weight = 1.0;
  k.density.assign(cells, 0.0f);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5) / nx, y = (j + 0.5) / ny;
      const double d = std::hypot(x - 0.35, y - 0.4);
      m.initial_density[i + size_t(nx) * j] = float(std::clamp(4.0 * (0.25 - d), 0.0, 1.0));
      if (std::abs(x - 0.6) < 0.2 && std::abs(y - 0.55) < 0.2) k.density[i + size_t(nx) * j] = 1.0f;
    }
  k.source = "box";
  m.keyframes.push_back(k);
  m.r = 1e-3;
  return m;
}

inline size_t face_count(const ControlModel& m) {
  const bool p = m.sim.boundary == Boundary::Periodic;
  size_t n = 0;
  for (int a = 0; a < m.sim.dim; ++a) {
    size_t c = 1;
    for (int b = 0; b < m.sim.dim; ++b) c *= size_t(m.sim.n[b] + (b == a && !p ? 1 : 0));
    n += c;
  }
  return n;
}

}  // namespace pliant::smoke::test
