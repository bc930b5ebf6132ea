// Picking articulated bodies (render/articulated_pick.cpp, no GL): rays against
// sphere, capsule, box and triangle mesh checked against hits worked out by
// hand; a box-shaped mesh against the slab test for many rays (a second
// method); posed geoms, the nearest body along a ray, occlusion by an obstacle;
// signed distances and the sides of a contact.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "render/articulated_pick.h"

namespace pliant::editor {
namespace {

// The box [-hx, hx] x [-hy, hy] x [-hz, hz] as 12 outward triangles.
std::shared_ptr<ArticulatedMesh> pick_test_box_mesh(float hx, float hy, float hz) {
  auto m = std::make_shared<ArticulatedMesh>();
  for (int i = 0; i < 8; ++i) {
    m->xyz.push_back(i & 1 ? hx : -hx);
    m->xyz.push_back(i & 2 ? hy : -hy);
    m->xyz.push_back(i & 4 ? hz : -hz);
  }
  // Faces as corner quads (counter-clockwise seen from outside).
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads)
    for (uint32_t t : {q[0], q[1], q[2], q[0], q[2], q[3]}) m->triangles.push_back(t);
  m->radius = std::sqrt(hx * hx + hy * hy + hz * hz);
  return m;
}

TEST(ArticulatedPick, SphereHitsWhereTheRayEntersAndLeavesFromInside) {
  EXPECT_NEAR(ray_sphere({-5, 0, 0}, {1, 0, 0}, 1), 4, 1e-12);
  EXPECT_NEAR(ray_sphere({-5, 0, 0}, {2, 0, 0}, 1), 2, 1e-12);  // t in units of d
  EXPECT_NEAR(ray_sphere({0, 0, 0}, {0, 1, 0}, 1), 1, 1e-12);   // from inside: where it leaves
  // Off-centre by 0.6: enters at x = -0.8.
  EXPECT_NEAR(ray_sphere({-5, 0.6f, 0}, {1, 0, 0}, 1), 5 - 0.8, 1e-6);
  EXPECT_LT(ray_sphere({-5, 1.01f, 0}, {1, 0, 0}, 1), 0);
  EXPECT_LT(ray_sphere({5, 0, 0}, {1, 0, 0}, 1), 0);  // behind the origin
}

TEST(ArticulatedPick, CapsuleSideAndCaps) {
  const double r = 0.5, h = 1;  // axis z, segment z in [-1, 1]
  EXPECT_NEAR(ray_capsule({-5, 0, 0.3f}, {1, 0, 0}, r, h), 4.5, 1e-6);  // the side
  // Past the segment's end: the cap sphere at z = 1, 0.2 above its centre.
  EXPECT_NEAR(ray_capsule({-5, 0, 1.2f}, {1, 0, 0}, r, h), 5 - std::sqrt(0.25 - 0.04), 1e-6);
  EXPECT_NEAR(ray_capsule({0, 0, 5}, {0, 0, -1}, r, h), 3.5, 1e-6);  // along the axis onto the top
  EXPECT_NEAR(ray_capsule({0.3f, 0, -5}, {0, 0, 1}, r, h), 5 - 1 - std::sqrt(0.25 - 0.09), 1e-6);
  EXPECT_LT(ray_capsule({-5, 0, 1.6f}, {1, 0, 0}, r, h), 0);
  EXPECT_LT(ray_capsule({-5, 0.6f, 0}, {1, 0, 0}, r, h), 0);
}

TEST(ArticulatedPick, BoxSlabsAndObliqueRays) {
  const Vec3 half{1, 2, 3};
  EXPECT_NEAR(ray_box({-5, 0.5f, 0.5f}, {2, 0, 0}, half), 2, 1e-12);
  EXPECT_NEAR(ray_box({0, 0, 10}, {0.1f, 0.1f, -1}, half), 7, 1e-6);  // top face at (0.7, 0.7, 3)
  EXPECT_NEAR(ray_box({0, 0, 0}, {0, 1, 0}, half), 2, 1e-12);         // from inside
  EXPECT_LT(ray_box({5, 5, 0}, {1, 0, 0}, half), 0);
  EXPECT_LT(ray_box({0, 0, 10}, {0.5f, 0, -1}, half), 0);  // passes beside: x = 3.5 at the top
}

TEST(ArticulatedPick, MeshMatchesTheBoxForManyRays) {
  const auto mesh = pick_test_box_mesh(0.3f, 0.5f, 0.7f);
  const Vec3 half{0.3f, 0.5f, 0.7f};
  EXPECT_NEAR(ray_mesh({-2, 0.1f, 0.2f}, {1, 0, 0}, *mesh), 1.7, 1e-6);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 o{3 * u(rng), 3 * u(rng), 3 * u(rng)};
    const Vec3 target{0.5f * u(rng), 0.7f * u(rng), 0.9f * u(rng)};
    const Vec3 d{target[0] - o[0], target[1] - o[1], target[2] - o[2]};
    const double tb = ray_box(o, d, half), tm = ray_mesh(o, d, *mesh);
    ASSERT_EQ(tb < 0, tm < 0) << i;
    if (tb >= 0) {
      EXPECT_NEAR(tm, tb, 1e-5) << i;
      ++hits;
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(ArticulatedPick, NearestPosedBodyAlongTheRayAndObstaclesOcclude) {
  ArticulatedGeometry model;
  model.bodies = 2;
  // Body 1: a capsule along its geom's z, turned by 90 degrees about y (lies along x).
  ArticulatedGeom cap;
  cap.shape = ArticulatedGeom::Capsule;
  cap.body = 1;
  cap.quat = {std::sqrt(0.5f), 0, std::sqrt(0.5f), 0};
  cap.size = {0.1f, 1.0f, 0};
  ArticulatedGeom ball;
  ball.shape = ArticulatedGeom::Sphere;
  ball.body = 2;
  ball.size = {0.2f, 0, 0};
  model.geoms = {cap, ball};
  std::vector<Vec3> pos = {{0, 0, 0}, {0, 0, 1}, {0.8f, 0, 0}};
  std::vector<Quat4> quat(3, Quat4{1, 0, 0, 0});
  // Down the z axis at x = 0.8: the capsule (top at z 1.1) before the ball (top at 0.2).
  ArticulatedPick p = articulated_pick(model, pos, quat, {0.8f, 0, 5}, {0, 0, -1});
  EXPECT_EQ(p.body, 1);
  EXPECT_NEAR(p.t, 5 - 1.1, 1e-5);
  // Beyond the capsule's end (it reaches x = 1.1) and the ball's (x = 1.0): nothing.
  EXPECT_EQ(articulated_pick(model, pos, quat, {1.25f, 0, 5}, {0, 0, -1}).body, -1);
  p = articulated_pick(model, pos, quat, {0.8f, 3, 0}, {0, -1, 0});
  EXPECT_EQ(p.body, 2);
  EXPECT_NEAR(p.t, 2.8, 1e-5);
  // Moving body 1 up by 1 along y through its pose: the ray down z at y = 0 misses it.
  pos[1] = {0, 1, 1};
  EXPECT_EQ(articulated_pick(model, pos, quat, {-0.5f, 0, 5}, {0, 0, -1}).body, -1);
  EXPECT_EQ(articulated_pick(model, pos, quat, {-0.5f, 1, 5}, {0, 0, -1}).body, 1);
  // A static box between the camera and the ball hides it.
  ArticulatedGeom wall;
  wall.shape = ArticulatedGeom::Box;
  wall.body = 0;
  wall.pos = {0.8f, 1.5f, 0};
  wall.size = {0.5f, 0.05f, 0.5f};
  model.geoms.push_back(wall);
  p = articulated_pick(model, pos, quat, {0.8f, 3, 0}, {0, -1, 0});
  EXPECT_EQ(p.body, 0);
  EXPECT_NEAR(p.t, 3 - 1.55, 1e-5);
}

TEST(ArticulatedPick, SignedDistancesAndContactSides) {
  ArticulatedGeom box;
  box.shape = ArticulatedGeom::Box;
  box.body = 1;
  box.size = {0.3f, 0.5f, 0.7f};
  ArticulatedGeom mesh = box;
  mesh.shape = ArticulatedGeom::Mesh;
  mesh.mesh = pick_test_box_mesh(0.3f, 0.5f, 0.7f);
  const GeomPose at{{1, 2, 3}, {1, 0, 0, 0}};
  for (const Vec3 p : {Vec3{2, 2, 3}, Vec3{1, 2, 3.5f}, Vec3{1.5f, 2.8f, 4}, Vec3{1.2f, 2.1f, 2.9f}}) {
    const double sb = geom_signed_distance(box, at, p), sm = geom_signed_distance(mesh, at, p);
    EXPECT_NEAR(sm, sb, 1e-5) << p[0] << " " << p[1] << " " << p[2];
  }
  EXPECT_NEAR(geom_signed_distance(box, at, {2, 2, 3}), 0.7, 1e-6);
  EXPECT_NEAR(geom_signed_distance(box, at, {1, 2, 3.5f}), -0.2, 1e-6);
  ArticulatedGeom cap;
  cap.shape = ArticulatedGeom::Capsule;
  cap.size = {0.1f, 0.5f, 0};
  EXPECT_NEAR(geom_signed_distance(cap, {}, {0.3f, 0, 0.2f}), 0.2, 1e-6);
  EXPECT_NEAR(geom_signed_distance(cap, {}, {0, 0, 0.9f}), 0.3, 1e-6);

  // A ball (body 1, radius 0.1) sunk 0.01 into the floor plane z = 0: the take's
  // contact point is the ball's lowest point.
  ArticulatedGeometry model;
  model.bodies = 1;
  ArticulatedGeom ball;
  ball.shape = ArticulatedGeom::Sphere;
  ball.body = 1;
  ball.size = {0.1f, 0, 0};
  ArticulatedGeom floor;
  floor.shape = ArticulatedGeom::Plane;
  model.geoms = {floor, ball};
  const std::vector<Vec3> pos = {{0, 0, 0}, {0.4f, 0, 0.09f}};
  const std::vector<Quat4> quat(2, Quat4{1, 0, 0, 0});
  const ContactSides s = articulated_contact_sides(model, pos, quat, {0.4f, 0, -0.01f}, 0.01);
  EXPECT_EQ(s.body, 1);
  EXPECT_EQ(s.geom, 1);
  EXPECT_EQ(s.other_body, 0);
  EXPECT_EQ(s.other_geom, 0);
}

}  // namespace
}  // namespace pliant::editor
