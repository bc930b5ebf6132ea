// Contact candidates and obstacle distances (see contact.h for the force laws).
#include "pliant/articulated/contact.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace pliant::articulated {
namespace {

// Corner c (bit i set: + side on axis i) of a box with half sizes `half`, in its frame.
Vec3 box_corner(const Vec3& half, int c) {
  return Vec3((c & 1 ? 1 : -1) * half[0], (c & 2 ? 1 : -1) * half[1], (c & 4 ? 1 : -1) * half[2]);
}

}  // namespace

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

std::vector<ContactPoint> contact_points(const Model& m) {
  std::vector<ContactPoint> pts;
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
      case GeomType::Mesh:  // vertices plus edge and face samples
        for (const Vec3& v : mesh_contact_samples(*g.mesh)) pts.push_back({g.body, g.pos + r * v, 0.0, gi});
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

namespace {

// Signed distance (positive outside) of world point x from a plane, sphere, box or
// capsule placed at (c, r), with its outward normal.
double shape_distance(GeomType type, const Vec3& size, const Vec3& c, const Mat3& r, const Vec3& x, Vec3* normal) {
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

}  // namespace

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

namespace {

// Obstacle point c (world; a sphere's centre with its radius) against moving mesh
// geom g at (gr, gp), through its tree where there is one (culled by the root box).
void feature_against_mesh(const Geom& g, const MeshBvh* tree, const Mat3& gr, const Vec3& gp, const Vec3& c,
                          double radius, const ContactMix& mix, std::vector<Contact>* out) {
  const Vec3 p = gr.transpose() * (c - gp);
  // Farther than the radius from the tree's root box: cannot reach the mesh.
  if (tree) {
    const double b2 = (tree->nodes[0].lo - p).cwiseMax(0.0).cwiseMax(p - tree->nodes[0].hi).squaredNorm();
    if (b2 > 0 && b2 >= radius * radius) return;
  }
  Vec3 n;
  const double d = (tree ? mesh_signed_distance(*g.mesh, *tree, p, &n) : mesh_signed_distance(*g.mesh, p, &n)) - radius;
  if (d >= 0) return;
  Contact ct;
  ct.slot = -1;
  ct.body = g.body;
  ct.normal = -(gr * n);
  ct.point = c + radius * ct.normal;
  ct.depth = -d;
  ct.mix = mix;
  out->push_back(ct);
}

}  // namespace

void mesh_feature_contacts(const Model& m, const Kinematics& k, const std::vector<int>& obs,
                           const std::vector<MeshBvh>& obstacle_trees, const std::vector<MeshBvh>& mesh_trees,
                           std::vector<Contact>* out) {
  const int nt = static_cast<int>(mesh_trees.size());
  for (size_t oi = 0; oi < obs.size(); ++oi) {
    const Geom& ob = m.geoms[obs[oi]];
    if (ob.type != GeomType::Box && ob.type != GeomType::Sphere && ob.type != GeomType::Mesh) continue;
    const MeshBvh* otree = ob.type == GeomType::Mesh && oi < obstacle_trees.size() && !obstacle_trees[oi].nodes.empty()
                               ? &obstacle_trees[oi]
                               : nullptr;
    const Mat3 obr = ob.quat.toRotationMatrix();
    for (int gi = 0; gi < static_cast<int>(m.geoms.size()); ++gi) {
      const Geom& g = m.geoms[gi];
      if (g.body == 0 || !g.contact || g.type != GeomType::Mesh) continue;
      const MeshBvh* tree = gi < nt && !mesh_trees[gi].nodes.empty() ? &mesh_trees[gi] : nullptr;
      const Mat3 gr = k.xmat[g.body] * g.quat.toRotationMatrix();
      const Vec3 gp = k.xpos[g.body] + k.xmat[g.body] * g.pos;
      const ContactMix mix = contact_mix(g, ob);
      const double mg = mix.margin;  // as extra radius: depth = margin - distance
      if (ob.type == GeomType::Box) {
        for (int f = 0; f < 8; ++f) feature_against_mesh(g, tree, gr, gp, ob.pos + ob.quat * box_corner(ob.size, f), mg, mix, out);
      } else if (ob.type == GeomType::Sphere) {
        feature_against_mesh(g, tree, gr, gp, ob.pos, ob.size[0] + mg, mix, out);
      } else if (!otree || !tree) {
        for (const Vec3& v : ob.mesh->vertices) feature_against_mesh(g, tree, gr, gp, ob.pos + obr * v, mg, mix, out);
      } else {
        // Static mesh vertices near the moving mesh only: walk the static mesh's tree
        // with the moving mesh's root box as a sphere (static mesh frame); each vertex
        // once, from its owner triangle (every leaf holding it has a box around it).
        const MeshBvh::Node& root = tree->nodes[0];
        double r2 = 0.25 * (root.hi - root.lo).squaredNorm() * (1 + 1e-9);
        if (mg > 0) r2 = (std::sqrt(r2) + mg) * (std::sqrt(r2) + mg);  // reach grown by the margin
        const Vec3 centre = obr.transpose() * (gp + gr * (0.5 * (root.lo + root.hi)) - ob.pos);
        int stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
          const int self = stack[--top];
          const MeshBvh::Node& nd = otree->nodes[self];
          if ((nd.lo - centre).cwiseMax(0.0).cwiseMax(centre - nd.hi).squaredNorm() > r2) continue;
          if (nd.count == 0) {
            stack[top++] = nd.right;
            stack[top++] = self + 1;
            continue;
          }
          for (int i = nd.first; i < nd.first + nd.count; ++i) {
            const int t = otree->order[i];
            for (int v : ob.mesh->triangles[t])
              if (otree->vertex_owner[v] == t) feature_against_mesh(g, tree, gr, gp, ob.pos + obr * ob.mesh->vertices[v], mg, mix, out);
          }
        }
      }
    }
  }
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

void find_contacts(const Model& m, const Kinematics& k, const std::vector<ContactPoint>& pts,
                   const std::vector<int>& obs, const std::vector<MeshBvh>& trees,
                   const std::vector<MeshBvh>& mesh_trees, std::vector<Contact>* out) {
  out->clear();
  const int no = static_cast<int>(obs.size());
  const int nt = static_cast<int>(trees.size());
  const bool mixed = geom_contact_params_set(m);
  for (size_t i = 0; i < pts.size(); ++i) {
    const ContactPoint& cp = pts[i];
    const Vec3 c = k.xpos[cp.body] + k.xmat[cp.body] * cp.local;
    for (int o = 0; o < no; ++o) {
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

// ---- Body-body contact ----

double geom_bounding_radius(const Geom& g) {
  switch (g.type) {
    case GeomType::Sphere: return g.size[0];
    case GeomType::Capsule: return g.size[0] + g.size[1];
    case GeomType::Box: return g.size.norm();
    case GeomType::Mesh: {
      double r = 0;
      for (const Vec3& v : g.mesh->vertices) r = std::max(r, v.norm());
      return r;
    }
    default: return 0;
  }
}

std::vector<GeomPair> contact_geom_pairs(const Model& m) {
  std::vector<GeomPair> out;
  const auto collides = [](const Geom& g) {
    return g.body != 0 && (g.type == GeomType::Sphere || g.type == GeomType::Capsule || g.type == GeomType::Box ||
                           g.type == GeomType::Mesh);
  };
  const auto is_explicit = [&m](int i, int j) {
    for (const ContactPair& p : m.contact_pairs)
      if ((p.geom1 == i && p.geom2 == j) || (p.geom1 == j && p.geom2 == i)) return true;
    return false;
  };
  // Mesh samples and trees once per mesh geom, shared by its pairs.
  std::vector<std::shared_ptr<const MeshCollider>> colliders(m.geoms.size());
  const auto collider = [&](int g) {
    if (m.geoms[g].type != GeomType::Mesh) return std::shared_ptr<const MeshCollider>();
    if (!colliders[g])
      colliders[g] = std::make_shared<const MeshCollider>(
          MeshCollider{mesh_contact_samples(*m.geoms[g].mesh), mesh_bvh(*m.geoms[g].mesh)});
    return colliders[g];
  };
  const auto pair_of = [&](int i, int j) {
    GeomPair p{};
    p.a = i;
    p.b = j;
    p.reach = geom_bounding_radius(m.geoms[i]) + geom_bounding_radius(m.geoms[j]);
    p.mesh_a = collider(i);
    p.mesh_b = collider(j);
    return p;
  };
  for (size_t i = 0; i < m.geoms.size(); ++i) {
    const Geom& ga = m.geoms[i];
    if (!collides(ga)) continue;
    for (size_t j = i + 1; j < m.geoms.size(); ++j) {
      const Geom& gb = m.geoms[j];
      if (!collides(gb) || ga.body == gb.body) continue;
      if (m.bodies[ga.body].parent == gb.body || m.bodies[gb.body].parent == ga.body) continue;
      if (!((ga.contype & gb.conaffinity) || (gb.contype & ga.conaffinity))) continue;
      const std::array<int, 2> key{std::min(ga.body, gb.body), std::max(ga.body, gb.body)};
      if (std::find(m.contact_exclude.begin(), m.contact_exclude.end(), key) != m.contact_exclude.end()) continue;
      if (is_explicit(static_cast<int>(i), static_cast<int>(j))) continue;  // listed below, with its own friction
      GeomPair p = pair_of(static_cast<int>(i), static_cast<int>(j));
      p.mix = contact_mix(ga, gb);
      p.reach += p.mix.margin;
      out.push_back(p);
    }
  }
  for (const ContactPair& cp : m.contact_pairs) {
    GeomPair p = pair_of(cp.geom1, cp.geom2);
    p.explicit_pair = true;
    p.mix.mu = cp.mu;  // the pair's own values, not the geoms' (as MuJoCo's <pair>)
    p.mix.scene_mu = cp.mu < 0;
    p.mix.margin = cp.margin;
    p.mix.frictionless = cp.frictionless;
    p.reach += cp.margin;
    out.push_back(p);
  }
  return out;
}

namespace {

struct Placed {  // a geom at its world pose
  const Geom* g;
  Vec3 c;
  Mat3 r;
};

// Point x of body `body` (a sphere of radius `radius` about it) against geom s: a
// contact on body s.g->body (a) and `body` (b) along s's outward normal.
void point_against(const Placed& s, int body, const Vec3& x, double radius, std::vector<PairContact>* out) {
  Vec3 n;
  const double d = shape_distance(s.g->type, s.g->size, s.c, s.r, x, &n) - radius;
  if (d < 0) out->push_back({s.g->body, body, x - radius * n, n, -d});
}

// The pair's margin enters as extra radius: depth = margin - distance, and the
// contact point stays on the force's line.
void corners_against(const Placed& box, const Placed& s, double margin, std::vector<PairContact>* out) {
  for (int f = 0; f < 8; ++f) point_against(s, box.g->body, box.c + box.r * box_corner(box.g->size, f), margin, out);
}

void end_spheres_against(const Placed& cap, const Placed& s, double margin, std::vector<PairContact>* out) {
  for (int e : {-1, 1})
    point_against(s, cap.g->body, cap.c + cap.r.col(2) * (e * cap.g->size[1]), cap.g->size[0] + margin, out);
}

// Closest points of segments p0 + s d0 and p1 + t d1 (s, t in [0, 1]); parallel
// segments: the middle of their overlap along the first (or the nearest ends).
void segment_closest(const Vec3& p0, const Vec3& d0, const Vec3& p1, const Vec3& d1, double* s_out, double* t_out) {
  const Vec3 w = p0 - p1;
  const double a = d0.dot(d0), b = d0.dot(d1), e = d1.dot(d1), c = d0.dot(w), f = d1.dot(w);
  const double denom = a * e - b * b;
  double s, t;
  if (denom > 1e-12 * a * e) {
    s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
  } else {  // parallel: the second segment's ends projected on the first
    const double s0 = -c / a, s1 = (b - c) / a;
    const double lo = std::max(0.0, std::min(s0, s1)), hi = std::min(1.0, std::max(s0, s1));
    s = lo <= hi ? 0.5 * (lo + hi) : std::clamp(0.5 * (s0 + s1), 0.0, 1.0);
  }
  t = (b * s + f) / e;
  if (t < 0 || t > 1) {
    t = std::clamp(t, 0.0, 1.0);
    s = std::clamp((b * t - c) / a, 0.0, 1.0);
  }
  *s_out = s;
  *t_out = t;
}

// Capsule against capsule, energy k/2 (d_c^2 + sum_e d_e^2 - max_e d_e^2): d_c the
// segments' closest-points depth, d_e the depth of each of the four end spheres
// against the other capsule. The closest points minimise the distance, so d_c >= d_e,
// with equality when they sit at an end (clamped; always so for near-parallel
// overlapping axes): there the energy is sum_e d_e^2, the overlap's end spheres (two
// contacts where the axes lie side by side, so a capsule lying on another cannot rock
// about one point); with both closest points interior (axes crossing) the crossing's
// contact plus every end sphere but the deepest. One formula everywhere, so the energy
// is continuous (and C1 where the closest point reaches an end: it tends to that end
// sphere's contact); exactly parallel axes count as clamped.
void capsule_capsule(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out) {
  const Vec3 pa = a.c - a.r.col(2) * a.g->size[1], pb = b.c - b.r.col(2) * b.g->size[1];
  const Vec3 da = a.r.col(2) * (2 * a.g->size[1]), db = b.r.col(2) * (2 * b.g->size[1]);
  const size_t first = out->size();
  end_spheres_against(a, b, margin, out);
  end_spheres_against(b, a, margin, out);
  const double dd = da.dot(db);
  if (da.squaredNorm() * db.squaredNorm() - dd * dd <= 1e-12 * da.squaredNorm() * db.squaredNorm()) return;  // parallel
  double s, t;
  segment_closest(pa, da, pb, db, &s, &t);
  if (!(s > 0 && s < 1 && t > 0 && t < 1)) return;  // clamped: an end sphere's contact
  const Vec3 xa = pa + s * da, xb = pb + t * db;
  const double len = (xb - xa).norm(), d = len - a.g->size[0] - b.g->size[0] - margin;
  if (d >= 0) return;
  size_t deepest = first;
  for (size_t i = first + 1; i < out->size(); ++i)
    if ((*out)[i].depth > (*out)[deepest].depth) deepest = i;
  if (deepest < out->size()) out->erase(out->begin() + static_cast<long>(deepest));
  const Vec3 n = len > 1e-12 ? Vec3((xb - xa) / len) : Vec3(a.r.col(0));
  out->push_back({a.g->body, b.g->body, xb - (b.g->size[0] + margin) * n, n, -d});
}

// A box's 12 edges in world: start points, full-length directions, and whether either
// end corner is inside box `other` (corners as in box_corner).
void box_edges(const Placed& b, const Placed& other, Vec3* p, Vec3* d, bool* corner_inside) {
  const Vec3& sz = b.g->size;
  bool in[8];
  Vec3 n;
  for (int f = 0; f < 8; ++f)
    in[f] = shape_distance(GeomType::Box, other.g->size, other.c, other.r, b.c + b.r * box_corner(sz, f), &n) < 0;
  int k = 0;
  for (int ax = 0; ax < 3; ++ax)
    for (int e = 0; e < 4; ++e, ++k) {
      const int u = (ax + 1) % 3, v = (ax + 2) % 3, start = (e & 1) << u | (e >> 1 & 1) << v;
      Vec3 local;
      local[ax] = -sz[ax];
      local[u] = (e & 1 ? 1 : -1) * sz[u];
      local[v] = (e & 2 ? 1 : -1) * sz[v];
      p[k] = b.c + b.r * local;
      d[k] = b.r.col(ax) * (2 * sz[ax]);
      corner_inside[k] = in[start] || in[start | 1 << ax];
    }
}

// Whether segment p + s d (world, s in [0, 1]) passes through box b (clipped against
// its three slabs).
bool edge_may_meet(const Placed& b, const Vec3& p, const Vec3& d) {
  const Vec3 x0 = b.r.transpose() * (p - b.c), dx = b.r.transpose() * d;
  double s0 = 0, s1 = 1;
  for (int i = 0; i < 3; ++i) {
    const double h = b.g->size[i];
    if (std::abs(dx[i]) < 1e-15) {
      if (std::abs(x0[i]) > h) return false;
      continue;
    }
    const double ta = (-h - x0[i]) / dx[i], tb = (h - x0[i]) / dx[i];
    s0 = std::max(s0, std::min(ta, tb));
    s1 = std::min(s1, std::max(ta, tb));
    if (s0 > s1) return false;
  }
  return true;
}

// Box edge across box edge (no corner inside the other, e.g. two boxes crosswise on
// their edges): for each non-parallel edge pair whose closest points xa, xb are
// interior to both edges, with xa inside b and xb inside a (each at least half the
// edge-edge distance deep, see below), a contact along the edge-edge direction
// (xa - xb: moves b's edge past a's), depth |xa - xb|, at xb. The closest points
// minimise |xa - xb|, so the gradient at fixed edge parameters is exact, and xa, xb
// lie on one line of action. Edges with a corner inside the other box are skipped:
// that corner's contact reports the touch (so the contact switches off with nonzero
// depth when a corner enters: the energy jumps there, see README, Missing).
void edges_across(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out) {
  Vec3 pa[12], da[12], pb[12], db[12], n;
  bool ma[12], mb[12];
  box_edges(a, b, pa, da, ma);
  box_edges(b, a, pb, db, mb);
  for (int i = 0; i < 12; ++i) {
    ma[i] = !ma[i] && edge_may_meet(b, pa[i], da[i]);
    mb[i] = !mb[i] && edge_may_meet(a, pb[i], db[i]);
  }
  for (int i = 0; i < 12; ++i) {
    if (!ma[i]) continue;
    for (int j = 0; j < 12; ++j) {
      if (!mb[j]) continue;
      if (da[i].cross(db[j]).squaredNorm() < 1e-4 * da[i].squaredNorm() * db[j].squaredNorm()) continue;
      double s, t;
      segment_closest(pa[i], da[i], pb[j], db[j], &s, &t);
      if (!(s > 0 && s < 1 && t > 0 && t < 1)) continue;  // an end: a corner's touch
      const Vec3 xa = pa[i] + s * da[i], xb = pb[j] + t * db[j];
      const double depth = (xa - xb).norm();
      // A crossing: xa lies in b's right-angle wedge at xb, at least depth cos 45 deg
      // deep (and xb in a's); edges that merely pass through both boxes far apart, or
      // an edge lying in the other's face, fail this.
      const double limit = -0.5 * depth;
      if (!(depth > 1e-12) || shape_distance(GeomType::Box, b.g->size, b.c, b.r, xa, &n) > limit ||
          shape_distance(GeomType::Box, a.g->size, a.c, a.r, xb, &n) > limit)
        continue;
      out->push_back({a.g->body, b.g->body, xb, (xa - xb) / depth, depth + margin});
    }
  }
}

// Point x of body `body` (a sphere of radius `radius` about it) against mesh geom
// `mesh`'s signed distance: a contact on the mesh's body (a) and `body` (b), normal
// out of the mesh (as mesh_feature_contacts, with the mesh as the other body).
// Points outside the mesh's bounding box by more than the radius are outside the
// closed mesh: skipped before the nearest-triangle query (the tree's root box).
void point_against_mesh(const Placed& mesh, const MeshBvh& bvh, int body, const Vec3& x, double radius,
                        std::vector<PairContact>* out) {
  const Vec3 p = mesh.r.transpose() * (x - mesh.c);
  if (bvh.nodes.empty() || ((bvh.nodes[0].lo - p).cwiseMax(p - bvh.nodes[0].hi).array() >= radius).any()) return;
  Vec3 n;
  const double d = mesh_signed_distance(*mesh.g->mesh, bvh, p, &n) - radius;
  if (d >= 0) return;
  const Vec3 nw = mesh.r * n;
  out->push_back({mesh.g->body, body, x - radius * nw, nw, -d});
}

// Mesh against a sphere, capsule or box `s`: the sphere's centre against the mesh
// (exact); a capsule's end spheres / a box's corners against the mesh, and the mesh's
// contact samples against the capsule / box (each sample a point of the mesh's body).
void mesh_against(const Placed& mesh, const MeshCollider& mc, const Placed& s, double margin,
                  std::vector<PairContact>* out) {
  const Geom& g = *s.g;
  switch (g.type) {
    case GeomType::Sphere: point_against_mesh(mesh, mc.bvh, g.body, s.c, g.size[0] + margin, out); return;
    case GeomType::Capsule:
      for (int e : {-1, 1})
        point_against_mesh(mesh, mc.bvh, g.body, s.c + s.r.col(2) * (e * g.size[1]), g.size[0] + margin, out);
      break;
    case GeomType::Box:
      for (int f = 0; f < 8; ++f) point_against_mesh(mesh, mc.bvh, g.body, s.c + s.r * box_corner(g.size, f), margin, out);
      break;
    default: return;
  }
  for (const Vec3& v : mc.samples) point_against(s, mesh.g->body, mesh.c + mesh.r * v, margin, out);
}

// Samples of mesh f against mesh t. Pre-test in f's frame, before a sample's world
// transform: t's bounding box (grown by the margin) as the axis-aligned box around it
// there (half extents |R| h, widened by 1e-9 relative for round-off), so every sample
// that point_against_mesh would test still reaches it, in the same order.
void samples_against_mesh(const Placed& f, const MeshCollider& mf, const Placed& t, const MeshCollider& mt,
                          double margin, std::vector<PairContact>* out) {
  if (mt.bvh.nodes.empty()) return;
  const MeshBvh::Node& root = mt.bvh.nodes[0];
  const Mat3 rel = f.r.transpose() * t.r;
  const Vec3 half = 0.5 * (root.hi - root.lo) + Vec3::Constant(margin);
  const Vec3 centre = f.r.transpose() * (t.c + t.r * (0.5 * (root.lo + root.hi)) - f.c);
  const Vec3 reach = (rel.cwiseAbs() * half) * (1 + 1e-9) + Vec3::Constant(1e-12);
  for (const Vec3& v : mf.samples) {
    if (((v - centre).cwiseAbs() - reach).maxCoeff() > 0) continue;
    point_against_mesh(t, mt.bvh, f.g->body, f.c + f.r * v, margin, out);
  }
}

// Mesh against mesh: each mesh's contact samples (vertices, edge and face samples)
// against the other's signed distance, both ways; each contact acts on the sample's
// body (b) and the other mesh's body (a) at the sample, along the other mesh's
// outward normal (as a box corner against a mesh).
void mesh_mesh(const Placed& a, const MeshCollider& ma, const Placed& b, const MeshCollider& mb, double margin,
               std::vector<PairContact>* out) {
  samples_against_mesh(a, ma, b, mb, margin, out);
  samples_against_mesh(b, mb, a, ma, margin, out);
}

}  // namespace

void find_pair_contacts(const Model& m, const Kinematics& k, const std::vector<GeomPair>& pairs,
                        std::vector<PairContact>* out, bool self_collision) {
  out->clear();
  for (const GeomPair& pr : pairs) {
    if (!self_collision && !pr.explicit_pair) continue;
    const Geom &g0 = m.geoms[pr.a], &g1 = m.geoms[pr.b];
    Placed a{&g0, k.xpos[g0.body] + k.xmat[g0.body] * g0.pos, Mat3()};
    Placed b{&g1, k.xpos[g1.body] + k.xmat[g1.body] * g1.pos, Mat3()};
    if ((a.c - b.c).squaredNorm() >= pr.reach * pr.reach) continue;  // bounding spheres apart
    a.r = k.xmat[g0.body] * g0.quat.toRotationMatrix();
    b.r = k.xmat[g1.body] * g1.quat.toRotationMatrix();
    const size_t first = out->size();
    // Order by type (sphere < capsule < box < mesh) so each combination has one case.
    const Placed* lo = &a;
    const Placed* hi = &b;
    const MeshCollider* mesh_lo = pr.mesh_a.get();
    const MeshCollider* mesh_hi = pr.mesh_b.get();
    const auto rank = [](GeomType t) {
      return t == GeomType::Sphere ? 0 : t == GeomType::Capsule ? 1 : t == GeomType::Box ? 2 : 3;
    };
    if (rank(hi->g->type) < rank(lo->g->type)) std::swap(lo, hi), std::swap(mesh_lo, mesh_hi);
    const int pair = rank(lo->g->type) * 3 + rank(hi->g->type);
    const double mg = pr.mix.margin;
    if (lo->g->type == GeomType::Mesh) {
      mesh_mesh(*lo, *mesh_lo, *hi, *mesh_hi, mg, out);
    } else if (hi->g->type == GeomType::Mesh) {  // against a sphere, capsule or box
      mesh_against(*hi, *mesh_hi, *lo, mg, out);
    } else {
      switch (pair) {
        case 0: case 1: case 2:  // sphere against sphere, capsule, box: exact
          point_against(*hi, lo->g->body, lo->c, lo->g->size[0] + mg, out);
          break;
        case 4: capsule_capsule(*lo, *hi, mg, out); break;
        case 5:  // capsule-box
          end_spheres_against(*lo, *hi, mg, out);
          corners_against(*hi, *lo, mg, out);
          break;
        case 8:  // box-box: corners, then edges crossing with neither edge's corners inside
          corners_against(*lo, *hi, mg, out);
          corners_against(*hi, *lo, mg, out);
          edges_across(*lo, *hi, mg, out);
          break;
        default: break;
      }
    }
    for (size_t i = first; i < out->size(); ++i) (*out)[i].mix = pr.mix;
  }
}

}  // namespace pliant::articulated
