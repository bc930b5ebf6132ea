// The keyframe canvas of 2D smoke scenes: paints the selected keyframe (or the
// initial density) of the scene's "control" section as a painted grid. A stroke
// edits a working copy and is written back with one Document::edit on release,
// so every stroke is one undo step and save/reopen is bit-exact (the grid is
// stored inline, geom/painted_grid.h).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "doc/paint_ops.h"
#include "doc/smoke_keyframes.h"
#include "pliant/geom/painted_grid.h"

namespace pliant::editor {

class App;

enum class CanvasTool { Brush, Eraser, Fill, Ellipse, Rectangle, Move, Text };

struct KeyframeCanvasState {
  int slot = kInitialDensitySlot;  // keyframe index, or the initial density
  CanvasTool tool = CanvasTool::Brush;
  float radius_cells = 4.0f, hardness = 0.7f;
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
  // 3D scenes: the slot's volume and the z slice shown (keyframe_slices.cpp).
  std::vector<float> volume;
  std::array<int, 3> volume_dims{0, 0, 0};
  uint64_t volume_revision = ~uint64_t(0);
  int volume_slot = -99, slice = -1, shown_slice = -2;
  std::array<uint64_t, 3> texture_key{~0ull, 0, 0};  // (revision, slot, onion) it shows
};

// The canvas with its toolbar, in the current window's remaining region.
void draw_keyframe_canvas(App& app);
// Refreshes the cached rasters when the document or the slot changed.
void refresh_canvas_cache(App& app);
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
// 3D smoke: the selected keyframe as z slices (read-only), a slice slider and the
// keyframe list; meshes are added by dropping them on the window.
void draw_keyframe_slices(App& app);

}  // namespace pliant::editor
