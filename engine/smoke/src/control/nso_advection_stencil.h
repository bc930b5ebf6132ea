// Picard linearisation of the velocity self-advection used by control_forward:
// semi-Lagrangian, RK2-midpoint backtrace through a frozen velocity zbar, then
// bilinear/trilinear sampling of each component (advection.h). With the
// backtrace frozen, A(zbar, z) is linear in z: row psi of A has 2^dim weights on
// samples of the same component, so A, A^T and the entries of A^T A that SCGS
// needs are cheap stencil operations. A(zbar, zbar) reproduces
// advect_semi_lagrangian_velocity(zbar) (same float backtrace).
#pragma once
#include <cstdint>
#include <vector>

#include "spacetime_multigrid_transfer.h"

namespace pliant::smoke {

struct SlStencil {
  int K = 4;                      // samples per row (2^dim)
  std::vector<int32_t> idx;       // faces*K source faces (frame-local face index)
  std::vector<float> wt;          // faces*K weights (0 on closed walls)
  std::vector<double> ata_diag;   // (A^T A)[phi, phi]
  std::vector<double> ata_hi;     // (A^T A)[phi, hi partner of phi] (see face_hi_partner)
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
// A[row, col], 0 when col is not in row's stencil.
inline double sl_entry(const SlStencil& s, size_t row, size_t col) {
  double v = 0;
  for (int k = 0; k < s.K; ++k)
    if (size_t(s.idx[row * s.K + k]) == col) v += s.wt[row * s.K + k];
  return v;
}

}  // namespace pliant::smoke
