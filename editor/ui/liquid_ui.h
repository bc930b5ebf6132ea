// Shared state and entry points of the liquid scene UI (issue 7, "pouring
// scenes"): ui/liquid_panels.cpp (inspector, jobs), ui/liquid_gizmos.cpp
// (placing and sizing containers in the viewport), ui/liquid_timeline.cpp
// (key poses of the hand-drawn source trajectory).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/liquid_drawer.h"
#include "render/orbit_camera.h"
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
  enum class Handle { None, MoveSource, MoveTarget, SizeSource, SizeTarget } drag = Handle::None;
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
void liquid_timeline(App& app);

}  // namespace pliant::editor
