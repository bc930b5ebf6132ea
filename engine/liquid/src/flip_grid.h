// Internal: the MAC grid of the FLIP solver and its per-substep scratch.
// Cells (i,j,k) are numbered i + nx (j + ny k); face arrays are staggered:
// u has (nx+1) ny nz entries, v nx (ny+1) nz, w nx ny (nz+1) (3D only).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "pliant/liquid/liquid.h"

namespace pliant::liquid {

struct FlipGrid {
  int dim = 2;
  int nx = 1, ny = 1, nz = 1;
  double h = 0.02;
  Vec3 lo{0, 0, 0};
  int cells() const { return nx * ny * nz; }
  int cell(int i, int j, int k) const { return i + nx * (j + ny * k); }
  // Face array dimensions of component c (0 = u, 1 = v, 2 = w).
  std::array<int, 3> face_dims(int c) const {
    return {nx + (c == 0), ny + (c == 1), nz + (c == 2)};
  }
  int faces(int c) const { auto d = face_dims(c); return d[0] * d[1] * d[2]; }
  // World position of face (i,j,k) of component c; z = 0 in 2D.
  Vec3 face_pos(int c, int i, int j, int k) const {
    return {lo[0] + (i + (c == 0 ? 0.0 : 0.5)) * h, lo[1] + (j + (c == 1 ? 0.0 : 0.5)) * h,
            dim == 3 ? lo[2] + (k + (c == 2 ? 0.0 : 0.5)) * h : 0.0};
  }
  Vec3 cell_pos(int i, int j, int k) const {
    return {lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, dim == 3 ? lo[2] + (k + 0.5) * h : 0.0};
  }
};

FlipGrid model_grid(const LiquidModel& m);

// Small grids run single-threaded: an OpenMP region costs more than it saves
// there (and much more on a loaded machine).
inline bool worth_threads(long long work) { return work > 16384; }
// Loops doing a few flops per element are memory-bound: a second thread buys
// little and a barrier costs much on a shared machine; thread only huge ones.
inline bool worth_threads_light(long long work) { return work > (1 << 20); }

// Per-substep scratch, reused between substeps (no allocation in the loop once warm).
struct FlipWorkspace {
  std::array<std::vector<float>, 3> vel, vel_old, weight, open, solid_vel;
  std::array<std::vector<float>, 3> static_phi;  // target (and nothing else) at faces
  std::vector<float> static_phi_cell;
  std::array<std::vector<unsigned char>, 3> valid, valid_tmp;
  std::vector<float> phi_liquid;        // per cell
  std::vector<unsigned char> fluid;     // per cell
  std::vector<unsigned char> solid_cell;  // per cell: centre inside a wall
  std::vector<int> cell_start, cell_fill, order;  // counting sort of particles by cell
  std::vector<int> particle_cell;
  std::vector<double> rhs, p, adiag;               // per cell
  std::array<std::vector<double>, 3> aplus;
  // Compacted pressure system (one row per fluid cell, pressure.cpp).
  std::vector<int> row_of, cell_of, nbr;
  std::vector<double> off, cdiag, cp, cr, cz, cs, cq, cAs, precon;
  std::vector<double> vx, vb, vr, vz, vs, vq, vdiag;  // viscosity solve
  std::array<std::vector<double>, 3> vplus;
  std::vector<int> vindex, vrows, vrow_of, vnbr;  // viscosity: face kinds, compacted rows
  std::array<std::vector<int>, 3> front, front_next;  // extrapolation band per component
  std::array<std::vector<float>, 3> front_value;
  bool static_ready = false;
  bool solids_fixed = false;  // no source, static target: open/solid_vel/solid_cell computed once
};

// Where a position falls on the staggered grid, per axis, for both kinds of
// sample: kind 0 on faces normal to that axis (offset 0), kind 1 at cell
// centres (offset 1/2). Computed once per particle and shared by the dim face
// components (component c uses kind 0 on axis c, kind 1 on the others).
struct GridSamples {
  int i[2][3];
  float t[2][3];
};

// Float copy of the grid mapping, made once per loop.
struct GridMap {
  float lo[3], ih;
  int hi[2][3];  // largest base index per kind and axis
  int dim;
  int d[3][3];   // face array dims per component
  explicit GridMap(const FlipGrid& g) : ih(float(1.0 / g.h)), dim(g.dim) {
    const int n[3] = {g.nx, g.ny, g.nz};
    for (int a = 0; a < 3; ++a) {
      lo[a] = float(g.lo[a]);
      hi[0][a] = std::max(0, n[a] - 1);  // faces: n + 1 of them
      hi[1][a] = std::max(0, n[a] - 2);  // centres: n of them
    }
    for (int c = 0; c < 3; ++c) {
      const auto fd = g.face_dims(c);
      for (int a = 0; a < 3; ++a) d[c][a] = fd[a];
    }
  }
  void samples(const float* x, GridSamples* s) const {
    for (int a = 0; a < dim; ++a) {
      const float u = (x[a] - lo[a]) * ih;
      for (int kind = 0; kind < 2; ++kind) {
        const float f = kind ? u - 0.5f : u;
        int i = int(std::floor(f));
        i = i < 0 ? 0 : i > hi[kind][a] ? hi[kind][a] : i;
        const float t = f - float(i);
        s->i[kind][a] = i;
        s->t[kind][a] = t < 0.f ? 0.f : t > 1.f ? 1.f : t;
      }
    }
    for (int a = dim; a < 3; ++a)
      for (int kind = 0; kind < 2; ++kind) s->i[kind][a] = 0, s->t[kind][a] = 0.f;
  }
};

// Tent-kernel stencil of face component c: base index, strides, weights.
struct Stencil {
  int base, sy, sz;
  float t[3];
};

inline Stencil stencil_of(const GridMap& m, const GridSamples& s, int c) {
  Stencil st;
  int i0[3];
  for (int a = 0; a < 3; ++a) {
    const int kind = a == c ? 0 : 1;
    i0[a] = s.i[kind][a], st.t[a] = s.t[kind][a];
  }
  st.sy = m.d[c][0];
  st.sz = m.d[c][0] * m.d[c][1];
  st.base = i0[0] + st.sy * i0[1] + st.sz * i0[2];
  return st;
}

// Trilinear (bilinear in 2D) value of a face field at the stencil.
inline float sample(int dim, const Stencil& s, const float* field) {
  const float* p = field + s.base;
  const float* t = s.t;
  const float a00 = p[0] + t[0] * (p[1] - p[0]);
  const float a10 = p[s.sy] + t[0] * (p[s.sy + 1] - p[s.sy]);
  const float b0 = a00 + t[1] * (a10 - a00);
  if (dim == 2) return b0;
  const float a01 = p[s.sz] + t[0] * (p[s.sz + 1] - p[s.sz]);
  const float a11 = p[s.sz + s.sy] + t[0] * (p[s.sz + s.sy + 1] - p[s.sz + s.sy]);
  const float b1 = a01 + t[1] * (a11 - a01);
  return b0 + t[2] * (b1 - b0);
}

// Interpolates face component c at world position x (linear tent kernel).
float interpolate(const FlipGrid& g, int c, const float* field, const float* x);
// Two fields of the same component at x with one stencil (new and old velocity).
void interpolate_pair(const FlipGrid& g, int c, const float* a, const float* b, const float* x, float* va,
                      float* vb);

// Pressure projection with solid fractions and ghost-fluid free surface; returns
// PCG iterations.
int project_pressure(const FlipGrid& g, const LiquidModel& m, FlipWorkspace& w, double dt);
// Implicit viscosity (no-op when mu = 0); returns CG iterations.
int apply_viscosity(const FlipGrid& g, const LiquidModel& m, FlipWorkspace& w, double dt);
// Extends w.vel from faces marked valid into `layers` rings of invalid faces.
void extrapolate(const FlipGrid& g, FlipWorkspace& w, int layers);

// Velocity of the source container's wall at world x (its path's linear and
// tilt rates at time t; the pose is the source's pose at t).
Vec3 source_point_velocity(const LiquidModel& m, double t, const Pose& pose, const Vec3& x);
// Reach of a container from its origin (bounding sphere radius).
double container_reach(const ContainerShape& c);
// Face open fractions and solid velocities for the source (and a moving target)
// at time t (flip_solids.cpp).
void build_solids(const FlipGrid& g, const LiquidModel& m, FlipWorkspace& w, double t);
// Faces closed by a solid take the solid's velocity.
void set_solid_faces(const FlipGrid& g, FlipWorkspace& w);
// Moves particle x out of solids (and into the domain), removing the inward
// relative normal velocity v.
void push_out(const FlipGrid& g, const LiquidModel& m, const Pose& pose, const Pose& tpose, double t, float* x,
              float* v);

// Signed distance to all solids at world x (negative inside), the source at
// `source_pose`, the target at `target_pose`; *source_closest tells whether the
// source wall is the nearest (else the target's, moving at target_velocity_mps).
double solid_sdf(const LiquidModel& m, const Pose& source_pose, const Pose& target_pose, const Vec3& x,
                 bool* source_closest);

}  // namespace pliant::liquid
