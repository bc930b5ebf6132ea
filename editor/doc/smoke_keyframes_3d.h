// 3D smoke keyframes as the editor edits them: a painted volume (geom::PaintedGrid
// with dim 3, stored inline as {"type":"painted","size":[w,h,d],"data":...}) is
// painted one slice at a time (x-y, x-z or y-z: doc/volume_slice.h) with the 2D tools of doc/paint_ops.h, and a mesh
// keyframe is placed by its transform ("center" as fractions of the domain,
// "scale", "rotation_deg" about "rotation_axis" (default +z): the engine's
// geom::Placement, an axis-angle, right-handed).
// Like smoke_keyframes.h every "with_" function returns a NEW scene for one
// Document::edit (one undo step).
#pragma once
#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "doc/volume_slice.h"
#include "pliant/geom/painted_grid.h"

namespace pliant::editor {

// grid.resolution [nx, ny, nz] of a 3D smoke scene ({0, 0, 0} otherwise).
std::array<int, 3> smoke_resolution_3d(const nlohmann::json& scene);

// An empty w x h x d painted volume.
geom::PaintedGrid make_painted_volume(int w, int h, int d);
// z slice `z` of a volume as a 2D grid (w x h), and its inverse: only the cells of
// that slice are written (the XY orientation of doc/volume_slice.h).
geom::PaintedGrid volume_slice(const geom::PaintedGrid& volume, int z);
void set_volume_slice(geom::PaintedGrid& volume, int z, const geom::PaintedGrid& slice);

// The slot's target rasterised on the 3D grid as bytes: a painted target of the
// grid's size decodes exactly (bit for bit), anything else goes through the
// engine's control_compile (meshes voxelised). Empty grid + *error on failure.
geom::PaintedGrid rasterize_slot_volume(const nlohmann::json& scene, const std::filesystem::path& scene_dir,
                                        int slot, std::string* error);
// The scene with the slot's target replaced by the painted volume.
nlohmann::json with_painted_volume_slot(const nlohmann::json& scene, int slot, const geom::PaintedGrid& volume);

// Placement of a mesh keyframe. center: fractions of each domain axis.
struct MeshTransform {
  std::array<double, 3> center{0.5, 0.5, 0.5};
  double scale = 1.0;
  double rotation_deg = 0.0;  // right-handed about rotation_axis
  std::array<double, 3> rotation_axis{0, 0, 1};  // any length > 0; +z = seen in the XY view
};

// True when the slot's target is {"type": "mesh"}.
bool is_mesh_slot(const nlohmann::json& scene, int slot);
// The slot's transform (defaults for missing fields; "center_m" converted to fractions;
// a "rotation_axis" that is not 3 numbers reads as +z, control_compile reports it).
MeshTransform mesh_transform(const nlohmann::json& scene, int slot);
// The scene with the slot's mesh transform replaced ("center_m" dropped for "center").
// "rotation_axis" is written when the target had one or the axis is not +z, so a
// scene that only ever turned about z keeps its plain "rotation_deg".
nlohmann::json with_mesh_transform(const nlohmann::json& scene, int slot, const MeshTransform& t);

// Gizmo drags, in slice cells (u right, v up; XY by default, where u = x, v = y)
// on a grid of n cells per axis: move by (dx, dy) in the slice plane; scale by the
// ratio of the distances from the centre of the start and end points; rotate by the
// angle swept about the centre, counter-clockwise on screen = right-handed about the
// slice's normal towards the viewer (XY +z, XZ +y, YZ +x), composed in world axes
// with the current rotation (geom::rotate_placement: a turn about the current axis
// just adds degrees, so XY drags on z-only scenes keep writing rotation_deg alone).
MeshTransform gizmo_move(const MeshTransform& t, double dx_cells, double dy_cells, const std::array<int, 3>& n,
                         SliceAxis a = SliceAxis::XY);
MeshTransform gizmo_scale(const MeshTransform& t, double x0, double y0, double x1, double y1,
                          const std::array<int, 3>& n, SliceAxis a = SliceAxis::XY);
// The transform's centre in continuous slice cells (u, v) of orientation a.
std::array<double, 2> mesh_centre_in_slice(const MeshTransform& t, const std::array<int, 3>& n, SliceAxis a);
MeshTransform gizmo_rotate(const MeshTransform& t, double x0, double y0, double x1, double y1,
                           const std::array<int, 3>& n, SliceAxis a = SliceAxis::XY);
// Screen angle (degrees, counter-clockwise) at which the gizmo draws its square
// footprint on orientation a: the direction of R times the world axis that points
// screen-right, projected on the slice (0 when it points along the normal). XY with
// a z axis returns rotation_deg itself (the drawing before 3D rotations).
double gizmo_footprint_deg(const MeshTransform& t, SliceAxis a);

// Density-weighted centroid of a volume in cells (cell centres at i + 0.5); tests
// and the gizmo's readout.
std::array<double, 3> volume_centroid(const geom::PaintedGrid& volume);

}  // namespace pliant::editor
