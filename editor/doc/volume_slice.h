// Slices of a 3D painted volume in three orientations, so a keyframe can be
// painted from the front, the top or the side. Each orientation is the view of
// an axis-aligned camera looking at the volume from outside, with the engine's
// vertical (+y: buoyancy and the renderer's up) up on screen wherever it lies in
// the slice, and no mirror (a letter painted on a slice reads the right way when
// the 3D view looks from that side):
//   XY (normal z, slice index k = z): front view from +z,  u = x,          v = y
//   XZ (normal y, k = y):             top view from +y,    u = x,          v = nz-1-z
//   YZ (normal x, k = x):             right view from +x,  u = nz-1-z,     v = y
// (u, v) are the 2D slice's cells (u right, v up, the paint_ops convention).
// UI state only: the orientation and index are never stored in the document.
#pragma once
#include <array>

#include "pliant/geom/painted_grid.h"

namespace pliant::editor {

enum class SliceAxis { XY = 0, XZ = 1, YZ = 2 };

// Name shown in the UI ("XY", "XZ", "YZ") and the letter of the normal axis ("z", "y", "x").
const char* slice_axis_name(SliceAxis a);
const char* slice_normal_name(SliceAxis a);
// Index of the normal axis in (x, y, z): 2, 1, 0.
int slice_normal_index(SliceAxis a);
// Number of slices along the normal, and a slice's size (w, h) in cells.
int slice_count(const std::array<int, 3>& n, SliceAxis a);
std::array<int, 2> slice_size(const std::array<int, 3>& n, SliceAxis a);
// Slice cell (k, u, v) -> voxel (x, y, z), and back ({k, u, v}).
std::array<int, 3> slice_to_voxel(const std::array<int, 3>& n, SliceAxis a, int k, int u, int v);
std::array<int, 3> voxel_to_slice(const std::array<int, 3>& n, SliceAxis a, int x, int y, int z);

// Slice k of a volume as a 2D grid (slice_size), zeros when k is out of range;
// and its inverse: only the voxels of that slice are written.
geom::PaintedGrid volume_slice(const geom::PaintedGrid& volume, SliceAxis a, int k);
void set_volume_slice(geom::PaintedGrid& volume, SliceAxis a, int k, const geom::PaintedGrid& slice);

// The slice's outline in the renderer's world frame (the domain centred at the
// origin, `extent` per axis): four corners on the plane through the slice's cell
// centres, spanning the two in-plane axes (the volume view draws it).
std::array<std::array<float, 3>, 4> slice_outline(const std::array<int, 3>& n, SliceAxis a, int k,
                                                  const std::array<float, 3>& extent);

}  // namespace pliant::editor
