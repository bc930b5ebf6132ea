#include "nso_advection_stencil.h"

#include <algorithm>
#include <array>
#include <stdexcept>

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

// The samples of one row along each axis: 1 (size-1 axis) or 2 (low, high), as
// index offsets in the component's layout and weights.
struct RowAxes {
  int n[3];
  int64_t off[3][2];
  double w[3][2];
};

inline void row_axes(const FieldLayout& l, int dim, const SlRow& r, RowAxes& ra) {
  int64_t stride = 1;
  for (int b = 0; b < 3; ++b) {
    const int size = l.size[b];
    if (b >= dim || size == 1) {
      ra.n[b] = 1, ra.off[b][0] = 0, ra.w[b][0] = 1.0;
    } else {
      const int i0 = r.i0[b], i1 = l.periodic && i0 + 1 == size ? 0 : i0 + 1;
      ra.n[b] = 2;
      ra.off[b][0] = i0 * stride, ra.off[b][1] = i1 * stride;
      ra.w[b][0] = 1.0 - double(r.f[b]), ra.w[b][1] = double(r.f[b]);
    }
    stride *= size;
  }
}

// Calls visit(sample index within the component, weight) for each unique sample.
template <class Visit>
inline void for_each_sample(const FieldLayout& l, int dim, const SlRow& r, Visit&& visit) {
  if (r.wall) return;
  RowAxes ra;
  row_axes(l, dim, r, ra);
  for (int c = 0; c < ra.n[2]; ++c)
    for (int b = 0; b < ra.n[1]; ++b)
      for (int a = 0; a < ra.n[0]; ++a)
        visit(ra.off[0][a] + ra.off[1][b] + ra.off[2][c], ra.w[0][a] * ra.w[1][b] * ra.w[2][c]);
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
  out.rows.resize(sg.faces());
  const double dt_h = dt / g.h;
  for (int a = 0; a < g.dim; ++a) {
    const FieldLayout l = g.face_layout(a);
    if (l.size[0] >= 65536 || l.size[1] >= 65536 || l.size[2] >= 65536)  // SlRow's 16-bit indices
      throw std::length_error("NSO stencil: a grid axis has 65536 or more samples");
#pragma omp parallel for collapse(2) schedule(static) if (l.count() > kSpacetimeOmpMinWork)
    for (int k = 0; k < l.size[2]; ++k)
      for (int j = 0; j < l.size[1]; ++j)
        for (int i = 0; i < l.size[0]; ++i) {
          SlRow& r = out.rows[sg.off[a] + l.index(i, j, k)];
          r = SlRow{{0, 0, 0}, {0, 0, 0}, 0};
          const int ia = a == 0 ? i : (a == 1 ? j : k);
          if (!g.periodic && (ia == 0 || ia == g.n[a])) {  // wall: row of zeros
            r.wall = 1;
            continue;
          }
          const auto p = backtrace(sg, zbar, dt_h, {i + l.offset[0], j + l.offset[1], k + l.offset[2]});
          for (int b = 0; b < g.dim; ++b) {
            const AxisWeights w = axis_weights(p[b], l.size[b], l.offset[b], l.periodic);
            r.i0[b] = uint16_t(w.i0);
            r.f[b] = float(w.f);
          }
        }
  }
}

namespace {
// Two samples per axis always (i1 = i0 on a size-1 axis: the two weights then add up
// to the merged weight), unrolled for the dimension: y = A x and y += alpha A^T x are
// linear, so unmerged duplicates give the same sums.
template <int DIM>
struct Corners {
  int64_t idx[1 << DIM];
  double w[1 << DIM];
};

template <int DIM>
inline void corners(const FieldLayout& l, const SlRow& r, Corners<DIM>& c) {
  int64_t o[3][2];
  double w[3][2];
  int64_t stride = 1;
  for (int b = 0; b < DIM; ++b) {
    const int size = l.size[b], i0 = r.i0[b];
    const int i1 = size == 1 ? i0 : (l.periodic && i0 + 1 == size ? 0 : i0 + 1);
    o[b][0] = i0 * stride, o[b][1] = i1 * stride;
    w[b][0] = 1.0 - double(r.f[b]), w[b][1] = double(r.f[b]);
    stride *= size;
  }
  if constexpr (DIM == 2) {
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) c.idx[2 * y + x] = o[0][x] + o[1][y], c.w[2 * y + x] = w[0][x] * w[1][y];
  } else {
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
          const int m = 4 * z + 2 * y + x;
          c.idx[m] = o[0][x] + o[1][y] + o[2][z];
          c.w[m] = w[0][x] * w[1][y] * w[2][z];
        }
  }
}

template <int DIM>
void apply_t(const SpacetimeGrid& sg, const SlStencil& s, const double* x, double* y) {
  for (int a = 0; a < DIM; ++a) {
    const FieldLayout l = sg.g.face_layout(a);
    const size_t o = sg.off[a], n = l.count();
    const double* xa = x + o;
    const SlRow* rows = s.rows.data() + o;
    for (size_t e = 0; e < n; ++e) {
      if (rows[e].wall) {
        y[o + e] = 0.0;
        continue;
      }
      Corners<DIM> c;
      corners<DIM>(l, rows[e], c);
      double acc = 0;
      for (int m = 0; m < (1 << DIM); ++m) acc += c.w[m] * xa[c.idx[m]];
      y[o + e] = acc;
    }
  }
}

template <int DIM>
void transpose_add_t(const SpacetimeGrid& sg, const SlStencil& s, double alpha, const double* x, double* y) {
  for (int a = 0; a < DIM; ++a) {
    const FieldLayout l = sg.g.face_layout(a);
    const size_t o = sg.off[a], n = l.count();
    double* ya = y + o;
    const SlRow* rows = s.rows.data() + o;
    for (size_t e = 0; e < n; ++e) {
      const double v = alpha * x[o + e];
      if (v == 0.0 || rows[e].wall) continue;
      Corners<DIM> c;
      corners<DIM>(l, rows[e], c);
      for (int m = 0; m < (1 << DIM); ++m) ya[c.idx[m]] += c.w[m] * v;
    }
  }
}
}  // namespace

void sl_apply(const SpacetimeGrid& sg, const SlStencil& s, const double* x, double* y) {
  if (sg.g.dim == 3) apply_t<3>(sg, s, x, y);
  else apply_t<2>(sg, s, x, y);
}

void sl_apply_transpose_add(const SpacetimeGrid& sg, const SlStencil& s, double alpha, const double* x,
                            double* y) {
  if (sg.g.dim == 3) transpose_add_t<3>(sg, s, alpha, x, y);
  else transpose_add_t<2>(sg, s, alpha, x, y);
}

void sl_ata(const SpacetimeGrid& sg, const SlStencil& s, double* diag, double* hi) {
  const MacGrid& g = sg.g;
  std::fill(diag, diag + sg.faces(), 0.0);
  std::fill(hi, hi + sg.faces(), 0.0);
  for (int a = 0; a < g.dim; ++a) {
    const FieldLayout l = g.face_layout(a);
    const size_t o = sg.off[a], n = l.count();
    double *da = diag + o, *ha = hi + o;
    for (size_t e = 0; e < n; ++e) {
      const SlRow& r = s.rows[o + e];
      if (r.wall) continue;
      RowAxes ra;
      row_axes(l, g.dim, r, ra);
      // Along the row's own axis a the sample pair (i0, i1) is (face, its hi partner):
      // i1 = i0 + 1, wrapped when periodic, exactly face_hi_partner's rule.
      const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
      for (int v = 0; v < ra.n[b2]; ++v)
        for (int u = 0; u < ra.n[b1]; ++u) {
          const double wo = ra.w[b1][u] * ra.w[b2][v];
          const int64_t base = ra.off[b1][u] + ra.off[b2][v];
          for (int p = 0; p < ra.n[a]; ++p) {
            const double wp = wo * ra.w[a][p];
            da[base + ra.off[a][p]] += wp * wp;
          }
          if (ra.n[a] == 2) ha[base + ra.off[a][0]] += wo * wo * ra.w[a][0] * ra.w[a][1];
        }
    }
  }
}

int sl_row_entries(const SpacetimeGrid& sg, const SlStencil& s, size_t row, int64_t* idx, double* wt) {
  const int a = face_axis(sg, row);
  int n = 0;
  for_each_sample(sg.g.face_layout(a), sg.g.dim, s.rows[row], [&](int64_t c, double w) {
    idx[n] = int64_t(sg.off[a]) + c;
    wt[n++] = w;
  });
  return n;
}

double sl_entry(const SpacetimeGrid& sg, const SlStencil& s, size_t row, size_t col) {
  int64_t idx[8];
  double wt[8];
  const int n = sl_row_entries(sg, s, row, idx, wt);
  double v = 0;
  for (int m = 0; m < n; ++m)
    if (size_t(idx[m]) == col) v += wt[m];
  return v;
}

}  // namespace pliant::smoke
