// Mesh import through assimp: every mesh of every node, with the node transforms
// applied, triangulated, merged into one triangle list.
#include "pliant/geom/triangle_mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <limits>

#include "pliant/geom/raster_grid.h"

namespace pliant::geom {
namespace {

void collect(const aiScene* s, const aiNode* node, const aiMatrix4x4& parent, TriangleMesh& out) {
  const aiMatrix4x4 m = parent * node->mTransformation;
  for (unsigned mi = 0; mi < node->mNumMeshes; ++mi) {
    const aiMesh* mesh = s->mMeshes[node->mMeshes[mi]];
    const uint32_t base = uint32_t(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = m * mesh->mVertices[v];
      out.vertices.push_back({p.x, p.y, p.z});
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no volume
      out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(s, node->mChildren[c], m, out);
}

}  // namespace

std::array<std::array<double, 3>, 2> TriangleMesh::bounds() const {
  if (vertices.empty()) return {{{0, 0, 0}, {0, 0, 0}}};
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& v : vertices)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], v[a]);
      hi[a] = std::max(hi[a], v[a]);
    }
  return {lo, hi};
}

double TriangleMesh::signed_volume() const {
  double vol = 0;
  for (const auto& t : triangles) {
    const auto &a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
    vol += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return vol / 6.0;
}

TriangleMesh load_mesh(const std::filesystem::path& file, const std::string& label) {
  if (!std::filesystem::exists(file)) throw GeomError(label + ": cannot load mesh: file not found");
  Assimp::Importer importer;
  const aiScene* s = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                          aiProcess_SortByPType);
  if (!s || !s->mRootNode || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw GeomError(label + ": cannot load mesh: " + importer.GetErrorString());
  TriangleMesh out;
  collect(s, s->mRootNode, aiMatrix4x4(), out);
  if (out.triangles.empty()) throw GeomError(label + ": mesh has no triangles");
  return out;
}

TriangleMesh unit_cube_mesh() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back({(i & 1) - 0.5, ((i >> 1) & 1) - 0.5, ((i >> 2) & 1) - 0.5});
  // Two outward-facing triangles per face.
  const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

}  // namespace pliant::geom
