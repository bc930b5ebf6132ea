// The liquid take drawer's public side (the drawer itself is make_liquid_drawer
// in frame_drawer.h): how it learns container shapes, and where the overlay
// panels read the last view transform.
//
// The render library does not link the liquid engine, so the editor library
// (ui/liquid_scene_geometry.cpp, which compiles scenes with engine/liquid)
// registers a resolver that turns a take's scene copy into container SDFs.
// Without one the drawer shows the particles and the container poses only.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/frame_drawer.h"
#include "render/liquid_container_mesh.h"

namespace pliant::editor {

using Pose7 = std::array<float, 7>;  // position xyz (m) + quaternion wxyz

struct LiquidContainerGeometry {
  LocalSdf wall_sdf;     // container frame (opening up +y)
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};  // local box that holds the wall
  float step = 0.005f;   // sampling step for the surface (< wall thickness / 2)
};

struct LiquidSceneGeometry {
  int dim = 2;
  bool has_source = false, has_target = false;
  LiquidContainerGeometry source, target;
  std::vector<Pose7> source_path;  // source pose at every frame (scene's key poses)
  Pose7 target_pose{0, 0, 0, 1, 0, 0, 0};
  float particle_spacing_m = 0.01f;  // cell size / particles per axis
  WorldBox domain;
};

// Fills *out from a take's scene copy; false (+ *err) when the scene cannot be
// compiled (then the drawer falls back to particles only).
using LiquidSceneResolver = bool (*)(const nlohmann::json& scene, LiquidSceneGeometry* out, std::string* err);
void set_liquid_scene_resolver(LiquidSceneResolver resolver);
LiquidSceneResolver liquid_scene_resolver();

// World -> clip of the last liquid draw, for overlays (gizmos) in screen space.
struct LiquidViewTransform {
  bool valid = false;
  int dim = 2;
  Mat4 world_to_clip{};
  int width = 0, height = 0;
};
const LiquidViewTransform& liquid_last_view();

}  // namespace pliant::editor
