// 3D smoke: the density field [nz, ny, nx] as an R32F 3D texture, ray marched
// through the domain box (shaders/volume.frag), with the box outline.
#pragma once
#include <string>

#include "pliant/core/take.h"
#include "render/gl_util.h"
#include "render/line_drawer.h"
#include "render/renderer.h"

namespace pliant::editor {

class Smoke3DDrawer {
 public:
  bool init(std::string* err);
  void upload(const Field& density);  // [nz, ny, nx]
  void draw(const Mat4& view_proj, const Vec3& half, const ViewSettings& view, LineDrawer& lines);
  void shutdown();

  // Extinction per unit density per world unit (the domain's longest side is 1):
  // density 1 over half the domain lets through exp(-4) of the light.
  static constexpr float kSigmaPerDensity = 8.0f;

 private:
  gl::Program program_;
  gl::VertexArray vao_;
  gl::Texture density_;
  int nx_ = 0, ny_ = 0, nz_ = 0;
};

}  // namespace pliant::editor
