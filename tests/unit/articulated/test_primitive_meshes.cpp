// Cylinder and ellipsoid tessellations (primitive_meshes.cpp): closed, outward-facing,
// close to the exact shape; as MJCF geoms they rest on the ground where the shape does.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"

namespace pliant::articulated {
namespace {

TEST(PrimitiveMeshes, TessellationsAreClosedOutwardAndNearTheExactVolume) {
  double v = 0;
  Vec3 centre;
  mesh_volume_moments(cylinder_mesh(0.04, 0.06), &v, &centre, nullptr);
  const double cylinder = M_PI * 0.04 * 0.04 * 0.12;
  // A 32-gon prism: (32 / 2 pi) sin(2 pi / 32) of the cylinder.
  EXPECT_NEAR(v / cylinder, 32 / (2 * M_PI) * std::sin(2 * M_PI / 32), 1e-12);
  EXPECT_LT(centre.norm(), 1e-12);
  mesh_volume_moments(ellipsoid_mesh(Vec3(0.03, 0.05, 0.02)), &v, &centre, nullptr);
  const double ellipsoid = 4.0 / 3.0 * M_PI * 0.03 * 0.05 * 0.02;
  EXPECT_GT(v / ellipsoid, 0.97);  // inscribed: below the exact volume, and positive (outward)
  EXPECT_LT(v / ellipsoid, 1.0);
  EXPECT_LT(centre.norm(), 1e-12);
  // Every edge is shared by exactly two triangles, in opposite directions (closed).
  for (const MeshShape& m : {cylinder_mesh(1, 2, 7), ellipsoid_mesh(Vec3(1, 2, 3), 5, 6)}) {
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : edges) {
      EXPECT_EQ(n, 1);
      EXPECT_EQ(edges.count({e.second, e.first}), 1u);
    }
  }
}

// Dropped 2 cm onto the plane: the upright cylinder rests on its end face at its
// half-height, the ellipsoid at its z radius (its lowest vertex is the pole), both at
// the penalty depth m g / (n k) below.
TEST(PrimitiveMeshes, CylinderAndEllipsoidRestOnTheGroundAtTheirHeights) {
  for (const char* geom : {R"(type="cylinder" size="0.04 0.06")", R"(type="ellipsoid" size="0.03 0.05 0.02")"}) {
    const double rest = std::string(geom).find("cylinder") != std::string::npos ? 0.06 : 0.02;
    const Model m = model_from_mjcf(std::string("<mujoco><worldbody><geom type=\"plane\" size=\"1 1 0.1\"/>"
                                                "<body pos=\"0 0 ") + std::to_string(rest + 0.02) +
                                        "\"><freejoint/><geom " + geom + "/></body></worldbody></mujoco>",
                                    "drop.xml");
    ASSERT_EQ(m.geoms[1].type, GeomType::Mesh);
    SimOptions o;
    o.dt = 0.01;
    State s = state_init(m);
    SimWorkspace ws;
    for (int i = 0; i < 150; ++i) ASSERT_TRUE(sim_step(m, o, s, ws));
    EXPECT_NEAR(s.qpos[2], rest, 2e-3) << geom;
    EXPECT_LT(s.qpos[2], rest) << geom;     // pressed into the ground, not hovering
    EXPECT_LT(s.qvel.norm(), 0.02) << geom;  // at rest
    EXPECT_NEAR(s.qpos[3], 1, 1e-3) << geom;  // upright
  }
}

}  // namespace
}  // namespace pliant::articulated
