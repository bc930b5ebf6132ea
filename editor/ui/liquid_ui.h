// Shared state and entry points of the liquid scene UI (issue 7, "pouring
// scenes"): ui/liquid_panels.cpp (inspector, jobs), ui/liquid_gizmos.cpp
// (placing and sizing containers in the viewport), ui/liquid_timeline.cpp
// (key poses of the hand-drawn source trajectory), ui/liquid_placement_view.cpp
// (the document's initial state before a run).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/liquid_drawer.h"
#include "render/orbit_camera.h"
#include "render/renderer.h"
#include "ui/kind_panels.h"

namespace pliant::editor {

class App;

// Not document data: selections, drags in progress, caches of take data.
struct LiquidUiState : KindUiState {
  // Fractions per frame of the shown take (in target, spilled, in source).
  std::filesystem::path series_dir;
  size_t series_frames = 0;
  std::vector<float> in_target, spilled, in_source;
  // Viewport gizmo drag: which handle, the scene and mouse point at its start.
  // KeyPose / KeyTilt: the hand-drawn key `drag_key_index` (/source/trajectory):
  // its position, or its tilt (the selected key's lever handle).
  enum class Handle { None, MoveSource, MoveTarget, SizeSource, SizeTarget, KeyPose, KeyTilt } drag = Handle::None;
  int drag_key_index = -1;
  double drag_z = 0;  // the drag plane (3D): z of the dragged handle
  nlohmann::json drag_scene;
  double drag_start[2] = {0, 0};
  uint64_t drag_key = 0;
  OrbitCamera camera_at_drag;
  // Geometry of the document's scene (container outlines while editing).
  uint64_t geo_doc = ~uint64_t(0), geo_revision = ~uint64_t(0);
  bool geo_ok = false;
  LiquidSceneGeometry geo;
  std::vector<LineSegment2> source_section, target_section;
  // Where a dropped container file goes ("source" or "target").
  bool drop_to_target = false;
  // Placement view: the document's initial state (liquid_initial_frame) drawn
  // by a private Renderer into the viewport's target, before the first run or
  // with "Place" ticked. The record is rebuilt per document revision.
  bool place_mode = false;
  Renderer place_renderer;
  bool place_ready = false, place_ok = false, place_dirty = false, place_reframe = true;
  uint64_t place_doc = ~uint64_t(0), place_revision = ~uint64_t(0), place_uploads = 0;
  std::string place_error;
  Record place_record;
  std::vector<float> place_drawn;  // what the viewport's target holds (redraw on change)
  LiquidViewTransform place_view;  // world -> clip of the placement view's last draw
  int place_redraws = 0;
  // The shown take's planned trajectory (metrics "trajectory") as the engine's
  // curve through those keys, per take.
  std::filesystem::path plan_dir;
  nlohmann::json plan_keys;
  std::vector<Pose7> plan_path;
  // Timeline key poses.
  int selected_key = -1;
  int dragging_key = -1;
  nlohmann::json key_drag_scene;
  uint64_t key_drag_key = 0;
};

LiquidUiState& liquid_ui(App& app);
// Points the scene resolver at the document's and the shown take's folders.
void liquid_update_scene_dirs(App& app);
// The document's container geometry (cached per revision); false if it does not compile.
bool liquid_doc_geometry(App& app);
// A fresh merge key for one user drag (one undo step per drag).
uint64_t liquid_next_merge_key();

void liquid_viewport_overlay(App& app, float x, float y, int w, int h);
// Gizmos (container move/size, key pose handles, planned path) over an image
// at (x, y, w, h) drawn with the world -> clip transform `view`.
void liquid_gizmos(App& app, const LiquidViewTransform& view, float x, float y, int w, int h);
// The shown take's planned keys and path (cached per take); false if none.
bool liquid_planned_path(App& app);
// Placement view (KindPanels::viewport_editor): true when it drew the viewport.
bool liquid_placement_view(App& app);
// The viewport toolbar's liquid part (drop target, Place, Use plan).
void liquid_viewport_toolbar(App& app);
void liquid_timeline(App& app);

}  // namespace pliant::editor
