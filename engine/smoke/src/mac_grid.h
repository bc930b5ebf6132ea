// MAC (marker-and-cell) staggered grid, 2D and 3D (Harlow & Welch 1965).
// Cells (i,j,k) are stored x-fastest: c = i + nx*(j + ny*k); nz = 1 in 2D.
// Face velocities: component a lives on the faces normal to axis a.
//   Closed:   n_a + 1 faces along axis a; faces 0 and n_a are solid walls (u.n = 0).
//   Periodic: n_a faces along axis a; face i lies between cells i-1 (wrapped) and i.
// Positions used by the operators are in grid units (cell i spans [i, i+1]), so a
// zero velocity backtraces exactly onto sample points (no h*x/h round-off).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace pliant::smoke {

// Where the samples of one array sit: extent per axis, offset of sample 0 in grid
// units (0.5 for cell-centred axes, 0 on the staggered axis), and wrapping.
struct FieldLayout {
  std::array<int, 3> size{1, 1, 1};
  std::array<double, 3> offset{0.5, 0.5, 0.5};
  int dim = 2;
  bool periodic = false;

  size_t count() const { return size_t(size[0]) * size[1] * size[2]; }
  size_t index(int i, int j, int k) const { return i + size_t(size[0]) * (j + size_t(size[1]) * k); }
};

struct MacGrid {
  int dim = 2;
  std::array<int, 3> n{1, 1, 1};
  double h = 0.01;  // cell size, metres
  bool periodic = false;

  size_t cells() const { return size_t(n[0]) * n[1] * n[2]; }
  size_t cell(int i, int j, int k) const { return i + size_t(n[0]) * (j + size_t(n[1]) * k); }

  FieldLayout cell_layout() const {
    FieldLayout l;
    l.size = n;
    l.dim = dim;
    l.periodic = periodic;
    if (dim == 2) l.offset[2] = 0.5;
    return l;
  }
  // Faces normal to `axis`; an empty layout (count 0) for axis 2 in 2D.
  FieldLayout face_layout(int axis) const {
    FieldLayout l = cell_layout();
    if (axis >= dim) {
      l.size = {0, 0, 0};
      return l;
    }
    l.size[axis] = periodic ? n[axis] : n[axis] + 1;
    l.offset[axis] = 0.0;
    return l;
  }
  size_t face_count(int axis) const { return face_layout(axis).count(); }

  // Face normal to `axis` on the low (minus) side of cell (i,j,k).
  size_t face_lo(int axis, int i, int j, int k) const {
    const int sx = (axis == 0 && !periodic) ? n[0] + 1 : n[0];
    const int sy = (axis == 1 && !periodic) ? n[1] + 1 : n[1];
    return i + size_t(sx) * (j + size_t(sy) * k);
  }
  // Face normal to `axis` on the high (plus) side of cell (i,j,k); wraps when periodic.
  size_t face_hi(int axis, int i, int j, int k) const {
    std::array<int, 3> c{i, j, k};
    c[axis] += 1;
    if (periodic && c[axis] == n[axis]) c[axis] = 0;
    return face_lo(axis, c[0], c[1], c[2]);
  }
};

// Linear interpolation weights along one axis: sample index pair (i0, i1) and weight f
// of i1, for a grid-unit coordinate x. Closed: clamped to the sample range. Periodic:
// wrapped with period `size`.
struct AxisWeights {
  int i0, i1;
  double f;
};
inline AxisWeights axis_weights(double x, int size, double offset, bool periodic) {
  double g = x - offset;
  // NaN/Inf positions (a blown-up velocity) map to sample 0 instead of an
  // out-of-range index, so the caller's NaN check can report the frame.
  if (periodic) {
    if (!(std::abs(g) < 1e9)) g = 0.0;
    const double fl = std::floor(g);
    int i0 = int(fl);
    if (i0 < 0 || i0 >= size) {  // rare: only points that left the periodic box
      i0 %= size;
      if (i0 < 0) i0 += size;
    }
    const int i1 = (i0 + 1 == size) ? 0 : i0 + 1;
    return {i0, i1, g - fl};
  }
  if (size == 1) return {0, 0, 0.0};
  g = g >= 0.0 ? std::min(g, double(size - 1)) : 0.0;  // also NaN -> 0
  int i0 = std::min(int(g), size - 2);
  return {i0, i0 + 1, g - i0};
}

// Bilinear (2D) / trilinear (3D) sample of `q` with layout `l` at grid-unit position p.
inline double sample(const float* q, const FieldLayout& l, double px, double py, double pz) {
  const AxisWeights wx = axis_weights(px, l.size[0], l.offset[0], l.periodic);
  const AxisWeights wy = axis_weights(py, l.size[1], l.offset[1], l.periodic);
  const size_t sx = l.size[0];
  auto row = [&](size_t base) {
    const double a = q[base + wy.i0 * sx + wx.i0], b = q[base + wy.i0 * sx + wx.i1];
    const double c = q[base + wy.i1 * sx + wx.i0], d = q[base + wy.i1 * sx + wx.i1];
    const double lo = a + wx.f * (b - a), hi = c + wx.f * (d - c);
    return lo + wy.f * (hi - lo);
  };
  if (l.dim == 2) return row(0);
  const AxisWeights wz = axis_weights(pz, l.size[2], l.offset[2], l.periodic);
  const size_t slab = sx * l.size[1];
  const double lo = row(wz.i0 * slab), hi = row(wz.i1 * slab);
  return lo + wz.f * (hi - lo);
}

// The three face-velocity arrays (w may be null in 2D).
struct FaceVelocity {
  const float* u = nullptr;
  const float* v = nullptr;
  const float* w = nullptr;
};
struct FaceVelocityMut {
  float* u = nullptr;
  float* v = nullptr;
  float* w = nullptr;
  operator FaceVelocity() const { return {u, v, w}; }
};

// Velocity (m/s) at grid-unit positions, interpolated from the faces. Holds the
// face layouts so hot loops do not rebuild them per sample.
struct VelocitySampler {
  VelocitySampler(const MacGrid& g, const FaceVelocity& vel)
      : dim(g.dim), vel(vel), lu(g.face_layout(0)), lv(g.face_layout(1)), lw(g.face_layout(2)) {}
  std::array<double, 3> operator()(double px, double py, double pz) const {
    std::array<double, 3> r{0, 0, 0};
    r[0] = sample(vel.u, lu, px, py, pz);
    r[1] = sample(vel.v, lv, px, py, pz);
    if (dim == 3) r[2] = sample(vel.w, lw, px, py, pz);
    return r;
  }
  int dim;
  FaceVelocity vel;
  FieldLayout lu, lv, lw;
};

inline std::array<double, 3> sample_velocity(const MacGrid& g, const FaceVelocity& vel, double px,
                                             double py, double pz) {
  return VelocitySampler(g, vel)(px, py, pz);
}

// Divergence (1/s) of the face velocity into `div` (one value per cell).
void divergence(const MacGrid& g, const FaceVelocity& vel, double* div);
// Largest |divergence| over the cells, 1/s.
double max_abs_divergence(const MacGrid& g, const FaceVelocity& vel);
// u_face -= scale * (phi_hi - phi_lo) / h on every face that is not a closed wall.
void subtract_gradient(const MacGrid& g, const double* phi, double scale, FaceVelocityMut vel);
// Sets closed-wall normal faces to zero (no-op for periodic grids).
void zero_wall_faces(const MacGrid& g, FaceVelocityMut vel);
// Cell-centred velocity (average of the two faces per axis) into out[c*dim + a].
void cell_centred_velocity(const MacGrid& g, const FaceVelocity& vel, float* out);

}  // namespace pliant::smoke
