// The keyframe canvas of 2D smoke scenes: paints the selected keyframe (or the
// initial density) of the scene's "control" section as a painted grid. A stroke
// edits a working copy and is written back with one Document::edit on release,
// so every stroke is one undo step and save/reopen is bit-exact (the grid is
// stored inline, geom/painted_grid.h).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "doc/paint_ops.h"
#include "doc/smoke_keyframes.h"
#include "doc/smoke_keyframes_3d.h"
#include "pliant/geom/painted_grid.h"

namespace pliant::editor {

class App;
struct KeyframeVolumeView;  // ui/keyframe_slices.h

// Gizmo is the mesh transform tool of 3D mesh keyframes (the 2D canvas shows the first 7).
enum class CanvasTool { Brush, Eraser, Fill, Ellipse, Rectangle, Move, Text, Gizmo };
enum class GizmoHandle { None, Move, Scale, Rotate, Fields };  // Fields: a number field dragged

struct KeyframeCanvasState {
  int slot = kInitialDensitySlot;  // keyframe index, or the initial density
  CanvasTool tool = CanvasTool::Brush;
  float radius_cells = 4.0f, hardness = 0.7f;
  // One strength for every painting tool (Brush, Eraser, Fill, Ellipse, Rectangle;
  // 2D canvas and 3D slices): the density they paint (the eraser: the fraction it
  // removes). Shared rather than per tool so switching tools never hides a value.
  float strength = 1.0f;
  bool onion = true;
  char text[64] = "F";
  char font[512] = "";           // "" = the shipped DejaVu Sans Bold
  float text_height = 0.45f;     // fraction of the grid height
  char import_path[1024] = "";
  int edit_frame = 0;            // current frame when no take has frames

  // Cache of the slot's raster and its neighbours (onion skin), per doc revision.
  uint64_t cached_revision = ~uint64_t(0);
  int cached_slot = -99;
  geom::PaintedGrid grid, onion_prev, onion_next;
  std::string error;
  // The stroke in progress (mouse held): edits go to `working`.
  bool stroking = false;
  geom::PaintedGrid working;
  double last_x = 0, last_y = 0, start_x = 0, start_y = 0;
  unsigned texture = 0;  // GL texture of the composite
  std::array<uint64_t, 3> texture_key{~0ull, 0, 0};  // (revision, slot, onion) it shows

  // 3D scenes (keyframe_slices.cpp): the slot's volume as bytes (exact for painted
  // volumes) and its densities, its onion-skin neighbours, the z slice painted.
  geom::PaintedGrid vol, vol_prev, vol_next;
  std::vector<float> volume;  // vol as densities 0..1
  std::array<int, 3> volume_dims{0, 0, 0};
  uint64_t volume_revision = ~uint64_t(0);
  int volume_slot = -99, slice = -1;  // slice: the z index of the XY orientation
  // Slice orientation (doc/volume_slice.h) and each orientation's own index
  // (slice_y for XZ, slice_x for YZ): UI state, never saved nor undone.
  SliceAxis slice_axis = SliceAxis::XY;
  int slice_y = -1, slice_x = -1;
  uint64_t volume_version = 0;  // bumped whenever the shown volume (or a stroke) changes
  std::array<uint64_t, 2> slice_key{~0ull, 0};  // (volume_version, axis + slice + onion) the texture shows
  unsigned slice_texture = 0;
  // Mesh gizmo drag: the transform at press and the previewed one.
  GizmoHandle gizmo = GizmoHandle::None;
  MeshTransform gizmo_start, gizmo_now;
  std::shared_ptr<KeyframeVolumeView> volume_view;  // the ray-marched keyframe beside the slice
};

// The canvas with its toolbar, in the current window's remaining region.
void draw_keyframe_canvas(App& app);
// Refreshes the cached rasters when the document or the slot changed.
void refresh_canvas_cache(App& app);
// A selected slot that no longer exists (undo of an add, a delete) falls back to
// the initial density.
void keep_canvas_slot_valid(KeyframeCanvasState& s, const nlohmann::json& scene);
// Writes a grid into the selected slot: one undo step labelled `what`.
void commit_canvas(App& app, const geom::PaintedGrid& g, const std::string& what);
// Text stamped at cell (x, y) with the canvas's text settings into g; false + log on failure.
bool stamp_canvas_text(App& app, geom::PaintedGrid& g, double x, double y);
// Imports an image file into the selected slot as painted coverage (luma, fitted
// to 80% of the grid); a new keyframe at the current frame when `new_keyframe`.
bool import_image_keyframe(App& app, const std::string& path, bool new_keyframe);
// 3D scenes: a "mesh" keyframe target for the file at the current frame.
bool import_mesh_keyframe(App& app, const std::string& path);
// The frame the keyframe tools act on: the take's frame when it has frames.
int canvas_current_frame(App& app);
void release_canvas_gl(KeyframeCanvasState& s);
// The composite of a keyframe grid over its onion-skin neighbours (previous in
// blue, next in orange; null = not shown) uploaded to *texture (created if 0).
void upload_composite_texture(unsigned* texture, const geom::PaintedGrid& g, const geom::PaintedGrid* onion_prev,
                              const geom::PaintedGrid* onion_next);
// The slots before and after `slot` in frame order (initial density first); -99 = none.
void keyframe_neighbours(const nlohmann::json& scene, int slot, int* prev, int* next);
// The index of the slice shown in the current orientation (slice, slice_y or slice_x).
inline int& current_slice(KeyframeCanvasState& s) {
  return s.slice_axis == SliceAxis::XZ ? s.slice_y : s.slice_axis == SliceAxis::YZ ? s.slice_x : s.slice;
}
// The "strength" slider (0..1) shared by the painting tools; marked "tool_strength".
void draw_strength_slider(KeyframeCanvasState& s);
// 3D smoke: the selected keyframe painted one z slice at a time (the 2D tools),
// mesh keyframes placed with a gizmo, and the ray-marched volume beside it.
void draw_keyframe_slices(App& app);

}  // namespace pliant::editor
