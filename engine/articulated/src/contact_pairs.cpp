// Body-body contact: the geom pair list (filters, mixing, mesh colliders) and the per-pair dispatch by shape.
#include <algorithm>
#include <array>

#include "contact_internal.h"
#include "pliant/articulated/contact.h"

namespace pliant::articulated {

using namespace contact_internal;

double geom_bounding_radius(const Geom& g) {
  switch (g.type) {
    case GeomType::Sphere: return g.size[0];
    case GeomType::Capsule: return g.size[0] + g.size[1];
    case GeomType::Box: return g.size.norm();
    case GeomType::Mesh: {
      // The exact shape's (its plane points, contact_support.cpp, lie on it).
      if (g.tessellates == Geom::Tessellated::Ellipsoid) return g.size.maxCoeff();
      if (g.tessellates == Geom::Tessellated::Cylinder) return std::hypot(g.size[0], g.size[1]);
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
  // Moving capsules against static box obstacles: the capsule's side (the obstacle path
  // has only its end spheres), with the mix the obstacle path uses.
  for (size_t i = 0; i < m.geoms.size(); ++i) {
    const Geom& ga = m.geoms[i];
    if (ga.body == 0 || !ga.contact || ga.type != GeomType::Capsule) continue;
    for (size_t j = 0; j < m.geoms.size(); ++j) {
      const Geom& gb = m.geoms[j];
      if (gb.body != 0 || !gb.contact || gb.type != GeomType::Box) continue;
      GeomPair p = pair_of(static_cast<int>(i), static_cast<int>(j));
      p.world_sides = true;
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
    p.mix.condim = cp.condim;
    p.mix.torsion = cp.torsion;
    p.mix.roll = cp.roll;
    p.reach += cp.margin;
    out.push_back(p);
  }
  return out;
}

namespace {

// One pair's contacts (appended), after its bounding-sphere test.
void pair_contacts(const Model& m, const Kinematics& k, const GeomPair& pr, std::vector<PairContact>* out) {
  const Geom &g0 = m.geoms[pr.a], &g1 = m.geoms[pr.b];
  Placed a{&g0, k.xpos[g0.body] + k.xmat[g0.body] * g0.pos, Mat3()};
  Placed b{&g1, k.xpos[g1.body] + k.xmat[g1.body] * g1.pos, Mat3()};
  if ((a.c - b.c).squaredNorm() >= pr.reach * pr.reach) return;  // bounding spheres apart
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
  if (pr.world_sides) {
    capsule_box(*lo, *hi, mg, out, false);
  } else if (lo->g->type == GeomType::Mesh) {
    mesh_mesh(*lo, *mesh_lo, *hi, *mesh_hi, mg, out);
  } else if (hi->g->type == GeomType::Mesh) {  // against a sphere, capsule or box
    mesh_against(*hi, *mesh_hi, *lo, mg, out);
  } else {
    switch (pair) {
      case 0: case 1: case 2:  // sphere against sphere, capsule, box: exact
        point_against(*hi, lo->g->body, lo->c, lo->g->size[0] + mg, out);
        break;
      case 4: capsule_capsule(*lo, *hi, mg, out); break;
      case 5: capsule_box(*lo, *hi, mg, out); break;  // contact_segment_box.cpp
      case 8: box_box(*lo, *hi, mg, out); break;  // contact_segment_box.cpp
      default: break;
    }
  }
  for (size_t i = first; i < out->size(); ++i) (*out)[i].mix = pr.mix;
}

}  // namespace

void find_pair_contacts(const Model& m, const Kinematics& k, const std::vector<GeomPair>& pairs,
                        std::vector<PairContact>* out, bool self_collision, PairBroadphase* broadphase) {
  out->clear();
  size_t begin = 0;
  if (self_collision && broadphase) {
    broadphase_candidates(m, k, pairs, *broadphase);
    for (int p : broadphase->candidates) pair_contacts(m, k, pairs[p], out);
    begin = broadphase->filtered;
  }
  for (size_t p = begin; p < pairs.size(); ++p) {
    const GeomPair& pr = pairs[p];
    if (!self_collision && !pr.explicit_pair && !pr.world_sides) continue;
    pair_contacts(m, k, pr, out);
  }
}

}  // namespace pliant::articulated
