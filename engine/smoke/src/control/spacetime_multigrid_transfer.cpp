#include "spacetime_multigrid_transfer.h"

#include <algorithm>

namespace pliant::smoke {

SpacetimeGrid::SpacetimeGrid(const MacGrid& grid, int frames) : g(grid), T(frames) {
  size_t o = 0;
  for (int a = 0; a < 3; ++a) {
    off[a] = o;
    o += g.face_count(a);
  }
  off[3] = o;
  for (int a = g.dim; a < 3; ++a) off[a] = o;
}

bool SpacetimeGrid::coarsenable() const {
  for (int a = 0; a < g.dim; ++a)
    if (g.n[a] % 2 || g.n[a] < 8) return false;
  return true;
}

SpacetimeGrid SpacetimeGrid::coarsened() const {
  MacGrid c = g;
  for (int a = 0; a < g.dim; ++a) c.n[a] = g.n[a] / 2;
  c.h = 2 * g.h;
  return SpacetimeGrid(c, T);
}

namespace {

// Calls visit(fine_index, coarse_index, weight) for every (fine sample, coarse
// sample) pair of the interpolation from layout lc (coarse) to lf (fine).
template <class Visit>
inline void for_each_weight(const FieldLayout& lf, const FieldLayout& lc, int i, int j, int k, Visit&& visit) {
  const AxisWeights wx = axis_weights(0.5 * (i + lf.offset[0]), lc.size[0], lc.offset[0], lc.periodic);
  const AxisWeights wy = axis_weights(0.5 * (j + lf.offset[1]), lc.size[1], lc.offset[1], lc.periodic);
  AxisWeights wz{0, 0, 0.0};
  if (lf.dim == 3) wz = axis_weights(0.5 * (k + lf.offset[2]), lc.size[2], lc.offset[2], lc.periodic);
  const size_t e = lf.index(i, j, k);
  const int xi[2] = {wx.i0, wx.i1}, yi[2] = {wy.i0, wy.i1}, zi[2] = {wz.i0, wz.i1};
  const double xw[2] = {1 - wx.f, wx.f}, yw[2] = {1 - wy.f, wy.f}, zw[2] = {1 - wz.f, wz.f};
  const int nz = lf.dim == 3 ? 2 : 1;
  for (int c = 0; c < nz; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const double w = xw[a] * yw[b] * (lf.dim == 3 ? zw[c] : 1.0);
        if (w != 0.0) visit(e, lc.index(xi[a], yi[b], zi[c]), w);
      }
}

void prolong_layout(const FieldLayout& lf, const FieldLayout& lc, const double* xc, double* xf, bool add = false) {
#pragma omp parallel for collapse(2) schedule(static) if (lf.count() > kSpacetimeOmpMinWork)
  for (int k = 0; k < lf.size[2]; ++k)
    for (int j = 0; j < lf.size[1]; ++j)
      for (int i = 0; i < lf.size[0]; ++i) {
        double acc = 0;
        for_each_weight(lf, lc, i, j, k, [&](size_t, size_t c, double w) { acc += w * xc[c]; });
        double& out = xf[lf.index(i, j, k)];
        out = add ? out + acc : acc;
      }
}

// Scatter (serial: called frame-parallel).
void restrict_layout(const FieldLayout& lf, const FieldLayout& lc, const double* xf, double* xc, double scale) {
  std::fill(xc, xc + lc.count(), 0.0);
  for (int k = 0; k < lf.size[2]; ++k)
    for (int j = 0; j < lf.size[1]; ++j)
      for (int i = 0; i < lf.size[0]; ++i)
        for_each_weight(lf, lc, i, j, k, [&](size_t e, size_t c, double w) { xc[c] += scale * w * xf[e]; });
}

double restrict_scale(const SpacetimeGrid& s) { return s.g.dim == 3 ? 0.125 : 0.25; }

}  // namespace

void prolong_faces(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf) {
  for (int a = 0; a < fine.g.dim; ++a)
    prolong_layout(fine.g.face_layout(a), coarse.g.face_layout(a), xc + coarse.off[a], xf + fine.off[a]);
}
void prolong_cells(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf) {
  prolong_layout(fine.g.cell_layout(), coarse.g.cell_layout(), xc, xf);
}
void restrict_faces(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc) {
  for (int a = 0; a < fine.g.dim; ++a)
    restrict_layout(fine.g.face_layout(a), coarse.g.face_layout(a), xf + fine.off[a], xc + coarse.off[a],
                    restrict_scale(fine));
}
void restrict_cells(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc) {
  restrict_layout(fine.g.cell_layout(), coarse.g.cell_layout(), xf, xc, restrict_scale(fine));
}

void prolong_faces_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf) {
#pragma omp parallel for schedule(static) if (fine.parallel())
  for (int t = 0; t < fine.T; ++t) prolong_faces(fine, coarse, xc + t * coarse.faces(), xf + t * fine.faces());
}
void prolong_cells_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf) {
#pragma omp parallel for schedule(static) if (fine.parallel())
  for (int t = 0; t < fine.T; ++t) prolong_cells(fine, coarse, xc + t * coarse.cells(), xf + t * fine.cells());
}
void prolong_add_faces_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf) {
#pragma omp parallel for schedule(static) if (fine.parallel())
  for (int t = 0; t < fine.T; ++t)
    for (int a = 0; a < fine.g.dim; ++a)
      prolong_layout(fine.g.face_layout(a), coarse.g.face_layout(a), xc + t * coarse.faces() + coarse.off[a],
                     xf + t * fine.faces() + fine.off[a], true);
}
void prolong_add_cells_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf) {
#pragma omp parallel for schedule(static) if (fine.parallel())
  for (int t = 0; t < fine.T; ++t)
    prolong_layout(fine.g.cell_layout(), coarse.g.cell_layout(), xc + t * coarse.cells(), xf + t * fine.cells(), true);
}
void restrict_faces_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc) {
#pragma omp parallel for schedule(static) if (fine.parallel())
  for (int t = 0; t < fine.T; ++t) restrict_faces(fine, coarse, xf + t * fine.faces(), xc + t * coarse.faces());
}
void restrict_cells_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc) {
#pragma omp parallel for schedule(static) if (fine.parallel())
  for (int t = 0; t < fine.T; ++t) restrict_cells(fine, coarse, xf + t * fine.cells(), xc + t * coarse.cells());
}

}  // namespace pliant::smoke
