// Ray casts and point distances against posed articulated geoms (see the
// header). Double precision inside: the poses are floats, but a ray hitting a
// thin capsule edge-on must not lose its root to cancellation.
#include "render/articulated_pick.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pliant::editor {

namespace {

struct D3 {
  double x = 0, y = 0, z = 0;
};
D3 d3(const Vec3& v) { return {v[0], v[1], v[2]}; }
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(double s, const D3& a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

struct DQuat {
  double w = 1, x = 0, y = 0, z = 0;
};
DQuat dquat(const Quat4& q) {
  const double n = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
  if (!(n > 0)) return {};
  return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}
DQuat mul(const DQuat& a, const DQuat& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
// v' = q v q*: v + 2 w (u x v) + 2 u x (u x v), u the vector part.
D3 rotate(const DQuat& q, const D3& v) {
  const D3 u{q.x, q.y, q.z};
  const D3 c = cross(u, v);
  return v + 2 * q.w * c + 2.0 * cross(u, c);
}
D3 rotate_inv(const DQuat& q, const D3& v) { return rotate({q.w, -q.x, -q.y, -q.z}, v); }

constexpr double kMiss = -1;

// Smallest root t >= 0 of a t^2 + 2 b t + c = 0 (a > 0), or kMiss.
double first_root(double a, double b, double c) {
  const double disc = b * b - a * c;
  if (disc < 0 || !(a > 0)) return kMiss;
  const double s = std::sqrt(disc);
  const double t0 = (-b - s) / a, t1 = (-b + s) / a;
  return t0 >= 0 ? t0 : t1 >= 0 ? t1 : kMiss;
}

double keep_nearest(double best, double t) { return t >= 0 && (best < 0 || t < best) ? t : best; }

double sphere_hit(const D3& o, const D3& d, double r) { return first_root(dot(d, d), dot(o, d), dot(o, o) - r * r); }

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
D3 closest_on_triangle(const D3& p, const D3& a, const D3& b, const D3& c) {
  const D3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const D3 bp = p - b;
  const double d3v = dot(ab, bp), d4 = dot(ac, bp);
  if (d3v >= 0 && d4 <= d3v) return b;
  const double vc = d1 * d4 - d3v * d2;
  if (vc <= 0 && d1 >= 0 && d3v <= 0) return a + (d1 / (d1 - d3v)) * ab;
  const D3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3v * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3v) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3v) / ((d4 - d3v) + (d5 - d6))) * (c - b);
  const double den = 1 / (va + vb + vc);
  return a + (vb * den) * ab + (vc * den) * ac;
}

D3 vertex(const ArticulatedMesh& m, uint32_t i) { return {m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]}; }

}  // namespace

double ray_sphere(const Vec3& o, const Vec3& d, double radius) { return sphere_hit(d3(o), d3(d), radius); }

double ray_capsule(const Vec3& o3, const Vec3& d3v, double r, double h) {
  const D3 o = d3(o3), d = d3(d3v);
  double best = kMiss;
  // The side: the infinite cylinder x^2 + y^2 = r^2 where |z| <= h.
  const double a = d.x * d.x + d.y * d.y;
  if (a > 0) {
    const double b = o.x * d.x + o.y * d.y, c = o.x * o.x + o.y * o.y - r * r;
    const double disc = b * b - a * c;
    if (disc >= 0) {
      const double s = std::sqrt(disc);
      for (double t : {(-b - s) / a, (-b + s) / a})
        if (t >= 0 && std::fabs(o.z + t * d.z) <= h) best = keep_nearest(best, t);
    }
  }
  // The caps: spheres at the segment's ends (their inner halves lie inside the side).
  for (double zc : {-h, h}) best = keep_nearest(best, sphere_hit(o - D3{0, 0, zc}, d, r));
  return best;
}

double ray_box(const Vec3& o, const Vec3& d, const Vec3& half) {
  // Slabs (Kay-Kajiya): the interval of t inside all three.
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (std::fabs(o[i]) > half[i]) return kMiss;
      continue;
    }
    double t0 = (-half[i] - double(o[i])) / d[i], t1 = (half[i] - double(o[i])) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  if (hi < lo || hi < 0) return kMiss;
  return lo >= 0 ? lo : hi;
}

double ray_mesh(const Vec3& o3, const Vec3& d3v, const ArticulatedMesh& m) {
  // Moller-Trumbore per triangle, no back-face culling (a ray from inside
  // still finds the surface).
  const D3 o = d3(o3), d = d3(d3v);
  double best = kMiss;
  for (size_t k = 0; k + 2 < m.triangles.size(); k += 3) {
    const D3 a = vertex(m, m.triangles[k]), e1 = vertex(m, m.triangles[k + 1]) - a,
             e2 = vertex(m, m.triangles[k + 2]) - a;
    const D3 p = cross(d, e2);
    const double det = dot(e1, p);
    if (std::fabs(det) < 1e-300) continue;
    const double inv = 1 / det;
    const D3 s = o - a;
    const double u = dot(s, p) * inv;
    if (u < 0 || u > 1) continue;
    const D3 q = cross(s, e1);
    const double v = dot(d, q) * inv;
    if (v < 0 || u + v > 1) continue;
    best = keep_nearest(best, dot(e2, q) * inv);
  }
  return best;
}

GeomPose articulated_geom_pose(const ArticulatedGeom& g, const std::vector<Vec3>& pos,
                               const std::vector<Quat4>& quat) {
  const bool posed = g.body > 0 && size_t(g.body) < pos.size() && size_t(g.body) < quat.size();
  const DQuat qb = posed ? dquat(quat[g.body]) : DQuat{};
  const D3 pb = posed ? d3(pos[g.body]) : D3{};
  const D3 p = pb + rotate(qb, d3(g.pos));
  const DQuat q = mul(qb, dquat(g.quat));
  return {{float(p.x), float(p.y), float(p.z)}, {float(q.w), float(q.x), float(q.y), float(q.z)}};
}

double ray_geom(const ArticulatedGeom& g, const GeomPose& pose, const Vec3& o, const Vec3& d) {
  const DQuat q = dquat(pose.quat);
  const D3 lo = rotate_inv(q, d3(o) - d3(pose.pos)), ld = rotate_inv(q, d3(d));
  const Vec3 ol{float(lo.x), float(lo.y), float(lo.z)}, dl{float(ld.x), float(ld.y), float(ld.z)};
  switch (g.shape) {
    case ArticulatedGeom::Sphere: return sphere_hit(lo, ld, g.size[0]);
    case ArticulatedGeom::Capsule: return ray_capsule(ol, dl, g.size[0], g.size[1]);
    case ArticulatedGeom::Box: return ray_box(ol, dl, g.size);
    case ArticulatedGeom::Mesh: return g.mesh ? ray_mesh(ol, dl, *g.mesh) : kMiss;
    case ArticulatedGeom::Plane: return kMiss;
  }
  return kMiss;
}

ArticulatedPick articulated_pick(const ArticulatedGeometry& model, const std::vector<Vec3>& pos,
                                 const std::vector<Quat4>& quat, const Vec3& o, const Vec3& d) {
  ArticulatedPick best;
  for (size_t i = 0; i < model.geoms.size(); ++i) {
    const ArticulatedGeom& g = model.geoms[i];
    const double t = ray_geom(g, articulated_geom_pose(g, pos, quat), o, d);
    if (t >= 0 && (best.t < 0 || t < best.t)) best = {g.body, int(i), t};
  }
  return best;
}

double geom_signed_distance(const ArticulatedGeom& g, const GeomPose& pose, const Vec3& p) {
  const D3 x = rotate_inv(dquat(pose.quat), d3(p) - d3(pose.pos));
  switch (g.shape) {
    case ArticulatedGeom::Plane: return x.z;
    case ArticulatedGeom::Sphere: return std::sqrt(dot(x, x)) - g.size[0];
    case ArticulatedGeom::Capsule: {
      const double h = g.size[1];
      const D3 c{0, 0, std::clamp(x.z, -h, h)};
      const D3 e = x - c;
      return std::sqrt(dot(e, e)) - g.size[0];
    }
    case ArticulatedGeom::Box: {
      // Outside: distance to the box; inside: minus the distance to the nearest face.
      D3 q{std::fabs(x.x) - g.size[0], std::fabs(x.y) - g.size[1], std::fabs(x.z) - g.size[2]};
      const D3 out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
      return std::sqrt(dot(out, out)) + std::min(std::max({q.x, q.y, q.z}), 0.0);
    }
    case ArticulatedGeom::Mesh: {
      if (!g.mesh || g.mesh->triangles.empty()) return std::numeric_limits<double>::infinity();
      const ArticulatedMesh& m = *g.mesh;
      double best = std::numeric_limits<double>::infinity(), sign = 1;
      for (size_t k = 0; k + 2 < m.triangles.size(); k += 3) {
        const D3 a = vertex(m, m.triangles[k]), b = vertex(m, m.triangles[k + 1]), c = vertex(m, m.triangles[k + 2]);
        const D3 e = x - closest_on_triangle(x, a, b, c);
        const double dd = dot(e, e);
        if (dd < best) {
          best = dd;
          sign = dot(e, cross(b - a, c - a)) < 0 ? -1 : 1;
        }
      }
      return sign * std::sqrt(best);
    }
  }
  return std::numeric_limits<double>::infinity();
}

ContactSides articulated_contact_sides(const ArticulatedGeometry& model, const std::vector<Vec3>& pos,
                                       const std::vector<Quat4>& quat, const Vec3& point, double depth) {
  ContactSides s;
  std::vector<double> sd(model.geoms.size());
  double on = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < model.geoms.size(); ++i) {
    const ArticulatedGeom& g = model.geoms[i];
    sd[i] = geom_signed_distance(g, articulated_geom_pose(g, pos, quat), point);
    if (g.body > 0 && std::fabs(sd[i]) < on) {
      on = std::fabs(sd[i]);
      s.body = g.body;
      s.geom = int(i);
    }
  }
  if (s.body < 0) return s;
  double off = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < model.geoms.size(); ++i) {
    const ArticulatedGeom& g = model.geoms[i];
    if (g.body == s.body) continue;
    const double e = std::fabs(sd[i] + depth);
    if (e < off) {
      off = e;
      s.other_body = g.body;
      s.other_geom = int(i);
    }
  }
  return s;
}

}  // namespace pliant::editor
