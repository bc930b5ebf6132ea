// Container surfaces from signed distances (render/liquid_container_mesh.cpp):
// marching tetrahedra on a sphere gives a closed, consistently outward-wound
// mesh whose enclosed volume and vertex radii match the sphere; the 2D section
// of a circle has its circumference; a wall SDF of the liquid engine (through
// ui/liquid_scene_geometry.cpp) gives a surface inside its box.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "render/liquid_container_mesh.h"
#include "ui/liquid_scene_geometry.h"

namespace pliant::editor {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(LiquidContainerMesh, SphereIsClosedOutwardAndRound) {
  const double r = 0.3;
  auto sdf = [r](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z) - r; };
  const float step = 0.04f;
  TriangleMesh m = sdf_surface_mesh(sdf, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, step);
  ASSERT_GT(m.triangle_count(), 100u);
  // Closed: every undirected edge in exactly two triangles, once each way
  // (consistent winding).
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t t = 0; t < m.triangle_count(); ++t)
    for (int e = 0; e < 3; ++e) ++directed[{m.tris[3 * t + e], m.tris[3 * t + (e + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << edge.first << "-" << edge.second;
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "open edge " << edge.first << "-" << edge.second;
  }
  // Vertices on the sphere (linear interpolation error of a smooth SDF is tiny).
  for (size_t i = 0; i < m.vertex_count(); ++i) {
    const double d = std::sqrt(m.xyz[3 * i] * m.xyz[3 * i] + m.xyz[3 * i + 1] * m.xyz[3 * i + 1] +
                               m.xyz[3 * i + 2] * m.xyz[3 * i + 2]);
    EXPECT_NEAR(d, r, 0.01);
  }
  // Divergence theorem: volume = sum over triangles of a . (b x c) / 6, positive
  // for outward normals; the inscribed polyhedron is slightly smaller.
  double vol = 0;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const float* a = &m.xyz[3 * m.tris[3 * t]];
    const float* b = &m.xyz[3 * m.tris[3 * t + 1]];
    const float* c = &m.xyz[3 * m.tris[3 * t + 2]];
    vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
            a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
  }
  const double exact = 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_GT(vol, 0.95 * exact);
  EXPECT_LT(vol, 1.001 * exact);
}

TEST(LiquidContainerMesh, CircleSectionHasItsCircumference) {
  const double r = 0.2;
  auto sdf = [r](double x, double y, double) { return std::sqrt(x * x + y * y) - r; };
  const auto lines = sdf_section_lines(sdf, {-0.3f, -0.3f, 0}, {0.3f, 0.3f, 0}, 0.01f);
  double len = 0;
  for (const auto& s : lines) {
    len += std::hypot(s.bx - s.ax, s.by - s.ay);
    EXPECT_NEAR(std::hypot(s.ax, s.ay), r, 0.003);
  }
  EXPECT_NEAR(len, 2 * kPi * r, 0.01 * 2 * kPi * r);
}

#ifdef PLIANT_HAVE_LIQUID
TEST(LiquidContainerMesh, EngineContainerWallsFromSceneGeometry) {
  const nlohmann::json scene = {
      {"pliant", 1}, {"kind", "liquid"}, {"dim", 3},
      {"domain", {{"min_m", {-0.2, 0, -0.1}}, {"max_m", {0.3, 0.3, 0.1}}, {"cell_size_m", 0.01}}},
      {"time", {{"frames", 10}}},
      {"source", {{"container", {{"shape", "cup"}, {"radius_m", 0.04}, {"height_m", 0.1}, {"wall_m", 0.012}}},
                  {"position_m", {0, 0.1, 0}}}},
      {"target", {{"container", {{"shape", "cylinder"}, {"radius_m", 0.07}, {"height_m", 0.08}, {"wall_m", 0.012}}},
                  {"position_m", {0.2, 0, 0}}}}};
  LiquidSceneGeometry g;
  std::string err;
  ASSERT_TRUE(liquid_scene_geometry(scene, &g, &err)) << err;
  EXPECT_EQ(g.dim, 3);
  ASSERT_TRUE(g.has_source && g.has_target);
  EXPECT_EQ(g.source_path.size(), 11u);
  EXPECT_FLOAT_EQ(g.target_pose[0], 0.2f);
  // Inside the cup's side wall: negative; in the cavity and outside: positive.
  EXPECT_LT(g.source.wall_sdf(0.046, 0.05, 0), 0);
  EXPECT_GT(g.source.wall_sdf(0, 0.05, 0), 0);
  EXPECT_GT(g.source.wall_sdf(0.3, 0.05, 0), 0);
  TriangleMesh m = sdf_surface_mesh(g.source.wall_sdf, g.source.lo, g.source.hi, g.source.step);
  ASSERT_GT(m.triangle_count(), 500u);
  // The handle reaches out on +x beyond the wall; nothing leaves the box.
  float max_x = -1;
  for (size_t i = 0; i < m.vertex_count(); ++i) {
    max_x = std::max(max_x, m.xyz[3 * i]);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(m.xyz[3 * i + a], g.source.lo[a]);
      EXPECT_LE(m.xyz[3 * i + a], g.source.hi[a]);
    }
  }
  EXPECT_GT(max_x, 0.04 + 0.012 + 0.01);
  EXPECT_LT(max_x, g.source.hi[0] - g.source.step);  // the box is not cutting the handle
}
#endif

}  // namespace
}  // namespace pliant::editor
