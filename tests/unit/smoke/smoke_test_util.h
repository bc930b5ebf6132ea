// Helpers shared by the smoke unit tests: grids, random divergence-free fields.
#pragma once
#include <random>
#include <vector>

#include "mac_grid.h"
#include "pressure_projection.h"

namespace pliant::smoke::test {

inline MacGrid make_grid(int dim, std::array<int, 3> n, bool periodic, double h = 0.01) {
  MacGrid g;
  g.dim = dim;
  g.n = n;
  if (dim == 2) g.n[2] = 1;
  g.h = h;
  g.periodic = periodic;
  return g;
}

struct Velocity {
  std::vector<float> u, v, w;
  explicit Velocity(const MacGrid& g) : u(g.face_count(0)), v(g.face_count(1)), w(g.face_count(2)) {}
  FaceVelocityMut mut() { return {u.data(), v.data(), w.empty() ? nullptr : w.data()}; }
  FaceVelocity view() const { return {u.data(), v.data(), w.empty() ? nullptr : w.data()}; }
  float max_abs() const {
    float m = 0;
    for (const auto* a : {&u, &v, &w})
      for (float x : *a) m = std::max(m, std::abs(x));
    return m;
  }
};

// Random face velocity in [-amp, amp] (walls zeroed), not divergence-free.
inline Velocity random_velocity(const MacGrid& g, unsigned seed, float amp = 1.0f) {
  Velocity vel(g);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> d(-amp, amp);
  for (auto* a : {&vel.u, &vel.v, &vel.w})
    for (float& x : *a) x = d(rng);
  zero_wall_faces(g, vel.mut());
  return vel;
}

// Random velocity projected to be divergence-free (MGPCG, tight tolerance).
inline Velocity random_divergence_free(const MacGrid& g, unsigned seed, float amp = 1.0f) {
  Velocity vel = random_velocity(g, seed, amp);
  PoissonSolver solver(g);
  std::vector<double> phi(g.cells(), 0.0), rhs(g.cells());
  project(g, solver, PoissonMethod::MultigridPCG, 1e-10, 200, vel.mut(), phi.data(), rhs.data());
  return vel;
}

inline double sum(const std::vector<float>& a) {
  double s = 0;
  for (float x : a) s += x;
  return s;
}

}  // namespace pliant::smoke::test
