// Synthetic take frames with known content for render tests.
#pragma once
#include "pliant/core/take.h"

namespace pliant::test {

// density [ny, nx] = peak * exp(-|p - c|^2 / (2 sigma^2)) in cell units (cell centres).
Field gaussian_blob_2d(int nx, int ny, float cx, float cy, float sigma, float peak = 1.0f);
// velocity [ny, nx, 2]: rigid rotation (counter-clockwise) about cell (cx, cy), 1 cell/s per cell.
Field vortex_velocity_2d(int nx, int ny, float cx, float cy);
// density [n, n, n]: 1 inside radius r (cells) about the centre, with a one-cell smooth edge.
Field sphere_3d(int n, float radius_cells);
// The same sphere about cell (cx, cy, cz).
Field sphere_3d_at(int n, float radius_cells, float cx, float cy, float cz);
// density of the given shape filled with a constant.
Field uniform_density(std::vector<uint32_t> shape, float value);

Record frame_of(std::vector<Field> fields);

}  // namespace pliant::test
