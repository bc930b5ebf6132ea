// Contact candidates and obstacle distances: body points against world obstacles (see
// contact.h for the force laws; body-body pairs: contact_pairs.cpp).
#include "pliant/articulated/contact.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "contact_internal.h"

namespace pliant::articulated {

using contact_internal::box_corner;
using contact_internal::shape_distance;

bool geom_contact_params_set(const Model& m) {
  for (const Geom& g : m.geoms)
    if (g.friction >= 0 || g.margin != 0 || g.condim != 3 || g.priority != 0) return true;
  return false;
}

std::vector<Vec3> mesh_contact_samples(const MeshShape& mesh) {
  std::vector<Vec3> out(mesh.vertices.begin(), mesh.vertices.end());
  if (mesh.vertices.empty()) return out;
  Vec3 lo = mesh.vertices[0], hi = lo;
  for (const Vec3& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double spacing = (hi - lo).maxCoeff() / kMeshSamplesPerExtent;
  if (!(spacing > 0)) return out;
  // Edges once each (shared by two faces), then each face's interior grid.
  std::map<std::pair<int, int>, bool> edges;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const int a = std::min(t[e], t[(e + 1) % 3]), b = std::max(t[e], t[(e + 1) % 3]);
      if (!edges.emplace(std::make_pair(a, b), true).second) continue;
      const Vec3 &va = mesh.vertices[a], &vb = mesh.vertices[b];
      const int n = static_cast<int>(std::ceil((vb - va).norm() / spacing - 1e-9));
      for (int i = 1; i < n; ++i) out.push_back(va + (vb - va) * (double(i) / n));
    }
  // Face grid a + (i/nb)(b - a) + (j/nc)(c - a), strictly inside: cells of at most
  // one spacing along both edges from a, so thin triangles get few points.
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const int nb = static_cast<int>(std::ceil((b - a).norm() / spacing - 1e-9));
    const int nc = static_cast<int>(std::ceil((c - a).norm() / spacing - 1e-9));
    for (int i = 1; i < nb; ++i)
      for (int j = 1; double(i) / nb + double(j) / nc < 1 - 1e-9; ++j)
        out.push_back(a + (b - a) * (double(i) / nb) + (c - a) * (double(j) / nc));
  }
  return out;
}

namespace {
// A cylinder's or ellipsoid's points for plane `plane` (contact.h, PointRole::Plane):
// the ellipsoid's support point; the cylinder's two rims' and its cap rings.
void add_plane_points(const Geom& g, int gi, int plane, std::vector<ContactPoint>* pts) {
  const auto add = [&](PointSupport s, const Vec3& local) {
    ContactPoint cp{g.body, local, 0.0, gi};
    cp.role = PointRole::Plane;
    cp.support = s;
    cp.plane = plane;
    pts->push_back(cp);
  };
  if (g.tessellates == Geom::Tessellated::Ellipsoid) {
    add(PointSupport::Ellipsoid, g.pos);
    return;
  }
  const Mat3 r = g.quat.toRotationMatrix();
  for (int cap : {-1, 1}) {
    add(cap < 0 ? PointSupport::RimLow : PointSupport::RimHigh, g.pos);
    for (int i = 0; i < kCapRingPoints; ++i) {
      const double a = 2 * M_PI * i / kCapRingPoints, rr = kCapRingRadius * g.size[0];
      add(PointSupport::Fixed, g.pos + r * Vec3(rr * std::cos(a), rr * std::sin(a), cap * g.size[1]));
    }
  }
}
}  // namespace

std::vector<ContactPoint> contact_points(const Model& m) {
  std::vector<ContactPoint> pts;
  std::vector<int> planes;
  for (int o : contact_obstacles(m))
    if (m.geoms[o].type == GeomType::Plane) planes.push_back(o);
  for (int gi = 0; gi < static_cast<int>(m.geoms.size()); ++gi) {
    const Geom& g = m.geoms[gi];
    if (g.body == 0 || !g.contact) continue;
    const Mat3 r = g.quat.toRotationMatrix();
    switch (g.type) {
      case GeomType::Sphere: pts.push_back({g.body, g.pos, g.size[0], gi}); break;
      case GeomType::Capsule:
        for (int s : {-1, 1}) pts.push_back({g.body, g.pos + r.col(2) * (s * g.size[1]), g.size[0], gi});
        break;
      case GeomType::Box:
        for (int c = 0; c < 8; ++c) pts.push_back({g.body, g.pos + r * box_corner(g.size, c), 0.0, gi});
        break;
      case GeomType::Mesh: {  // vertices plus edge and face samples
        const bool exact = g.tessellates != Geom::Tessellated::None && g.exact_plane_contact && !planes.empty();
        for (const Vec3& v : mesh_contact_samples(*g.mesh)) {
          pts.push_back({g.body, g.pos + r * v, 0.0, gi});
          if (exact) pts.back().role = PointRole::NotPlanes;
        }
        if (exact)
          for (int pl : planes) add_plane_points(g, gi, pl, &pts);
        break;
      }
      case GeomType::Plane: break;
    }
  }
  for (ContactPoint& p : pts) p.geom_radius = geom_bounding_radius(m.geoms[p.geom]);
  return pts;
}

std::vector<int> contact_obstacles(const Model& m) {
  std::vector<int> obs;
  for (size_t i = 0; i < m.geoms.size(); ++i)
    if (m.geoms[i].body == 0 && m.geoms[i].contact) obs.push_back(static_cast<int>(i));
  return obs;
}

double obstacle_distance(const Geom& g, const MeshBvh* tree, const Vec3& x, Vec3* normal) {
  const Mat3 r = g.quat.toRotationMatrix();
  if (g.type == GeomType::Mesh) {
    Vec3 n;
    const Vec3 p = r.transpose() * (x - g.pos);
    const double d = tree ? mesh_signed_distance(*g.mesh, *tree, p, &n) : mesh_signed_distance(*g.mesh, p, &n);
    *normal = r * n;
    return d;
  }
  return shape_distance(g.type, g.size, g.pos, r, x, normal);
}

std::vector<MeshBvh> moving_mesh_trees(const Model& m) {
  std::vector<MeshBvh> trees(m.geoms.size());
  for (size_t g = 0; g < m.geoms.size(); ++g)
    if (m.geoms[g].body != 0 && m.geoms[g].contact && m.geoms[g].type == GeomType::Mesh) trees[g] = mesh_bvh(*m.geoms[g].mesh);
  return trees;
}

std::vector<MeshBvh> obstacle_trees(const Model& m, const std::vector<int>& obs) {
  std::vector<MeshBvh> trees(obs.size());
  for (size_t o = 0; o < obs.size(); ++o)
    if (m.geoms[obs[o]].type == GeomType::Mesh) trees[o] = mesh_bvh(*m.geoms[obs[o]].mesh);
  return trees;
}

void ObstacleCull::update(const Model& m, const Kinematics& k, const ContactPoint& cp, const std::vector<int>& obs,
                          bool mixed) {
  if (cp.geom == geom_) return;
  geom_ = cp.geom;
  active_ = cp.geom >= 0 && cp.geom_radius >= 0 && obs.size() <= kMax;
  if (!active_) return;
  const Geom& g = m.geoms[cp.geom];
  const Vec3 centre = k.xpos[g.body] + k.xmat[g.body] * g.pos;
  const double radius = cp.geom_radius;
  all_ = true;
  for (size_t o = 0; o < obs.size(); ++o) {
    const Geom& ob = m.geoms[obs[o]];
    Vec3 n;
    const double margin = mixed ? point_contact_mix(m, cp, obs[o]).margin : 0.0;
    culled_[o] = ob.type != GeomType::Mesh && obstacle_distance(ob, nullptr, centre, &n) - radius - margin > 1e-9;
    all_ = all_ && culled_[o];
  }
}

void find_contacts(const Model& m, const Kinematics& k, const std::vector<ContactPoint>& pts,
                   const std::vector<int>& obs, const std::vector<MeshBvh>& trees,
                   const std::vector<MeshBvh>& mesh_trees, std::vector<Contact>* out) {
  out->clear();
  const int no = static_cast<int>(obs.size());
  const int nt = static_cast<int>(trees.size());
  const bool mixed = geom_contact_params_set(m);
  ObstacleCull cull;
  for (size_t i = 0; i < pts.size(); ++i) {
    const ContactPoint& cp = pts[i];
    cull.update(m, k, cp, obs, mixed);
    if (cull.skip_all()) continue;
    const Vec3 c = k.xpos[cp.body] + k.xmat[cp.body] * contact_point_local(m, cp, k.xmat[cp.body]);
    for (int o = 0; o < no; ++o) {
      if (cull.skip(o) || !point_meets(m, cp, obs[o])) continue;
      Vec3 n;
      const ContactMix mix = mixed ? point_contact_mix(m, cp, obs[o]) : ContactMix{};
      const double reach = cp.radius + mix.margin;  // the margin as extra radius
      const double d = obstacle_distance(m.geoms[obs[o]], o < nt ? &trees[o] : nullptr, c, &n) - reach;
      if (d >= 0) continue;
      Contact ct;
      ct.slot = static_cast<int>(i) * no + o;
      ct.body = cp.body;
      ct.point = c - reach * n;
      ct.normal = n;
      ct.depth = -d;
      ct.mix = mix;
      out->push_back(ct);
    }
  }
  mesh_feature_contacts(m, k, obs, trees, mesh_trees, out);
}

}  // namespace pliant::articulated
