// Internals shared by the contact files: box corners, primitive signed distances, a geom
// at its world pose, and the body-body narrow-phase routines (contact_pair_primitives.cpp:
// sphere / capsule / box; contact_pair_meshes.cpp: with a mesh) that contact_pairs.cpp
// dispatches to.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "pliant/articulated/contact.h"

namespace pliant::articulated::contact_internal {

// Corner c (bit i set: + side on axis i) of a box with half sizes `half`, in its frame.
inline Vec3 box_corner(const Vec3& half, int c) {
  return Vec3((c & 1 ? 1 : -1) * half[0], (c & 2 ? 1 : -1) * half[1], (c & 4 ? 1 : -1) * half[2]);
}

// Signed distance (positive outside) of world point x from a plane, sphere, box or
// capsule placed at (c, r), with its outward normal.
inline double shape_distance(GeomType type, const Vec3& size, const Vec3& c, const Mat3& r, const Vec3& x, Vec3* normal) {
  const Vec3 p = r.transpose() * (x - c);
  switch (type) {
    case GeomType::Plane:
      *normal = r.col(2);
      return p.z();
    case GeomType::Sphere: {
      const double d = p.norm();
      *normal = d > 1e-12 ? Vec3(r * p / d) : Vec3(r.col(2));
      return d - size[0];
    }
    case GeomType::Box: {
      const Vec3 q = p.cwiseAbs() - size;
      const Vec3 sg(p.x() < 0 ? -1 : 1, p.y() < 0 ? -1 : 1, p.z() < 0 ? -1 : 1);
      if (q.maxCoeff() > 0) {
        const Vec3 out = q.cwiseMax(0.0).cwiseProduct(sg);
        const double d = out.norm();
        *normal = r * out / d;
        return d;
      }
      int a;
      const double d = q.maxCoeff(&a);
      *normal = r.col(a) * sg[a];
      return d;
    }
    case GeomType::Capsule: {
      const double h = std::clamp(p.z(), -size[1], size[1]);
      const Vec3 dp = p - Vec3(0, 0, h);
      const double d = dp.norm();
      *normal = d > 1e-12 ? Vec3(r * dp / d) : Vec3(r.col(0));
      return d - size[0];
    }
    case GeomType::Mesh: break;
  }
  return 1e300;
}

struct Placed {  // a geom at its world pose
  const Geom* g;
  Vec3 c;
  Mat3 r;
};

// Point x of body `body` (a sphere of radius `radius` about it) against geom s: a
// contact on body s.g->body (a) and `body` (b) along s's outward normal.
inline void point_against(const Placed& s, int body, const Vec3& x, double radius, std::vector<PairContact>* out) {
  Vec3 n;
  const double d = shape_distance(s.g->type, s.g->size, s.c, s.r, x, &n) - radius;
  if (d < 0) out->push_back({s.g->body, body, x - radius * n, n, -d});
}

// Closest points p0 + s d0, p1 + t d1 of two segments (s, t in [0, 1]; parallel: the
// middle of their overlap), contact_pair_primitives.cpp.
void segment_closest(const Vec3& p0, const Vec3& d0, const Vec3& p1, const Vec3& d1, double* s_out, double* t_out);

// Sphere / capsule / box pairs (contact_pair_primitives.cpp); the margin enters as extra
// radius (depth = margin - distance).
void corners_against(const Placed& box, const Placed& s, double margin, std::vector<PairContact>* out);
void end_spheres_against(const Placed& cap, const Placed& s, double margin, std::vector<PairContact>* out);
void capsule_capsule(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out);
// Capsule-box: end spheres, box edges and the segment's deepest point; box-box: corners
// and edges pressed into the other box (contact_segment_box.cpp).
// end_spheres false: a static box obstacle, whose end-sphere contacts the obstacle path has.
void capsule_box(const Placed& cap, const Placed& box, double margin, std::vector<PairContact>* out,
                 bool end_spheres = true);
void box_box(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out);

// Pairs with a mesh (contact_pair_meshes.cpp).
void mesh_against(const Placed& mesh, const MeshCollider& mc, const Placed& s, double margin,
                  std::vector<PairContact>* out);
// PairBroadphase's candidate pairs at k, ascending (contact_broadphase.cpp).
void broadphase_candidates(const Model& m, const Kinematics& k, const std::vector<GeomPair>& pairs,
                           PairBroadphase& bp);
void mesh_mesh(const Placed& a, const MeshCollider& ma, const Placed& b, const MeshCollider& mb, double margin,
               std::vector<PairContact>* out);

}  // namespace pliant::articulated::contact_internal
