// Triangle meshes imported with assimp (OBJ, PLY, STL, glTF, FBX, ...), node
// transforms applied, all meshes of the file merged.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pliant::geom {

struct TriangleMesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
  // Bounding box (min, max); zero-size for an empty mesh.
  std::array<std::array<double, 3>, 2> bounds() const;
  // Signed volume by the divergence theorem (positive for outward-facing triangles).
  double signed_volume() const;
};

// Throws GeomError("<label>: cannot load mesh: <assimp's message>") or
// "<label>: mesh has no triangles".
TriangleMesh load_mesh(const std::filesystem::path& file, const std::string& label);
// An axis-aligned unit cube [-0.5,0.5]^3, 12 triangles (tests, default targets).
TriangleMesh unit_cube_mesh();

}  // namespace pliant::geom
