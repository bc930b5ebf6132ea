// Body-body narrow phase with a mesh: mesh against sphere / capsule / box, and mesh against mesh.
#include "contact_internal.h"

namespace pliant::articulated::contact_internal {
namespace {

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

}  // namespace

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
  // Pre-test in the mesh's frame, before a sample's world transform (as
  // samples_against_mesh): s's axis-aligned box there, grown by the margin and widened
  // for round-off; a sample outside it is farther than the margin from s.
  const Mat3 rel = mesh.r.transpose() * s.r;
  const Vec3 centre = mesh.r.transpose() * (s.c - mesh.c);
  const Vec3 half = g.type == GeomType::Box ? Vec3(rel.cwiseAbs() * g.size)
                                            : Vec3(rel.col(2).cwiseAbs() * g.size[1] + Vec3::Constant(g.size[0]));
  const Vec3 reach = (half + Vec3::Constant(margin)) * (1 + 1e-9) + Vec3::Constant(1e-12);
  for (const Vec3& v : mc.samples) {
    if (((v - centre).cwiseAbs() - reach).maxCoeff() > 0) continue;
    point_against(s, mesh.g->body, mesh.c + mesh.r * v, margin, out);
  }
}

namespace {

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

}  // namespace

// Mesh against mesh: each mesh's contact samples (vertices, edge and face samples)
// against the other's signed distance, both ways; each contact acts on the sample's
// body (b) and the other mesh's body (a) at the sample, along the other mesh's
// outward normal (as a box corner against a mesh).
void mesh_mesh(const Placed& a, const MeshCollider& ma, const Placed& b, const MeshCollider& mb, double margin,
               std::vector<PairContact>* out) {
  samples_against_mesh(a, ma, b, mb, margin, out);
  samples_against_mesh(b, mb, a, ma, margin, out);
}

}  // namespace pliant::articulated::contact_internal
