#include "forces.h"

#include <cmath>

namespace pliant::smoke {
namespace {

// Calls fn(index, position_m) for every element of layout l, in parallel.
template <class Fn>
void for_each_sample(const MacGrid& g, const FieldLayout& l, Fn fn) {
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < l.size[2]; ++k)
    for (int j = 0; j < l.size[1]; ++j)
      for (int i = 0; i < l.size[0]; ++i) {
        const std::array<double, 3> x{(i + l.offset[0]) * g.h, (j + l.offset[1]) * g.h,
                                      g.dim == 3 ? (k + l.offset[2]) * g.h : 0.0};
        fn(l.index(i, j, k), std::array<int, 3>{i, j, k}, x);
      }
}

bool is_wall(const MacGrid& g, int axis, const std::array<int, 3>& ijk) {
  return !g.periodic && (ijk[axis] == 0 || ijk[axis] == g.n[axis]);
}

}  // namespace

bool shape_contains(const Shape& s, int dim, const std::array<double, 3>& x) {
  if (s.type == Shape::Sphere) {
    double d2 = 0;
    for (int a = 0; a < dim; ++a) d2 += (x[a] - s.center_m[a]) * (x[a] - s.center_m[a]);
    return d2 <= s.radius_m * s.radius_m;
  }
  for (int a = 0; a < dim; ++a)
    if (std::abs(x[a] - s.center_m[a]) > s.half_size_m[a]) return false;
  return true;
}

void add_buoyancy(const MacGrid& g, double b, const float* density, double dt, FaceVelocityMut vel) {
  if (b == 0.0) return;
  const FieldLayout l = g.face_layout(1);
  const int ny = g.n[1];
  for_each_sample(g, l, [&](size_t e, std::array<int, 3> ijk, const std::array<double, 3>&) {
    if (is_wall(g, 1, ijk)) return;
    const int j = ijk[1];
    const int jlo = j == 0 ? ny - 1 : j - 1;  // j == 0 only when periodic
    const int jhi = j == ny ? 0 : j;
    const double rho = 0.5 * (double(density[g.cell(ijk[0], jlo, ijk[2])]) +
                              density[g.cell(ijk[0], jhi, ijk[2])]);
    vel.v[e] = float(vel.v[e] + dt * b * rho);
  });
}

void add_uniform_acceleration(const MacGrid& g, const std::array<double, 3>& a, double dt,
                              FaceVelocityMut vel) {
  float* comp[3] = {vel.u, vel.v, vel.w};
  for (int ax = 0; ax < g.dim; ++ax) {
    if (a[ax] == 0.0) continue;
    for_each_sample(g, g.face_layout(ax), [&](size_t e, std::array<int, 3> ijk, const std::array<double, 3>&) {
      if (!is_wall(g, ax, ijk)) comp[ax][e] = float(comp[ax][e] + dt * a[ax]);
    });
  }
}

void add_vortex(const MacGrid& g, const ForceField& f, double dt, FaceVelocityMut vel) {
  if (f.radius_m <= 0 || f.strength_per_s == 0) return;
  // Plane of rotation: (x, y) in 2D, (z, x) in 3D (right-handed about +y).
  const int p = g.dim == 2 ? 0 : 2, q = g.dim == 2 ? 1 : 0;
  const double s2 = f.strength_per_s * std::abs(f.strength_per_s);
  float* comp[3] = {vel.u, vel.v, vel.w};
  for (int ax : {p, q}) {
    for_each_sample(g, g.face_layout(ax), [&](size_t e, std::array<int, 3> ijk, const std::array<double, 3>& x) {
      if (is_wall(g, ax, ijk)) return;
      const double rp = x[p] - f.center_m[p], rq = x[q] - f.center_m[q];
      const double d = std::sqrt(rp * rp + rq * rq);
      if (d >= f.radius_m || d == 0.0) return;
      const double mag = s2 * d * (1.0 - d / f.radius_m);
      // Tangent (-rq, rp)/d: component along p is -rq/d, along q is rp/d.
      const double t = ax == p ? -rq / d : rp / d;
      comp[ax][e] = float(comp[ax][e] + dt * mag * t);
    });
  }
}

void apply_source(const MacGrid& g, const Source& s, double dt, float* density, FaceVelocityMut vel) {
  const float add = float(s.density_per_s * dt);
  for_each_sample(g, g.cell_layout(), [&](size_t e, std::array<int, 3>, const std::array<double, 3>& x) {
    if (shape_contains(s.shape, g.dim, x)) density[e] += add;
  });
  float* comp[3] = {vel.u, vel.v, vel.w};
  for (int ax = 0; ax < g.dim; ++ax) {
    const float value = float(s.velocity_m_per_s[ax]);
    for_each_sample(g, g.face_layout(ax), [&](size_t e, std::array<int, 3> ijk, const std::array<double, 3>& x) {
      if (!is_wall(g, ax, ijk) && shape_contains(s.shape, g.dim, x)) comp[ax][e] = value;
    });
  }
}

void fill_shape(const MacGrid& g, const Shape& shape, float* density) {
  for_each_sample(g, g.cell_layout(), [&](size_t e, std::array<int, 3>, const std::array<double, 3>& x) {
    if (shape_contains(shape, g.dim, x)) density[e] = 1.0f;
  });
}

}  // namespace pliant::smoke
