// Mesh -> body: every mesh in tests/meshes either becomes a body or fails with an
// InputError at /character/mesh naming the problem; winding number and embedding.
#include <gtest/gtest.h>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/body.h"
#include "pliant/soft/soft.h"

using namespace pliant::soft;

namespace {
pliant::Scene mesh_scene(const std::string& mesh) {
  const std::string text = R"({"pliant": 1, "kind": "soft", "character": {"mesh": ")" + mesh +
                           R"(", "resolution": 4, "modes": 4}, "simulation": {"frames": 2},
      "optimizer": {"method": "none"}})";
  return pliant::parse_scene(text, "scene.json", PLIANT_TEST_MESHES_DIR);
}

std::string compile_error(const std::string& mesh) {
  try {
    soft_compile(mesh_scene(mesh));
  } catch (const pliant::InputError& e) {
    EXPECT_EQ(e.pointer(), "/character/mesh") << mesh;
    return e.problem();
  }
  return "";
}
}  // namespace

TEST(Body, BrokenMeshesFailNamingTheProblem) {
  EXPECT_NE(compile_error("empty.obj").find("empty.obj"), std::string::npos);
  const std::string garbage = compile_error("garbage.obj");  // assimp may read it as an empty OBJ
  EXPECT_TRUE(garbage.find("cannot load mesh") != std::string::npos ||
              garbage.find("no triangles") != std::string::npos) << garbage;
  EXPECT_NE(compile_error("missing.obj").find("file not found"), std::string::npos);
  EXPECT_NE(compile_error("zero_area.obj").find("no area"), std::string::npos);
  EXPECT_NE(compile_error("absurd_scale.obj").find("absurd scale"), std::string::npos);
  EXPECT_NE(compile_error("tiny_scale.obj").find("absurd scale"), std::string::npos);
}

TEST(Body, OddMeshesBecomeBodies) {
  for (const char* name : {"cube.ply", "cube.stl", "open_box.obj", "two_pieces.obj", "overlapping_pieces.obj",
                           "non_manifold.obj", "unwelded_cube.obj", "sheet.obj"}) {
    SCOPED_TRACE(name);
    SoftModel m = soft_compile(mesh_scene(name));
    EXPECT_GT(m.character.lattice.cells.size(), 0u);
    EXPECT_GT(m.character.basis.r(), 0);
    EXPECT_EQ(m.character.lattice.vertex_cell.size(), m.character.surface.vertices.size());
    if (std::string(name) == "two_pieces.obj") {
      EXPECT_EQ(m.character.lattice.pieces_found, 2);
      EXPECT_EQ(m.character.lattice.pieces_dropped, 1);
    }
    if (std::string(name) == "unwelded_cube.obj") {
      // assimp joins exact duplicates itself; the near-duplicates are ours to weld.
      EXPECT_GT(m.repair.welded_vertices, 0);
      EXPECT_EQ(m.character.surface.vertices.size(), 8u);
      EXPECT_EQ(m.repair.dropped_triangles, 1);
    }
  }
}

TEST(Body, WindingNumberInsideOutsideAndOpen) {
  auto cube = pliant::geom::unit_cube_mesh();
  const SurfaceMesh m = repair_mesh(cube);
  EXPECT_NEAR(winding_number(m, Eigen::Vector3d(0.1, -0.2, 0.3)), 1.0, 1e-9);
  EXPECT_NEAR(winding_number(m, Eigen::Vector3d(2, 0, 0)), 0.0, 1e-9);
  // Without its top face the cube's winding number at the centre drops by the
  // solid angle of the missing face (1/6).
  SurfaceMesh open = m;
  open.triangles.erase(open.triangles.begin() + 6, open.triangles.begin() + 8);
  EXPECT_NEAR(winding_number(open, Eigen::Vector3d::Zero()), 5.0 / 6.0, 1e-9);
}

TEST(Body, LatticeOfABoxAndEmbedding) {
  auto cube = pliant::geom::unit_cube_mesh();
  const SurfaceMesh m = repair_mesh(cube);
  const Lattice lat = build_lattice(m, 4, 500);
  // Faces lie on cell planes: exactly 4^3 cells, 5^3 nodes, mass = density * volume.
  EXPECT_EQ(lat.cells.size(), 64u);
  EXPECT_EQ(lat.nodes(), 125);
  double mass = 0;
  for (double w : lat.node_mass_kg) mass += w;
  EXPECT_NEAR(mass, 500.0, 1e-9);
  EXPECT_EQ(lat.boundary_faces.size(), 6u * 16u);
  // Embedding reproduces the rest surface.
  Eigen::VectorXd x(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j) x.segment<3>(3 * j) = lat.rest[j];
  std::vector<Eigen::Vector3d> v;
  embed_surface(lat, x, v);
  for (size_t i = 0; i < v.size(); ++i) EXPECT_LT((v[i] - m.vertices[i]).norm(), 1e-12);
}
