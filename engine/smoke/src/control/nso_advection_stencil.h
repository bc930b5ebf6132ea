// Picard linearisation of the velocity self-advection used by control_forward:
// semi-Lagrangian, Euler backtrace through a frozen velocity zbar, then
// bilinear/trilinear sampling of each component (advection.h). With the
// backtrace frozen, A(zbar, z) is linear in z: row psi of A has 2^dim weights on
// samples of the same component, so A, A^T and the entries of A^T A that SCGS
// needs are cheap stencil operations. A(zbar, zbar) reproduces
// advect_semi_lagrangian_velocity(zbar) (same backtrace).
// Storage (memory was the 3D limit: 80 bytes per face and frame with explicit
// indices, weights and A^T A entries): per row only the low sample index and the
// fraction per axis (20 bytes); the 2^dim indices and weights are rebuilt on use
// (axis_weights' rule: i1 = i0 + 1, wrapped when periodic, i1 = i0 on size-1 axes).
#pragma once
#include <cstdint>
#include <vector>

#include "spacetime_multigrid_transfer.h"

namespace pliant::smoke {

struct SlRow {
  float f[3];         // weight of the high sample per axis
  uint16_t i0[3];     // low sample per axis (layout of the row's component)
  uint16_t wall;      // 1: closed-wall face, row of zeros
};

struct SlStencil {
  std::vector<SlRow> rows;  // one per frame-local face
};

// The face on the high side of the cell whose low face is phi (same component),
// or -1 when phi is the high wall of a closed grid.
int64_t face_hi_partner(const SpacetimeGrid& sg, size_t phi);
// Component (axis) of frame-local face index phi.
inline int face_axis(const SpacetimeGrid& sg, size_t phi) {
  return phi < sg.off[1] ? 0 : (phi < sg.off[2] ? 1 : 2);
}
// True for the wall faces of a closed grid (fixed at zero).
bool is_wall_face(const SpacetimeGrid& sg, size_t phi);

// Builds the stencil of A(zbar, .) for one frame.
void build_sl_stencil(const SpacetimeGrid& sg, const double* zbar, double dt, SlStencil& out);
// y = A x.
void sl_apply(const SpacetimeGrid& sg, const SlStencil& s, const double* x, double* y);
// y += alpha A^T x (serial scatter; callers parallelise over frames).
void sl_apply_transpose_add(const SpacetimeGrid& sg, const SlStencil& s, double alpha, const double* x,
                            double* y);
// The unique (frame-local index, weight) pairs of row `row` (at most 8); returns the count.
int sl_row_entries(const SpacetimeGrid& sg, const SlStencil& s, size_t row, int64_t* idx, double* wt);
// The entries of A^T A that SCGS needs: diag[phi] = (A^T A)[phi, phi] and
// hi[phi] = (A^T A)[phi, face_hi_partner(phi)] (overwrites both, faces values each).
void sl_ata(const SpacetimeGrid& sg, const SlStencil& s, double* diag, double* hi);
// A[row, col] for rows and columns of one component, given col's coordinates in that
// component's layout l (SCGS's local blocks: no search over the row's samples).
inline double sl_entry_at(const FieldLayout& l, int dim, const SlRow& r, const int* col) {
  if (r.wall) return 0.0;
  double w = 1.0;
  for (int b = 0; b < dim; ++b) {
    const int size = l.size[b];
    if (size == 1) continue;  // the merged sample: weight 1
    const int i0 = r.i0[b], i1 = l.periodic && i0 + 1 == size ? 0 : i0 + 1;
    const double f = r.f[b];
    w *= (col[b] == i0 ? 1.0 - f : 0.0) + (col[b] == i1 ? f : 0.0);
  }
  return w;
}
// A[row, col], 0 when col is not in row's stencil.
double sl_entry(const SpacetimeGrid& sg, const SlStencil& s, size_t row, size_t col);

}  // namespace pliant::smoke
