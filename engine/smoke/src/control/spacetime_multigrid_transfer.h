// Grid transfers of the spacetime multigrid (semi-coarsening in space only: time is
// never coarsened, so every transfer acts frame by frame).
// Prolongation P: bilinear (2D) / trilinear (3D) interpolation of the coarse samples
// (cell centres, or the faces of one velocity component) at the fine sample
// positions, fine position x -> coarse x/2 in grid units, with the same clamping /
// wrapping as mac_grid.h's sample(). Restriction R = P^T / 2^dim (full weighting;
// every row of R sums to 1, so constants are restricted exactly).
#pragma once
#include <array>
#include <cstddef>

#include "../mac_grid.h"

namespace pliant::smoke {

// Below this many unknowns (cells x frames) a loop of the spacetime solver runs on
// one thread: on a loaded 2-core machine each OpenMP fork/join can cost milliseconds
// (measured: 32^2 x 20 V-cycles 0.8 s serial vs 30 s with 2 threads at load 9).
inline constexpr size_t kSpacetimeOmpMinWork = 200000;

// One level of the spacetime hierarchy: a MAC grid and T frames of unknowns.
// Face unknowns of a frame are the u, v (, w) faces concatenated (FaceSeries order).
struct SpacetimeGrid {
  MacGrid g;
  int T = 1;
  std::array<size_t, 4> off{0, 0, 0, 0};  // component offsets; off[dim] = faces()

  SpacetimeGrid() = default;
  SpacetimeGrid(const MacGrid& grid, int frames);
  size_t faces() const { return off[3]; }
  size_t cells() const { return g.cells(); }
  // The next coarser grid (every axis halved, cell size doubled).
  SpacetimeGrid coarsened() const;
  // True when every axis is even and >= 8 (so the coarse level has >= 4 cells per axis).
  bool coarsenable() const;
  bool parallel() const { return cells() * size_t(T) >= kSpacetimeOmpMinWork; }
};

// x_fine = P x_coarse for one frame (faces or cells).
void prolong_faces(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf);
void prolong_cells(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf);
// x_coarse = R x_fine for one frame.
void restrict_faces(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc);
void restrict_cells(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc);

// The same over all T frames (frame-parallel), arrays of T*faces / T*cells values.
void prolong_faces_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf);
void prolong_cells_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf);
// x_fine += P x_coarse over all T frames (the FAS correction, no fine-sized temporary).
void prolong_add_faces_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf);
void prolong_add_cells_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xc, double* xf);
void restrict_faces_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc);
void restrict_cells_series(const SpacetimeGrid& fine, const SpacetimeGrid& coarse, const double* xf, double* xc);

}  // namespace pliant::smoke
