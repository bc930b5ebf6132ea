// 2D smoke: the density field [ny, nx] as an R32F texture on the domain quad,
// optional grid/outline and velocity arrows ([ny, nx, 2], one per k-th cell).
#pragma once
#include <string>
#include <vector>

#include "pliant/core/take.h"
#include "render/gl_util.h"
#include "render/line_drawer.h"
#include "render/renderer.h"

namespace pliant::editor {

class Smoke2DDrawer {
 public:
  bool init(std::string* err);
  // density: [ny, nx]; velocity and force: [ny, nx, 2] or nullptr.
  void upload(const Field& density, const Field* velocity, const Field* force = nullptr);
  // half extent of the domain quad (longest side 1).
  void draw(const Mat4& mvp, float half_w, float half_h, const ViewSettings& view, LineDrawer& lines);
  void shutdown();

  // Velocity arrow spacing in cells: about 16 arrows along the longest side.
  static int arrow_stride(int nx, int ny);

 private:
  void add_arrows(const std::vector<float>& field, float half_w, float half_h,
                  const std::array<float, 4>& color, LineDrawer& lines) const;

  gl::Program program_;
  gl::VertexArray vao_;
  gl::Texture density_;
  int nx_ = 0, ny_ = 0;
  std::vector<float> velocity_;  // [ny, nx, 2], empty if none
  std::vector<float> force_;     // [ny, nx, 2], empty if none
};

}  // namespace pliant::editor
