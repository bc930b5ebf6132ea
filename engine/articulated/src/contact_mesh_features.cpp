// World obstacle features (box corners, sphere centres, mesh vertices) against moving mesh geoms.
#include <cmath>

#include "contact_internal.h"
#include "pliant/articulated/contact.h"

namespace pliant::articulated {

using contact_internal::box_corner;

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

}  // namespace pliant::articulated
