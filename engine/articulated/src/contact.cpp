// Contact candidates and obstacle distances (see contact.h for the force laws).
#include "pliant/articulated/contact.h"

#include <cmath>

namespace pliant::articulated {

std::vector<ContactPoint> contact_points(const Model& m) {
  std::vector<ContactPoint> pts;
  for (const Geom& g : m.geoms) {
    if (g.body == 0 || !g.contact) continue;
    const Mat3 r = g.quat.toRotationMatrix();
    switch (g.type) {
      case GeomType::Sphere: pts.push_back({g.body, g.pos, g.size[0]}); break;
      case GeomType::Capsule:
        for (int s : {-1, 1}) pts.push_back({g.body, g.pos + r.col(2) * (s * g.size[1]), g.size[0]});
        break;
      case GeomType::Box:
        for (int c = 0; c < 8; ++c) {
          const Vec3 corner((c & 1 ? 1 : -1) * g.size[0], (c & 2 ? 1 : -1) * g.size[1],
                            (c & 4 ? 1 : -1) * g.size[2]);
          pts.push_back({g.body, g.pos + r * corner, 0.0});
        }
        break;
      case GeomType::Plane: break;
    }
  }
  return pts;
}

std::vector<int> contact_obstacles(const Model& m) {
  std::vector<int> obs;
  for (size_t i = 0; i < m.geoms.size(); ++i)
    if (m.geoms[i].body == 0 && m.geoms[i].contact) obs.push_back(static_cast<int>(i));
  return obs;
}

double obstacle_distance(const Geom& g, const Vec3& x, Vec3* normal) {
  const Mat3 r = g.quat.toRotationMatrix();
  const Vec3 p = r.transpose() * (x - g.pos);
  switch (g.type) {
    case GeomType::Plane:
      *normal = r.col(2);
      return p.z();
    case GeomType::Sphere: {
      const double d = p.norm();
      *normal = d > 1e-12 ? Vec3(r * p / d) : Vec3(r.col(2));
      return d - g.size[0];
    }
    case GeomType::Box: {
      const Vec3 q = p.cwiseAbs() - g.size;
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
      const double h = std::clamp(p.z(), -g.size[1], g.size[1]);
      const Vec3 dp = p - Vec3(0, 0, h);
      const double d = dp.norm();
      *normal = d > 1e-12 ? Vec3(r * dp / d) : Vec3(r.col(0));
      return d - g.size[0];
    }
  }
  return 1e300;
}

void find_contacts(const Model& m, const Kinematics& k, const std::vector<ContactPoint>& pts,
                   const std::vector<int>& obs, std::vector<Contact>* out) {
  out->clear();
  const int no = static_cast<int>(obs.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const ContactPoint& cp = pts[i];
    const Vec3 c = k.xpos[cp.body] + k.xmat[cp.body] * cp.local;
    for (int o = 0; o < no; ++o) {
      Vec3 n;
      const double d = obstacle_distance(m.geoms[obs[o]], c, &n) - cp.radius;
      if (d >= 0) continue;
      Contact ct;
      ct.slot = static_cast<int>(i) * no + o;
      ct.body = cp.body;
      ct.point = c - cp.radius * n;
      ct.normal = n;
      ct.depth = -d;
      out->push_back(ct);
    }
  }
}

}  // namespace pliant::articulated
