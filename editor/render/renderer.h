// Draws one take frame into the currently bound framebuffer with OpenGL 3.3
// core. The same code runs under GLFW and EGL, so CI renders the pixels a user
// sees. 2D smoke: density as a texture; 3D smoke: ray marching a 3D texture.
// Other kinds (liquid, soft, articulated) through their FrameDrawer
// (render/frame_drawer.h), framed into the same unit box.
#pragma once
#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "pliant/core/take.h"
#include "render/orbit_camera.h"

namespace pliant::editor {

struct ViewSettings {
  float density_scale = 1.0f;     // density mapped to opacity
  bool show_grid = true;          // domain outline / grid
  bool show_velocity = false;     // 2D: velocity arrows
  bool show_force = false;        // 2D: control force arrows (keyframe takes)
  std::array<float, 3> background{0.08f, 0.09f, 0.11f};
  std::array<float, 3> smoke_color{0.95f, 0.95f, 1.0f};
};

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Compiles the embedded shaders; needs a current GL context.
  bool init(std::string* err);
  // Uploads a record's "density" (and "velocity") to GL textures, or hands the
  // record to the first kind drawer that takes it. `take_scene`: the take
  // manifest's scene copy (kind drawers read geometry from it); may be null.
  void set_frame(const Record& frame, const nlohmann::json* take_scene = nullptr);
  // Shows frame `i` of a take. Kind drawers are framed from the take's frame 0
  // whichever frame comes first after reset_framing(): a running job shows its
  // newest frame, which must not decide the camera box.
  void set_take_frame(TakeReader& take, size_t i);
  void clear_frame();
  // Kind drawers: the next upload (frame 0 of the take, with set_take_frame)
  // fixes the world -> unit-box framing again (call when a different take is shown).
  void reset_framing();
  // Name of the kind drawer showing the frame ("" for smoke or none).
  std::string drawer_name() const;
  bool has_frame() const;
  // Domain size in world units, for camera framing: 2D (nx, ny, 0), 3D (nx, ny, nz)
  // scaled so the longest side is 1.
  std::array<float, 3> domain_extent() const;
  int frame_dim() const;  // 0 none, 2 or 3
  // Draws into the bound framebuffer at viewport (0, 0, w, h).
  void render(const OrbitCamera& cam, const ViewSettings& view, int w, int h);
  void shutdown();

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace pliant::editor
