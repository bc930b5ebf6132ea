// Loading models: Pliant JSON (bodies with joints, geoms, inertials; or a chain
// generator) and a subset of MuJoCo's MJCF (mujoco/compiler/option/worldbody/body/
// joint/freejoint/geom/inertial/actuator motor). Every problem is an InputError
// naming the file and the JSON pointer or the XML element path
// (e.g. /mujoco/worldbody/body[0]/geom[1]/@size).
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "pliant/articulated/model.h"
#include "pliant/core/json_reader.h"

namespace pliant::articulated {

// How the MJCF reader treats what Pliant cannot honour. ignore_solver_params: MuJoCo's
// constraint-solver parameters, which Pliant's penalties have no use for (geom and
// contact-pair `solref`, `solimp`, `solmix`; joint `solreflimit`, `solimplimit`,
// `solreffriction`, `solimpfriction`; option `impratio`, `cone`, `noslip_*`), are
// recorded in Model::ignored_attributes instead of exiting 2, so gym-style models load.
// mesh_inertia: mesh geoms' mass properties, the enclosed solid's (Exact, default) or
// libmujoco 2.2.2's (MuJoCo222: its mass from the equivalent inertia box, larger for
// most shapes, e.g. 1.44x for the mug of libmujoco-samples), for side-by-side runs.
// exact_plane_contact: cylinders and ellipsoids meet planes at their exact surface
// (true, default) or through their tessellation's samples (Geom::exact_plane_contact).
struct MjcfOptions {
  bool ignore_solver_params = false;
  Geom::MeshInertia mesh_inertia = Geom::MeshInertia::Exact;
  bool exact_plane_contact = true;
};

// Mesh files (<asset><mesh file=.../>) are read relative to base_dir (the MJCF
// file's folder; compiler meshdir is appended).
Model model_from_mjcf(const std::string& text, const std::string& file,
                      const std::filesystem::path& base_dir = {}, const MjcfOptions& options = {});
// Mesh geoms' files ("type": "mesh", "file", "scale") are read relative to base_dir
// (the model file's folder, or the scene's for an inline model).
Model model_from_json(JsonReader& r, const std::filesystem::path& base_dir = {});
// Shared by MJCF <asset><mesh> and JSON mesh geoms: a triangle mesh file (OBJ, STL,
// PLY, ... through pliant_geom's assimp loader) scaled per axis (throws
// std::exception with the loader's message), and a geom made a mesh geom of it,
// re-centred at the mesh's centre of mass (geom pos moved to compensate; throws
// std::invalid_argument when the mesh has no positive volume).
std::shared_ptr<const MeshShape> mesh_load_file(const std::filesystem::path& file, const Vec3& scale);
void geom_set_mesh(Geom& g, const std::shared_ptr<const MeshShape>& shape);
// Tessellations for cylinder and ellipsoid geoms (primitive_meshes.cpp, Geom::tessellates):
// closed and outward-facing, centred at the origin.
MeshShape cylinder_mesh(double radius, double half_height, int segments = 32);
MeshShape ellipsoid_mesh(const Vec3& radii, int rings = 12, int segments = 24);
// .xml -> MJCF, .json -> Pliant JSON model (the whole document is the model).
Model model_load_file(const std::filesystem::path& path, const std::string& label, const MjcfOptions& options = {});

}  // namespace pliant::articulated
