#include "nso_advection_stencil.h"

#include <algorithm>
#include <array>

#include "control_sampling.h"

namespace pliant::smoke {

namespace {
std::array<int, 3> face_coords(const FieldLayout& l, size_t e) {
  const size_t sx = l.size[0], sy = l.size[1];
  return {int(e % sx), int((e / sx) % sy), int(e / (sx * sy))};
}

// Euler backtrace of the control model's A_sl (control_notes.md / control_forward_model.h):
// x_b = x - (dt/h) U(x), U interpolated from the double-precision zbar.
inline std::array<double, 3> backtrace(const SpacetimeGrid& sg, const double* zbar, double dt_h,
                                       std::array<double, 3> p) {
  std::array<double, 3> out = p;
  for (int b = 0; b < sg.g.dim; ++b) {
    control_detail::Stencil st;
    control_detail::make_stencil(sg.g.face_layout(b), p[0], p[1], p[2], st);
    out[b] -= dt_h * control_detail::apply_stencil(st, zbar + sg.off[b]);
  }
  return out;
}
}  // namespace

bool is_wall_face(const SpacetimeGrid& sg, size_t phi) {
  if (sg.g.periodic) return false;
  const int a = face_axis(sg, phi);
  const FieldLayout l = sg.g.face_layout(a);
  const auto c = face_coords(l, phi - sg.off[a]);
  return c[a] == 0 || c[a] == sg.g.n[a];
}

int64_t face_hi_partner(const SpacetimeGrid& sg, size_t phi) {
  const int a = face_axis(sg, phi);
  const FieldLayout l = sg.g.face_layout(a);
  const auto c = face_coords(l, phi - sg.off[a]);
  if (c[a] >= sg.g.n[a]) return -1;
  return int64_t(sg.off[a] + sg.g.face_hi(a, c[0], c[1], c[2]));
}

void build_sl_stencil(const SpacetimeGrid& sg, const double* zbar, double dt, SlStencil& out) {
  const MacGrid& g = sg.g;
  const size_t F = sg.faces();
  const int K = g.dim == 3 ? 8 : 4;
  out.K = K;
  out.idx.assign(F * K, 0);
  out.wt.assign(F * K, 0.0f);
  out.ata_diag.assign(F, 0.0);
  out.ata_hi.assign(F, 0.0);
  const double dt_h = dt / g.h;
  for (int a = 0; a < g.dim; ++a) {
    const FieldLayout l = g.face_layout(a);
#pragma omp parallel for collapse(2) schedule(static) if (l.count() > kSpacetimeOmpMinWork)
    for (int k = 0; k < l.size[2]; ++k)
      for (int j = 0; j < l.size[1]; ++j)
        for (int i = 0; i < l.size[0]; ++i) {
          const size_t row = sg.off[a] + l.index(i, j, k);
          int32_t* id = &out.idx[row * K];
          float* w = &out.wt[row * K];
          for (int m = 0; m < K; ++m) id[m] = int32_t(row);
          const int ia = a == 0 ? i : (a == 1 ? j : k);
          if (!g.periodic && (ia == 0 || ia == g.n[a])) continue;  // wall: row of zeros
          const auto p = backtrace(sg, zbar, dt_h, {i + l.offset[0], j + l.offset[1], k + l.offset[2]});
          const AxisWeights wx = axis_weights(p[0], l.size[0], l.offset[0], l.periodic);
          const AxisWeights wy = axis_weights(p[1], l.size[1], l.offset[1], l.periodic);
          AxisWeights wz{0, 0, 0.0};
          if (g.dim == 3) wz = axis_weights(p[2], l.size[2], l.offset[2], l.periodic);
          const int xi[2] = {wx.i0, wx.i1}, yi[2] = {wy.i0, wy.i1}, zi[2] = {wz.i0, wz.i1};
          const double xw[2] = {1 - wx.f, wx.f}, yw[2] = {1 - wy.f, wy.f}, zw[2] = {1 - wz.f, wz.f};
          int m = 0;
          for (int c = 0; c < (g.dim == 3 ? 2 : 1); ++c)
            for (int b = 0; b < 2; ++b)
              for (int aa = 0; aa < 2; ++aa, ++m) {
                id[m] = int32_t(sg.off[a] + l.index(xi[aa], yi[b], zi[c]));
                w[m] = float(xw[aa] * yw[b] * (g.dim == 3 ? zw[c] : 1.0));
              }
          // Merge repeated samples (size-1 axes) so entries are unique per row.
          for (int m1 = 0; m1 < K; ++m1)
            for (int m2 = m1 + 1; m2 < K; ++m2)
              if (id[m2] == id[m1] && w[m2] != 0.0f) {
                w[m1] += w[m2];
                w[m2] = 0.0f;
              }
        }
  }
  // A^T A entries SCGS needs: the diagonal and the (lo, hi) pair of each cell.
  for (size_t row = 0; row < F; ++row) {
    const int32_t* id = &out.idx[row * K];
    const float* w = &out.wt[row * K];
    for (int m1 = 0; m1 < K; ++m1) {
      if (w[m1] == 0.0f) continue;
      out.ata_diag[id[m1]] += double(w[m1]) * w[m1];
      const int64_t hi = face_hi_partner(sg, size_t(id[m1]));
      if (hi < 0) continue;
      for (int m2 = 0; m2 < K; ++m2)
        if (m2 != m1 && id[m2] == hi) out.ata_hi[id[m1]] += double(w[m1]) * w[m2];
    }
  }
}

void sl_apply(const SpacetimeGrid& sg, const SlStencil& s, const double* x, double* y) {
  const size_t F = sg.faces();
  const int K = s.K;
  for (size_t row = 0; row < F; ++row) {
    double acc = 0;
    for (int m = 0; m < K; ++m) acc += double(s.wt[row * K + m]) * x[s.idx[row * K + m]];
    y[row] = acc;
  }
}

void sl_apply_transpose_add(const SpacetimeGrid& sg, const SlStencil& s, double alpha, const double* x,
                            double* y) {
  const size_t F = sg.faces();
  const int K = s.K;
  for (size_t row = 0; row < F; ++row) {
    const double v = alpha * x[row];
    if (v == 0.0) continue;
    for (int m = 0; m < K; ++m) y[s.idx[row * K + m]] += double(s.wt[row * K + m]) * v;
  }
}

}  // namespace pliant::smoke
