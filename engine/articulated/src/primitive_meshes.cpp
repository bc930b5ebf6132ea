// Closed, outward-facing triangle meshes standing in for MJCF cylinders and ellipsoids
// in contact (Geom::tessellates): Pliant's contact handles spheres, capsules, boxes and
// meshes, so these shapes take the mesh path (samples on the surface against obstacles
// and other bodies) while their mass properties stay exact (model.cpp).
#include <cmath>

#include "pliant/articulated/io.h"

namespace pliant::articulated {

// Radius r, half-height h along local z; `segments` around (a rim point every
// 2 pi / segments: the flats' midpoints lie r (1 - cos(pi / segments)) inside).
MeshShape cylinder_mesh(double r, double h, int segments) {
  MeshShape m;
  for (int k = 0; k < segments; ++k) {
    const double a = 2 * M_PI * k / segments;
    for (double z : {-h, h}) m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  const int bottom = static_cast<int>(m.vertices.size()), top = bottom + 1;
  m.vertices.emplace_back(0, 0, -h);
  m.vertices.emplace_back(0, 0, h);
  for (int k = 0; k < segments; ++k) {
    const int b0 = 2 * k, t0 = b0 + 1, b1 = 2 * ((k + 1) % segments), t1 = b1 + 1;
    m.triangles.push_back({b0, b1, t1});
    m.triangles.push_back({b0, t1, t0});
    m.triangles.push_back({bottom, b1, b0});
    m.triangles.push_back({top, t0, t1});
  }
  return m;
}

// Radii a, b, c along local x, y, z: a latitude-longitude sphere scaled per axis.
MeshShape ellipsoid_mesh(const Vec3& radii, int rings, int segments) {
  MeshShape m;
  m.vertices.emplace_back(0, 0, -radii.z());
  for (int i = 1; i < rings; ++i) {
    const double t = M_PI * i / rings - M_PI / 2;
    for (int k = 0; k < segments; ++k) {
      const double a = 2 * M_PI * k / segments;
      m.vertices.emplace_back(radii.x() * std::cos(t) * std::cos(a), radii.y() * std::cos(t) * std::sin(a),
                              radii.z() * std::sin(t));
    }
  }
  const int north = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, radii.z());
  const auto at = [segments](int ring, int k) { return 1 + (ring - 1) * segments + (k % segments); };
  for (int k = 0; k < segments; ++k) {
    m.triangles.push_back({0, at(1, k + 1), at(1, k)});
    m.triangles.push_back({north, at(rings - 1, k), at(rings - 1, k + 1)});
    for (int i = 1; i + 1 < rings; ++i) {
      m.triangles.push_back({at(i, k), at(i, k + 1), at(i + 1, k + 1)});
      m.triangles.push_back({at(i, k), at(i + 1, k + 1), at(i + 1, k)});
    }
  }
  return m;
}

}  // namespace pliant::articulated
