// Bi/trilinear sampling stencils with position derivatives, for the control model's
// semi-Lagrangian operator and its adjoint. Same conventions as mac_grid.h's
// axis_weights (clamped to the sample range when closed, wrapped when periodic); the
// derivative of a clamped coordinate is 0.
#pragma once
#include <algorithm>
#include <cmath>

#include "../mac_grid.h"

namespace pliant::smoke::control_detail {

struct AxisStencil {
  int i0, i1;
  double f;     // weight of i1
  double dfdx;  // d f / d x (0 where clamped)
};

inline AxisStencil axis_stencil(double x, int size, double offset, bool periodic) {
  double g = x - offset;
  if (periodic) {
    const double fl = std::floor(g);
    int i0 = int(fl) % size;
    if (i0 < 0) i0 += size;
    return {i0, i0 + 1 == size ? 0 : i0 + 1, g - fl, 1.0};
  }
  if (size == 1) return {0, 0, 0.0, 0.0};
  double d = 1.0;
  if (g < 0) g = 0, d = 0;
  else if (g > size - 1) g = size - 1, d = 0;
  const int i0 = std::min(int(g), size - 2);
  return {i0, i0 + 1, g - i0, d};
}

// Up to 8 sample indices and weights, plus d(weight)/d(position) per axis.
struct Stencil {
  int count = 0;
  size_t idx[8];
  double w[8];
  double dw[3][8];
};

inline void make_stencil(const FieldLayout& l, double px, double py, double pz, Stencil& s) {
  const AxisStencil ax = axis_stencil(px, l.size[0], l.offset[0], l.periodic);
  const AxisStencil ay = axis_stencil(py, l.size[1], l.offset[1], l.periodic);
  const int nz = l.dim == 3 ? 2 : 1;
  AxisStencil az{0, 0, 0.0, 0.0};
  if (l.dim == 3) az = axis_stencil(pz, l.size[2], l.offset[2], l.periodic);
  s.count = 0;
  for (int c = 0; c < nz; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const double wx = a ? ax.f : 1 - ax.f, wy = b ? ay.f : 1 - ay.f;
        const double wz = l.dim == 3 ? (c ? az.f : 1 - az.f) : 1.0;
        const double sx = a ? ax.dfdx : -ax.dfdx, sy = b ? ay.dfdx : -ay.dfdx;
        const double sz = l.dim == 3 ? (c ? az.dfdx : -az.dfdx) : 0.0;
        const int n = s.count++;
        s.idx[n] = l.index(a ? ax.i1 : ax.i0, b ? ay.i1 : ay.i0, l.dim == 3 ? (c ? az.i1 : az.i0) : 0);
        s.w[n] = wx * wy * wz;
        s.dw[0][n] = sx * wy * wz;
        s.dw[1][n] = wx * sy * wz;
        s.dw[2][n] = wx * wy * sz;
      }
}

inline double apply_stencil(const Stencil& s, const double* q) {
  double v = 0;
  for (int n = 0; n < s.count; ++n) v += s.w[n] * q[s.idx[n]];
  return v;
}

}  // namespace pliant::smoke::control_detail
