// Surfaces of liquid containers for drawing: the zero level set of a container's
// wall signed distance (engine/liquid ContainerShape::wall_sdf), in the
// container's own frame (opening up +y, floor at y = 0).
// 3D: marching tetrahedra (6 tetrahedra per cube along its main diagonal: no
// ambiguous cases, so the surface is watertight), vertices shared per grid
// edge and triangles wound so their normal points out of the wall (the
// MeshDrawer's smooth normals need one consistent winding).
// 2D: the z = 0 section as line segments (marching squares, render/contour.h).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "render/mat4.h"

namespace pliant::editor {

// Signed distance in the container's frame (negative inside the wall material).
using LocalSdf = std::function<double(double x, double y, double z)>;

struct TriangleMesh {
  std::vector<float> xyz;       // 3 per vertex
  std::vector<uint32_t> tris;   // 3 per triangle
  size_t vertex_count() const { return xyz.size() / 3; }
  size_t triangle_count() const { return tris.size() / 3; }
};

struct LineSegment2 {
  float ax, ay, bx, by;
};

// Samples the SDF on a grid of spacing `step` over [lo, hi] (corners) and
// extracts its zero level set.
TriangleMesh sdf_surface_mesh(const LocalSdf& sdf, const Vec3& lo, const Vec3& hi, float step);
// The zero set of sdf(x, y, 0) over [lo, hi] (x, y only).
std::vector<LineSegment2> sdf_section_lines(const LocalSdf& sdf, const Vec3& lo, const Vec3& hi, float step);

}  // namespace pliant::editor
