#include "mac_grid.h"

namespace pliant::smoke {
namespace {

// Net outflow of cell (i,j,k) in face-velocity units (divergence times h).
inline double cell_outflow(const MacGrid& g, const FaceVelocity& vel, int i, int j, int k) {
  double d = double(vel.u[g.face_hi(0, i, j, k)]) - vel.u[g.face_lo(0, i, j, k)];
  d += double(vel.v[g.face_hi(1, i, j, k)]) - vel.v[g.face_lo(1, i, j, k)];
  if (g.dim == 3) d += double(vel.w[g.face_hi(2, i, j, k)]) - vel.w[g.face_lo(2, i, j, k)];
  return d;
}

}  // namespace

void divergence(const MacGrid& g, const FaceVelocity& vel, double* div) {
  const int nx = g.n[0], ny = g.n[1], nz = g.n[2];
  const double inv_h = 1.0 / g.h;
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        div[g.cell(i, j, k)] = cell_outflow(g, vel, i, j, k) * inv_h;
      }
}

double max_abs_divergence(const MacGrid& g, const FaceVelocity& vel) {
  const int nx = g.n[0], ny = g.n[1], nz = g.n[2];
  const double inv_h = 1.0 / g.h;
  double m = 0;
#pragma omp parallel for collapse(2) schedule(static) reduction(max : m)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        m = std::max(m, std::abs(cell_outflow(g, vel, i, j, k) * inv_h));
      }
  return m;
}

void subtract_gradient(const MacGrid& g, const double* phi, double scale, FaceVelocityMut vel) {
  float* comp[3] = {vel.u, vel.v, vel.w};
  const double s = scale / g.h;
  for (int a = 0; a < g.dim; ++a) {
    const FieldLayout l = g.face_layout(a);
    float* q = comp[a];
#pragma omp parallel for collapse(2) schedule(static)
    for (int k = 0; k < l.size[2]; ++k)
      for (int j = 0; j < l.size[1]; ++j)
        for (int i = 0; i < l.size[0]; ++i) {
          std::array<int, 3> hi{i, j, k};
          const int ia = hi[a];
          if (!g.periodic && (ia == 0 || ia == g.n[a])) continue;  // wall: stays 0
          std::array<int, 3> lo = hi;
          lo[a] = (ia == 0) ? g.n[a] - 1 : ia - 1;  // periodic wrap at face 0
          const double grad = phi[g.cell(hi[0], hi[1], hi[2])] - phi[g.cell(lo[0], lo[1], lo[2])];
          float& f = q[l.index(i, j, k)];
          f = float(f - s * grad);
        }
  }
}

void zero_wall_faces(const MacGrid& g, FaceVelocityMut vel) {
  if (g.periodic) return;
  float* comp[3] = {vel.u, vel.v, vel.w};
  for (int a = 0; a < g.dim; ++a) {
    const FieldLayout l = g.face_layout(a);
    float* q = comp[a];
    for (int k = 0; k < l.size[2]; ++k)
      for (int j = 0; j < l.size[1]; ++j)
        for (int i = 0; i < l.size[0]; ++i) {
          const int ia = a == 0 ? i : (a == 1 ? j : k);
          if (ia == 0 || ia == g.n[a]) q[l.index(i, j, k)] = 0.0f;
        }
  }
}

void cell_centred_velocity(const MacGrid& g, const FaceVelocity& vel, float* out) {
  const int nx = g.n[0], ny = g.n[1], nz = g.n[2], d = g.dim;
  const float* comp[3] = {vel.u, vel.v, vel.w};
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const size_t c = g.cell(i, j, k);
        for (int a = 0; a < d; ++a)
          out[c * d + a] = 0.5f * (comp[a][g.face_lo(a, i, j, k)] + comp[a][g.face_hi(a, i, j, k)]);
      }
}

}  // namespace pliant::smoke
