// The articulated view's document-side pieces (no GL): the geometry the drawer
// gets from the engine's compile of a scene, and the drift figure of the
// "Compare integrators" legend.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "render/articulated_drawer.h"
#include "render/mesh_drawer.h"
#include "ui/articulated_panels.h"

namespace pliant::editor {
namespace {

using nlohmann::json;

json chain_scene() {
  auto capsule = json{{"type", "capsule"}, {"fromto", {0, 0, 0, 0.1, 0, 0}}, {"size", {0.015}}};
  return {{"pliant", 1},
          {"kind", "articulated"},
          {"name", "chain"},
          {"model",
           {{"bodies",
             {{{"name", "a"}, {"parent", "world"}, {"joints", {{{"type", "hinge"}, {"axis", {0, 1, 0}}}}},
               {"geoms", {capsule}}},
              {{"name", "b"},
               {"parent", "a"},
               {"pos", {0.1, 0, 0}},
               {"joints", {{{"type", "hinge"}, {"axis", {0, 1, 0}}}}},
               {"geoms", {capsule, {{"type", "box"}, {"pos", {0.12, 0, 0}}, {"size", {0.03, 0.03, 0.03}}}}}}}},
            {"obstacles", {{{"type", "plane"}, {"pos", {0, 0, -0.2}}}}}}}};
}

TEST(ArticulatedGeometry, ChainScene) {
  ArticulatedGeometry g;
  std::string err;
  ASSERT_TRUE(articulated_scene_geometry(chain_scene(), ".", &g, &err)) << err;
  EXPECT_EQ(g.bodies, 2);
  EXPECT_FALSE(g.floating);
  EXPECT_NEAR(g.gravity, 9.81, 1e-12);
  ASSERT_EQ(g.geoms.size(), 4u);  // two capsules, the box, the floor
  // Capsule (density 1000): cylinder pi r^2 L + sphere 4/3 pi r^3; box 0.06^3.
  const double r = 0.015, L = 0.1, pi = 3.14159265358979;
  const double capsule = 1000 * (pi * r * r * L + 4.0 / 3.0 * pi * r * r * r), box = 1000 * 0.06 * 0.06 * 0.06;
  EXPECT_NEAR(g.total_mass, 2 * capsule + box, 1e-9);
  int planes = 0;
  for (const ArticulatedGeom& geom : g.geoms) {
    if (geom.shape == ArticulatedGeom::Plane) {
      ++planes;
      EXPECT_EQ(geom.body, 0);
      EXPECT_FLOAT_EQ(geom.pos[2], -0.2f);
    }
    if (geom.shape == ArticulatedGeom::Capsule) {
      // fromto (0,0,0)-(0.1,0,0): centred at x = 0.05, half length 0.05, local z along x.
      EXPECT_FLOAT_EQ(geom.pos[0], 0.05f);
      EXPECT_FLOAT_EQ(geom.size[0], 0.015f);
      EXPECT_FLOAT_EQ(geom.size[1], 0.05f);
      const Mat4 m = pose_matrix({0, 0, 0}, geom.quat);
      EXPECT_NEAR(m[8], 1.0f, 1e-6f);  // column 2 (local z) = world x
      EXPECT_NEAR(m[9], 0.0f, 1e-6f);
      EXPECT_NEAR(m[10], 0.0f, 1e-6f);
    }
  }
  EXPECT_EQ(planes, 1);
}

TEST(ArticulatedGeometry, SlideRootIsFloating) {
  json s = chain_scene();
  s["model"]["bodies"][0]["joints"] = json::array({{{"type", "slide"}, {"axis", {1, 0, 0}}}});
  ArticulatedGeometry g;
  std::string err;
  ASSERT_TRUE(articulated_scene_geometry(s, ".", &g, &err)) << err;
  EXPECT_TRUE(g.floating);
}

TEST(ArticulatedGeometry, InvalidSceneNamesTheField) {
  json s = chain_scene();
  s["model"]["bodies"][1]["geoms"][1]["size"] = json::array({0.03});
  ArticulatedGeometry g;
  std::string err;
  EXPECT_FALSE(articulated_scene_geometry(s, ".", &g, &err));
  EXPECT_NE(err.find("/model/bodies/1/geoms/1/size"), std::string::npos) << err;
  s["model"] = "no_such_model.xml";
  EXPECT_FALSE(articulated_scene_geometry(s, ".", &g, &err));
  EXPECT_NE(err.find("/model"), std::string::npos) << err;
}

// Mesh geoms reach the drawer as their triangles (they were drawn as boxes of the
// geom's unused size before), for moving bodies and static obstacles alike.
TEST(ArticulatedGeometry, MeshGeomsCarryTheirTriangles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("pliant_art_geom_mesh_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    // A unit-ish tetrahedron, off its centre of mass: the compile re-centres the
    // vertices and moves the geom's pos to compensate.
    std::ofstream obj(dir / "tet.obj");
    obj << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  }
  json s = chain_scene();
  s["model"]["bodies"][1]["geoms"] = json::array({{{"type", "mesh"}, {"file", "tet.obj"}, {"mass", 0.2}}});
  s["model"]["obstacles"].push_back({{"type", "mesh"}, {"file", "tet.obj"}, {"pos", {0.5, 0, 0}}});
  ArticulatedGeometry g;
  std::string err;
  ASSERT_TRUE(articulated_scene_geometry(s, dir, &g, &err)) << err;
  int meshes = 0;
  for (const ArticulatedGeom& geom : g.geoms) {
    if (geom.shape != ArticulatedGeom::Mesh) continue;
    ++meshes;
    ASSERT_NE(geom.mesh, nullptr);
    ASSERT_EQ(geom.mesh->xyz.size(), 12u);
    ASSERT_EQ(geom.mesh->triangles.size(), 12u);
    // Centroid of the solid tetrahedron = mean of its vertices (0.025, 0.025, 0.025):
    // the stored vertices average to minus nothing, i.e. they are re-centred there.
    float mean[3] = {0, 0, 0}, r = 0;
    for (int v = 0; v < 4; ++v) {
      const float* p = geom.mesh->xyz.data() + 3 * v;
      for (int i = 0; i < 3; ++i) mean[i] += p[i] / 4;
      r = std::max(r, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
    }
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(mean[i], 0.0f, 1e-6f);
    EXPECT_FLOAT_EQ(geom.mesh->radius, r);
    EXPECT_NEAR(geom.mesh->radius, std::sqrt(0.075 * 0.075 + 2 * 0.025 * 0.025), 1e-6);
    for (uint32_t t : geom.mesh->triangles) EXPECT_LT(t, 4u);
  }
  EXPECT_EQ(meshes, 2);
  EXPECT_NEAR(g.total_mass, 1000 * (3.14159265358979 * 0.015 * 0.015 * 0.1 +
                                    4.0 / 3.0 * 3.14159265358979 * 0.015 * 0.015 * 0.015) + 0.2, 1e-9);
  std::filesystem::remove_all(dir);
}

TEST(ArticulatedCompare, DriftPercentOfTheExchangedEnergy) {
  IntegratorRun run;
  EXPECT_LT(run.drift_percent(), 0);  // no frames yet
  // A swing: kinetic 0 -> 2 J -> 0, potential 0 -> -2 J -> 0; total drifts to -0.1 J.
  for (int i = 0; i <= 20; ++i) {
    const float s = std::sin(3.14159265f * i / 20);
    const float drift = -0.1f * i / 20;
    run.time_s.push_back(0.01f * i);
    run.kinetic.push_back(2 * s * s);
    run.potential.push_back(-2 * s * s);  // (the drift left out: scale exactly 2 J)
    run.total.push_back(drift);
  }
  EXPECT_NEAR(run.drift_percent(), 100 * 0.1 / 2.0, 1e-3);
  // Conservative: no drift.
  for (float& t : run.total) t = 1.5f;
  EXPECT_NEAR(run.drift_percent(), 0.0, 1e-9);
}

}  // namespace
}  // namespace pliant::editor
