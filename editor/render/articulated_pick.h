// Picking articulated bodies (no GL): a camera ray against the drawn geoms
// (sphere, capsule, box, triangle mesh) posed by a frame's body poses, and the
// signed distance of a point to a posed geom, which tells which body a take's
// contact point lies on (takes store only the point and the force).
// Everything is in the engine's world frame (z-up), metres.
#pragma once
#include <array>
#include <vector>

#include "render/articulated_drawer.h"

namespace pliant::editor {

using Quat4 = std::array<float, 4>;  // w x y z

// Smallest t >= 0 with o + t d on the shape's surface (the shape in its own
// frame), or -1 when the ray misses it; d need not be unit (t is in units of d).
// A ray starting inside a shape hits it where it leaves.
double ray_sphere(const Vec3& o, const Vec3& d, double radius);
double ray_capsule(const Vec3& o, const Vec3& d, double radius, double half_length);  // axis local z
double ray_box(const Vec3& o, const Vec3& d, const Vec3& half);
double ray_mesh(const Vec3& o, const Vec3& d, const ArticulatedMesh& mesh);  // both faces of each triangle

// World pose of a geom: body pose * geom pose. pos/quat are indexed by body,
// [0] the world (identity).
struct GeomPose {
  Vec3 pos{0, 0, 0};
  Quat4 quat{1, 0, 0, 0};
};
GeomPose articulated_geom_pose(const ArticulatedGeom& g, const std::vector<Vec3>& pos,
                               const std::vector<Quat4>& quat);

// t of a world ray against one posed geom (-1: missed; planes are never hit).
double ray_geom(const ArticulatedGeom& g, const GeomPose& pose, const Vec3& o, const Vec3& d);

// Nearest geom along the ray: body >= 1 a moving body, 0 a static obstacle
// (it hides the bodies behind it), -1 nothing hit.
struct ArticulatedPick {
  int body = -1, geom = -1;
  double t = -1;
};
ArticulatedPick articulated_pick(const ArticulatedGeometry& model, const std::vector<Vec3>& pos,
                                 const std::vector<Quat4>& quat, const Vec3& o, const Vec3& d);

// Signed distance (positive outside) of world point p to a posed geom; planes
// by their local z, meshes by the nearest triangle with its face normal's sign.
double geom_signed_distance(const ArticulatedGeom& g, const GeomPose& pose, const Vec3& p);

// The body a take contact (point, penetration depth) lies on: the moving geom
// whose surface is nearest to the point; the other side is the geom of another
// body or a static obstacle whose signed distance is nearest to -depth.
struct ContactSides {
  int body = -1, geom = -1;              // -1: no moving geom
  int other_body = -1, other_geom = -1;  // other_body 0: a static obstacle
};
ContactSides articulated_contact_sides(const ArticulatedGeometry& model, const std::vector<Vec3>& pos,
                                       const std::vector<Quat4>& quat, const Vec3& point, double depth);

}  // namespace pliant::editor
