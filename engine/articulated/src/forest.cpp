// The model's trees (dynamics.h): which bodies and dofs each child of the world
// carries, for solves that touch only some trees (lm_solve's contact terms).
#include "pliant/articulated/dynamics.h"

namespace pliant::articulated {

Forest model_forest(const Model& m) {
  Forest f;
  const int nb = static_cast<int>(m.bodies.size());
  f.body_tree.assign(nb, -1);
  for (int b = 1; b < nb; ++b) {  // parents come before children (model_finalize)
    const int p = m.bodies[b].parent;
    if (p == 0) {
      f.body_tree[b] = static_cast<int>(f.bodies.size());
      f.bodies.emplace_back();
      f.dofs.emplace_back();
    } else {
      f.body_tree[b] = f.body_tree[p];
    }
    const int t = f.body_tree[b];
    f.bodies[t].push_back(b);
    const Body& body = m.bodies[b];
    for (int d = body.dof_begin; d < body.dof_begin + body.dof_count; ++d) f.dofs[t].push_back(d);
  }
  return f;
}

}  // namespace pliant::articulated
