// Articulated take frames (issue 6): bodies posed by "body_pose" with the
// model's geoms, the ground and static obstacles, contact points with force
// arrows. The model comes from compiling the take manifest's scene copy once
// per take (articulated_compile); the drawer itself is render/articulated_drawer.cpp.
//
// Display frame: the engine is z-up, the orbit camera y-up, so the drawer shows
// world (x, y, z) at display (x, z, -y); bounds are reported in display units.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/mat4.h"

namespace pliant::editor {

// Settings the articulated panels change; the drawer reads them at upload time
// (panels force a re-upload after a change).
struct ArticulatedDrawOptions {
  bool show_contacts = true;
  bool follow = true;        // floating models: keep the root body centred horizontally
  // Arrow length 0.4 * view * (1 - exp(-force_scale * |f| / weight)): the weight
  // is 0.25 of the view, impacts saturate at 0.4.
  float force_scale = 1.0f;
};
ArticulatedDrawOptions& articulated_draw_options();

// The folder that relative model paths of the take's scene copy are resolved
// against (the folder of the manifest's scene_file). The drawer's upload() only
// receives the scene JSON, so the panels set this before the viewport draws.
void articulated_drawer_set_scene_dir(const std::filesystem::path& dir);

// The model's geometry as the drawer needs it. render/ does not link the engine
// module, so the articulated panels (ui/, which do) register the function that
// compiles a scene into this (articulated_compile); without one, bodies are
// drawn as plain balls.
// A mesh geom's triangles in the geom's frame, shared by every frame's upload.
struct ArticulatedMesh {
  std::vector<float> xyz;         // 3 per vertex
  std::vector<uint32_t> triangles;  // 3 per triangle
  float radius = 0;               // largest vertex distance from the geom origin
};
struct ArticulatedGeom {
  enum Shape { Plane, Sphere, Capsule, Box, Mesh } shape = Sphere;
  int body = 0;  // 0: a static obstacle in the world
  Vec3 pos{0, 0, 0};                     // in the body frame (world for static)
  std::array<float, 4> quat{1, 0, 0, 0};  // w x y z
  Vec3 size{0, 0, 0};  // sphere r; capsule r, half length (local z); box half sizes
  std::shared_ptr<const ArticulatedMesh> mesh;  // Shape::Mesh only
};
struct ArticulatedGeometry {
  int bodies = 0;          // without the world
  bool floating = false;   // a root body has a free or slide joint
  double total_mass = 0;   // kg
  double gravity = 9.81;   // m/s^2
  std::vector<ArticulatedGeom> geoms;
};
using ArticulatedGeometryFn = bool (*)(const nlohmann::json& scene, const std::filesystem::path& dir,
                                       ArticulatedGeometry* out, std::string* err);
void articulated_drawer_set_geometry_source(ArticulatedGeometryFn fn);

// What the last uploaded frame held (the viewport overlay prints it).
struct ArticulatedFrameInfo {
  int bodies = 0, geoms = 0, contacts = 0;
  bool has_energy = false;
  float energy[3] = {0, 0, 0};  // kinetic, potential, total (J)
  float max_force = 0;          // N, largest contact force of the frame
  std::string model_error;      // compile error: bodies drawn as plain spheres
};
const ArticulatedFrameInfo& articulated_last_frame_info();

// What the main viewport's drawer shows (the first articulated drawer alive;
// A/B's comes later), for picking bodies under the mouse: the last frame's
// body poses (engine world, [0] the world), its model (null when none
// compiled) and the engine world -> clip matrix of its last draw (z-up -> y-up,
// follow shift and framing included).
struct ArticulatedView {
  bool drawn = false;
  Mat4 world_to_clip{};
  int width = 0, height = 0;
  const ArticulatedGeometry* model = nullptr;
  std::vector<Vec3> pos;
  std::vector<std::array<float, 4>> quat;
};
const ArticulatedView* articulated_primary_view();
// The body drawn tinted as selected (0: none), applied at the next upload;
// returns true when it changed (the caller then uploads the frame again).
bool articulated_drawer_set_highlight(int body);

}  // namespace pliant::editor
