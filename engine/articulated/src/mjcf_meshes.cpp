// MJCF <asset> meshes, and loading a mesh file into a geom (public: io.h).
#include "mjcf_internal.h"
#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "pliant/geom/triangle_mesh.h"

namespace pliant::articulated {
namespace mjcf_internal {

// <asset><mesh name file scale/>: triangle meshes through pliant_geom (assimp: OBJ,
// STL, PLY, ...); textures and materials are ignored.
void read_assets(Ctx& c, const XmlElement& e, const std::string& path, const std::filesystem::path& base_dir) {
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string p = child_path(path, e, k);
    if (ch.name == "texture" || ch.name == "material") continue;
    if (ch.name != "mesh") throw InputError(c.file, p, "unsupported element <" + ch.name + "> in <asset>");
    check_attrs(c, ch, p, {"name", "file", "scale"});
    if (!ch.attr("file")) throw InputError(c.file, p + "/@file", "mesh needs a file");
    const std::filesystem::path file = base_dir / c.mesh_dir / *ch.attr("file");
    std::string name = ch.attr("name") ? *ch.attr("name") : file.stem().string();
    const Vec3 scale = vec3(c, ch, p, "scale", Vec3::Ones());
    std::shared_ptr<const MeshShape> shape;
    try {
      shape = mesh_load_file(file, scale);
    } catch (const std::exception& err) {
      throw InputError(c.file, p + "/@file", err.what());
    }
    if (c.meshes.count(name)) throw InputError(c.file, p + "/@name", "mesh \"" + name + "\" defined twice");
    c.meshes[name] = shape;
  }
}

}  // namespace mjcf_internal

std::shared_ptr<const MeshShape> mesh_load_file(const std::filesystem::path& file, const Vec3& scale) {
  const geom::TriangleMesh tm = geom::load_mesh(file, file.string());
  auto shape = std::make_shared<MeshShape>();
  for (const auto& v : tm.vertices) shape->vertices.emplace_back(v[0] * scale.x(), v[1] * scale.y(), v[2] * scale.z());
  for (const auto& t : tm.triangles)
    shape->triangles.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
  return shape;
}

void geom_set_mesh(Geom& g, const std::shared_ptr<const MeshShape>& shape) {
  // Re-centre at the mesh's centre of mass (vertices stay in the geom frame): the
  // solid's, or under g.mesh_inertia MuJoCo222 the one MuJoCo 2.2.2 compiles.
  double volume;
  Vec3 centre;
  mesh_volume_moments(*shape, &volume, &centre, nullptr);
  if (!(volume > 0)) throw std::invalid_argument("has no positive volume (not closed or inward-facing)");
  if (g.mesh_inertia == Geom::MeshInertia::MuJoCo222) {
    double box, unsigned_volume;
    mesh_mujoco222_moments(*shape, &box, &unsigned_volume, &centre, nullptr);
    if (!(box > 0)) throw std::invalid_argument("has a flat equivalent inertia box (MuJoCo 2.2.2's mass rule gives it no mass)");
  }
  auto shifted = std::make_shared<MeshShape>(*shape);
  for (Vec3& v : shifted->vertices) v -= centre;
  g.type = GeomType::Mesh;
  g.mesh = shifted;
  g.pos += g.quat * centre;
}

}  // namespace pliant::articulated
