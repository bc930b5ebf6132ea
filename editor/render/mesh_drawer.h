// Batches lit triangle meshes (soft characters, articulated bodies, containers)
// and draws them in one call with a headlight, two-sided Lambert shading, so
// open meshes look right from both sides. Primitives (sphere, capsule, box) are
// tessellated on the CPU; counts are small (tens of thousands of triangles).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "render/gl_util.h"

namespace pliant::editor {

class MeshDrawer {
 public:
  using Color = std::array<float, 4>;
  bool init(std::string* err);
  void clear();
  // A mesh given by xyz positions and index triples, under `model` (world units).
  // Smooth normals (area-weighted), or with crease_deg > 0 per-corner normals over
  // the faces within that angle of the corner's face (sharp edges stay sharp);
  // indices out of range are skipped.
  void add_mesh(const float* xyz, size_t nverts, const uint32_t* tris, size_t ntris, const Color& c,
                const Mat4& model, float crease_deg = 0);
  // Primitives centred at the model origin: sphere of radius r; capsule of
  // radius r around the local z axis from -half_len to +half_len; box of half sizes.
  void add_sphere(const Mat4& model, float r, const Color& c);
  void add_capsule(const Mat4& model, float r, float half_len, const Color& c);
  void add_box(const Mat4& model, const Vec3& half, const Color& c);
  size_t triangle_count() const { return verts_.size() / 3; }
  // Draws everything added since clear(); the batch stays until clear(), so
  // redrawing an unchanged frame costs no upload.
  void draw(const Mat4& world_to_clip, const Mat4& world_to_view);
  void shutdown();

 private:
  struct Vertex {
    float pos[3];
    float normal[3];
    float color[4];
  };
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb, const Vec3& nc,
                    const Color& col);
  std::vector<Vertex> verts_;
  bool dirty_ = true;
  gl::Program program_;
  gl::VertexArray vao_;
  gl::Buffer vbo_;
};

// Rigid transform helpers for models: translation + unit quaternion (w, x, y, z).
Mat4 pose_matrix(const Vec3& position, const std::array<float, 4>& quat_wxyz);

}  // namespace pliant::editor
