// The model's trees and the solve restricted to some of them (forest.cpp,
// tree_resolve_in in dynamics.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pliant/articulated/dynamics.h"
#include "pliant/articulated/io.h"

namespace pliant::articulated {
namespace {

// Three trees: an arm of two bodies (hinge, then ball) and two free boxes.
Model three_trees() {
  Model m = model_from_mjcf(
      "<mujoco><worldbody>"
      "<body name=\"arm\" pos=\"0 0 1\"><joint type=\"hinge\" axis=\"0 1 0\"/>"
      "<geom type=\"capsule\" fromto=\"0 0 0 0.5 0 0\" size=\"0.05\"/>"
      "<body name=\"fore\" pos=\"0.5 0 0\"><joint type=\"ball\"/>"
      "<geom type=\"capsule\" fromto=\"0 0 0 0.5 0 0\" size=\"0.05\"/></body></body>"
      "<body name=\"box\" pos=\"2 0 1\"><freejoint/><geom type=\"box\" size=\"0.1 0.2 0.3\"/></body>"
      "<body name=\"box2\" pos=\"4 0 1\"><freejoint/><geom type=\"box\" size=\"0.3 0.2 0.1\"/></body>"
      "</worldbody></mujoco>",
      "forest.xml");
  return m;
}

TEST(Forest, GroupsBodiesAndDofsByTheirChildOfTheWorld) {
  const Model m = three_trees();
  const Forest f = model_forest(m);
  ASSERT_EQ(f.bodies.size(), 3u);
  EXPECT_EQ(f.body_tree[0], -1);
  for (int b = 1; b < static_cast<int>(m.bodies.size()); ++b) {
    int root = b;
    while (m.bodies[root].parent != 0) root = m.bodies[root].parent;
    EXPECT_EQ(f.body_tree[b], f.body_tree[root]) << m.bodies[b].name;
  }
  int dofs = 0;
  for (size_t t = 0; t < f.bodies.size(); ++t) {
    for (size_t i = 1; i < f.dofs[t].size(); ++i) EXPECT_LT(f.dofs[t][i - 1], f.dofs[t][i]);
    for (int d : f.dofs[t]) EXPECT_EQ(f.body_tree[m.dof_body[d]], static_cast<int>(t));
    dofs += static_cast<int>(f.dofs[t].size());
  }
  EXPECT_EQ(dofs, m.nv);  // 1 + 3, 6, 6
  EXPECT_EQ(f.dofs[f.body_tree[1]].size(), 4u);
}

// A right-hand side in two of the three trees: tree_resolve_in gives tree_resolve's
// solution there bit for bit and writes nothing at the third tree's dofs.
TEST(Forest, ResolveInSomeTreesMatchesTheWholeResolve) {
  const Model m = three_trees();
  const Forest f = model_forest(m);
  VecX q = m.qpos0;
  VecX dv(m.nv);
  for (int i = 0; i < m.nv; ++i) dv[i] = 0.3 * std::sin(0.7 * i + 0.2);
  qpos_integrate(m, q, dv, 1.0);
  Kinematics k;
  kinematics(m, q, &k);
  TreeWorkspace ws;
  VecX x;
  const VecX arm = VecX::Constant(m.nv, 0.5);
  tree_solve(m, k, k.cinert, arm, VecX::Ones(m.nv), &x, &ws);
  const int trees[2] = {f.body_tree[1], f.body_tree[4]};  // the arm's and box2's
  VecX rhs = VecX::Zero(m.nv);
  for (int t : trees)
    for (int d : f.dofs[t]) rhs[d] = std::cos(1.1 * d + 0.3);
  VecX whole;
  tree_resolve(m, k, rhs, &whole, &ws);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  VecX part = VecX::Constant(m.nv, nan);
  tree_resolve_in(m, k, f, trees, 2, rhs, part, &ws);
  for (int t : trees)
    for (int d : f.dofs[t]) EXPECT_EQ(part[d], whole[d]) << d;
  for (int d : f.dofs[f.body_tree[3]]) {
    EXPECT_TRUE(std::isnan(part[d])) << d;
    EXPECT_EQ(whole[d], 0) << d;
  }
  EXPECT_GT(whole.norm(), 0.1);
}

}  // namespace
}  // namespace pliant::articulated
