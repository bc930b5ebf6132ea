#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "container_mesh.h"
#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/geom/triangle_mesh.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {
namespace {

const std::string kAssets = PLIANT_ASSETS_DIR;
const std::string kMeshes = kAssets + "/../tests/meshes/";

// The shipped mug (make_mug.py): cavity radius 0.04, rim 0.1 above the base,
// floor 0.012 thick, wall 0.012; a handle tube on -x.
ContainerShape mug(double h = 0.0025) {
  return mesh_container(geom::load_mesh(kAssets + "/containers/mug.obj", "mug"), 1.0, h);
}

std::string mesh_problem(const geom::TriangleMesh& m) {
  try {
    mesh_container(m, 1.0, 0.01);
  } catch (const MeshContainerError& e) {
    return e.what();
  }
  return "";
}

TEST(ContainerMesh, MugFrameCavityAndDistances) {
  const ContainerShape c = mug();
  const double h = 0.0025;
  ASSERT_EQ(c.type, ContainerShape::Mesh);
  EXPECT_NEAR(c.height_m, 0.1 - 0.012, h);  // rim above the cavity floor
  EXPECT_NEAR(c.radius_m, 0.04, h);
  EXPECT_NEAR(c.depth_m, 0.04, h);
  EXPECT_NEAR(c.wall_m, 0.012, h);
  // 48-gon cavity: area 0.5 * 48 * r^2 sin(2 pi / 48).
  const double area = 0.5 * 48 * 0.04 * 0.04 * std::sin(2 * M_PI / 48);
  EXPECT_NEAR(c.cavity_volume(3) / (area * 0.088), 1.0, 0.06);
  EXPECT_NEAR(c.cavity_volume(2) / (0.08 * 0.088), 1.0, 0.06);
  // Distances against the exact geometry (a vertex of the 48-gon lies on +x),
  // away from the walls' mid planes (the distance's ridge, where sampling
  // cuts the peak by up to h / 2).
  EXPECT_NEAR(c.wall_sdf({0.037, 0.05, 0}, 3), 0.003, 0.3 * h);    // cavity, 3 mm from the inner wall
  EXPECT_NEAR(c.wall_sdf({0.041, 0.05, 0}, 3), -0.001, 0.3 * h);   // 1 mm into the wall
  EXPECT_NEAR(c.wall_sdf({0.0, -0.002, 0}, 3), -0.002, 0.3 * h);   // 2 mm into the floor
  EXPECT_NEAR(c.wall_sdf({0.055, 0.05, 0}, 3), 0.003, 0.3 * h);    // 3 mm outside
  EXPECT_NEAR(c.wall_sdf({0.0, 0.092, 0.0}, 3) , c.wall_sdf({0.0, 0.092, 0.0}, 2), 1e-12);  // 2D: z = 0 section
  EXPECT_GT(c.wall_sdf({0.0, 0.05, 0}, 3), 0.005);                  // deep in the cavity (clamped band)
  EXPECT_GT(c.wall_sdf({0.3, 0.05, 0}, 3), 0.2);                    // far outside the sampled box
  EXPECT_LT(c.wall_sdf({-0.082, 0.043, 0}, 3), 0.0);                 // inside the handle tube
  EXPECT_TRUE(c.in_cavity({0.0, 0.05, 0}, 3));
  EXPECT_TRUE(c.in_cavity({0.02, 0.01, -0.02}, 3));
  EXPECT_FALSE(c.in_cavity({-0.066, 0.043, 0}, 3));  // beside the mug, inside the handle's loop
  EXPECT_GT(c.wall_sdf({-0.066, 0.043, 0}, 3), 0.0);
  EXPECT_FALSE(c.in_cavity({0.0, 0.12, 0}, 3));    // above the rim
  EXPECT_TRUE(c.in_extended_cavity({0.0, 0.3, 0}, 3));
  EXPECT_FALSE(c.in_extended_cavity({-0.066, 0.3, 0}, 3));
}

TEST(ContainerMesh, LiquidAtRestInTheMugStaysAtRest) {
  // The flip_step rest test with the mesh mug as the source (2D section).
  LiquidModel m;
  m.dim = 2;
  m.domain_min_m = {-0.1, 0, 0};
  m.domain_max_m = {0.1, 0.16, 0};
  m.cell_size_m = 0.008;
  m.n = {25, 20, 1};
  m.has_target = false;
  m.source.shape = mug(0.004);
  m.source.pose.position_m = {0, 0.03, 0};
  m.fill_fraction = 0.6;
  LiquidState s = liquid_init(m);
  ASSERT_GT(s.count(), 200u);
  auto mean_y = [&] {
    double y = 0;
    for (size_t p = 0; p < s.count(); ++p) y += s.x[3 * p + 1];
    return y / double(s.count());
  };
  const double y0 = mean_y() - 0.03;
  for (int f = 0; f < 40; ++f) liquid_step(m, s);
  double vmax = 0;
  for (size_t p = 0; p < s.count(); ++p) vmax = std::max(vmax, double(std::hypot(s.v[3 * p], s.v[3 * p + 1])));
  // Rest-level noise: 0.02-0.04 m/s here against 0.013-0.02 for the analytic
  // cylinder of the same size on this grid (the sampled SDF is rougher); a
  // drop from the rim would reach 0.5.
  EXPECT_LT(vmax, 0.05);
  EXPECT_NEAR((mean_y() - 0.03) / y0, 1.0, 0.01);
  EXPECT_DOUBLE_EQ(liquid_fractions(m, s)[2], 1.0);
}

TEST(ContainerMesh, BadMeshesAreRefusedWithTheirProblem) {
  const auto open_box = geom::load_mesh(kMeshes + "open_box.obj", "open_box");
  EXPECT_NE(mesh_problem(open_box).find("not closed: 4 boundary edge"), std::string::npos) << mesh_problem(open_box);
  const auto sheet = geom::load_mesh(kMeshes + "sheet.obj", "sheet");
  EXPECT_NE(mesh_problem(sheet).find("not closed"), std::string::npos) << mesh_problem(sheet);
  // Closed but flat: four coplanar points as a tetrahedron.
  geom::TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}};
  flat.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  EXPECT_NE(mesh_problem(flat).find("no volume"), std::string::npos) << mesh_problem(flat);
  // A solid cube holds nothing.
  geom::TriangleMesh cube = geom::unit_cube_mesh();
  for (auto& v : cube.vertices)
    for (double& x : v) x *= 0.1;
  EXPECT_NE(mesh_problem(cube).find("no cavity"), std::string::npos) << mesh_problem(cube);
}

TEST(ContainerMesh, SceneContainerFileAndErrorsNameTheFile) {
  nlohmann::json d = {{"pliant", 1}, {"kind", "liquid"}, {"dim", 2},
                      {"domain", {{"min_m", {-0.1, 0}}, {"max_m", {0.3, 0.3}}, {"cell_size_m", 0.008}}},
                      {"source", {{"container", kAssets + "/containers/mug.json"}, {"position_m", {0, 0.05}}}}};
  const LiquidModel m = liquid_compile(parse_scene(d.dump(), "scene.json"));
  EXPECT_EQ(m.source.shape.type, ContainerShape::Mesh);
  const LiquidState s = liquid_init(m);
  EXPECT_GT(s.count(), 100u);
  EXPECT_DOUBLE_EQ(liquid_fractions(m, s)[2], 1.0);  // seeded inside the mesh's cavity
  auto problem = [&](const nlohmann::json& container) {
    auto e = d;
    e["source"]["container"] = container;
    try {
      liquid_compile(parse_scene(e.dump(), "scene.json"));
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string();
  };
  const std::string open = problem({{"shape", "mesh"}, {"file", kMeshes + "open_box.obj"}});
  EXPECT_NE(open.find("/source/container/file"), std::string::npos) << open;
  EXPECT_NE(open.find("open_box.obj"), std::string::npos) << open;
  EXPECT_NE(open.find("not closed"), std::string::npos) << open;
  const std::string missing = problem({{"shape", "mesh"}, {"file", "no_such_mug.obj"}});
  EXPECT_NE(missing.find("no_such_mug.obj"), std::string::npos) << missing;
  EXPECT_NE(missing.find("cannot load mesh"), std::string::npos) << missing;
  const std::string garbage = problem({{"shape", "mesh"}, {"file", kMeshes + "garbage.obj"}});
  EXPECT_NE(garbage.find("garbage.obj"), std::string::npos) << garbage;
  const std::string thin = problem({{"shape", "mesh"}, {"file", kAssets + "/containers/mug.obj"}, {"scale", 0.5}});
  EXPECT_NE(thin.find("thinner than"), std::string::npos) << thin;
  const std::string extra = problem({{"shape", "mesh"}, {"file", kAssets + "/containers/mug.obj"}, {"radius_m", 1}});
  EXPECT_NE(extra.find("/source/container/radius_m"), std::string::npos) << extra;
}

TEST(ContainerMesh, FeedbackPlannerRefusesAMeshSource) {
  // The network one-hots the five analytic shapes; a mesh source would index past them.
  nlohmann::json d = {{"pliant", 1}, {"kind", "liquid"}, {"dim", 2},
                      {"domain", {{"min_m", {-0.1, 0}}, {"max_m", {0.3, 0.3}}, {"cell_size_m", 0.008}}},
                      {"source", {{"container", kAssets + "/containers/mug.json"}, {"position_m", {0, 0.05}}}},
                      {"target", {{"container", {{"shape", "box"}, {"radius_m", 0.05}, {"height_m", 0.06},
                                                 {"wall_m", 0.01}}},
                                  {"position_m", {0.2, 0.0}}}},
                      {"planner", {{"mode", "feedback"}}}};
  std::string msg;
  try {
    liquid_compile(parse_scene(d.dump(), "scene.json"));
  } catch (const InputError& err) {
    msg = err.what();
  }
  EXPECT_NE(msg.find("/planner/mode"), std::string::npos) << msg;
  EXPECT_NE(msg.find("analytic source shapes"), std::string::npos) << msg;
}

}  // namespace
}  // namespace pliant::liquid
