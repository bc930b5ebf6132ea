// Batches coloured line segments on the CPU and draws them in one call
// (outlines, grids, velocity arrows). Counts are small (thousands), so a
// streamed VBO is simpler than instancing.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "render/gl_util.h"

namespace pliant::editor {

class LineDrawer {
 public:
  using Color = std::array<float, 4>;
  bool init(std::string* err);
  void clear() { verts_.clear(); }
  void add(const Vec3& a, const Vec3& b, const Color& c);
  // Axis-aligned box [lo, hi] as 12 edges.
  void add_box(const Vec3& lo, const Vec3& hi, const Color& c);
  // Draws everything added since clear() with alpha blending, then clears.
  void draw(const Mat4& mvp);
  void shutdown();

 private:
  struct Vertex {
    float pos[3];
    float color[4];
  };
  std::vector<Vertex> verts_;
  gl::Program program_;
  gl::VertexArray vao_;
  gl::Buffer vbo_;
};

}  // namespace pliant::editor
