// Drawers for take frames of kinds other than smoke (liquid particles, soft
// character meshes, articulated bodies). The Renderer asks each drawer in turn
// whether it draws a frame; smoke density stays built into the Renderer.
//
// Drawers work in world units (metres). The Renderer frames the take: it maps
// the bounds of the take's first drawn frame to a box centred at the origin
// whose longest side is 1 (the camera's convention), and hands the drawer the
// full world -> clip matrix.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pliant/core/take.h"
#include "render/line_drawer.h"
#include "render/mat4.h"

namespace pliant::editor {

struct ViewSettings;

struct WorldBox {
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  bool empty() const { return !(hi[0] >= lo[0] && hi[1] >= lo[1] && hi[2] >= lo[2]); }
};

struct DrawContext {
  Mat4 world_to_clip;         // projection * view * framing
  Mat4 world_to_view;         // view * framing (for lighting in view space)
  Vec3 eye_world{0, 0, 0};    // camera position in world units
  float pixels_per_metre = 1; // at the framing box's centre, for point sprite sizes
  int width = 0, height = 0;  // viewport in pixels
  const ViewSettings* view = nullptr;
  LineDrawer* lines = nullptr;  // world-space lines: add with world_to_clip, drawn after draw()
};

class FrameDrawer {
 public:
  virtual ~FrameDrawer() = default;
  virtual const char* name() const = 0;
  // Compiles shaders; needs a current GL context.
  virtual bool init(std::string* err) = 0;
  // Uploads `frame` if it holds this drawer's fields and returns true; false
  // means "not mine" (the Renderer tries the next drawer). `take_scene` is the
  // take manifest's copy of its scene (container shapes, body geometry, ...);
  // it may be null (a lone record).
  virtual bool upload(const Record& frame, const nlohmann::json* take_scene) = 0;
  // World-space bounds of the uploaded frame (camera framing).
  virtual WorldBox bounds() const = 0;
  // 2 (drawn with the 2D pan/zoom camera in the x-y plane) or 3.
  virtual int dim() const = 0;
  virtual void draw(const DrawContext& ctx) = 0;
  virtual void shutdown() = 0;
};

// One factory per kind, each in its own file (render/<kind>_drawer.cpp).
std::unique_ptr<FrameDrawer> make_liquid_drawer();
std::unique_ptr<FrameDrawer> make_soft_drawer();
std::unique_ptr<FrameDrawer> make_articulated_drawer();

}  // namespace pliant::editor
