// Internal: the MAC grid of the FLIP solver and its per-substep scratch.
// Cells (i,j,k) are numbered i + nx (j + ny k); face arrays are staggered:
// u has (nx+1) ny nz entries, v nx (ny+1) nz, w nx ny (nz+1) (3D only).
#pragma once
#include <array>
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
  std::vector<double> rhs, p, r, z, s, q, precon, adiag;
  std::array<std::vector<double>, 3> aplus;
  std::vector<double> vx, vb, vr, vz, vs, vq, vdiag;  // viscosity solve
  std::array<std::vector<double>, 3> vplus;
  std::vector<int> vindex;
  std::vector<int> front, front_next;  // extrapolation band
  std::vector<float> front_value;
  bool static_ready = false;
};

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

// Signed distance to all solids at world x (negative inside), the source at
// `source_pose`, the target at `target_pose`; *source_closest tells whether the
// source wall is the nearest (else the target's, moving at target_velocity_mps).
double solid_sdf(const LiquidModel& m, const Pose& source_pose, const Pose& target_pose, const Vec3& x,
                 bool* source_closest);

}  // namespace pliant::liquid
