// LM's linear solve with body-body contact (sim_internal.h): the tree solve of the
// per-body blocks plus each contact's rank-1 terms by Woodbury's identity, with the
// terms' columns restricted to the trees they touch and the capacitance solved per
// group of terms coupled through shared trees.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// Generalized force of wrench wb on body b and wa on body a (their ancestors' dofs
// only; world-frame motion subspaces), added to u (zero at those rows).
void pair_column(const Model& m, const Kinematics& k, const WrenchTerm& t, Eigen::Ref<VecX> u) {
  for (int b = t.body_b; b != 0; b = m.bodies[b].parent)
    for (int d = m.bodies[b].dof_begin; d < m.bodies[b].dof_begin + m.bodies[b].dof_count; ++d) u[d] += k.cdof[d].dot(t.wb);
  for (int b = t.body_a; b != 0; b = m.bodies[b].parent)
    for (int d = m.bodies[b].dof_begin; d < m.bodies[b].dof_begin + m.bodies[b].dof_count; ++d) u[d] += k.cdof[d].dot(t.wa);
}

// ws.pair_terms as wrench terms (a unit force dir at point_b on b, -dir at point_a on
// a). Where one body pair has more than kMaxTermsPerBodyPair terms (a mesh face or a
// box face lying on another body: tens of contacts), their sum
// M = sum w (wa; wb)(wa; wb)^T (12 x 12, bodies in index order) replaces them by its
// pivoted LDL^T factors, M = sum_i D_i l_i l_i^T, at most 12 terms: the Woodbury solve
// costs O(terms^3), and the LM matrix is the same up to round-off. Otherwise the terms
// keep their order (and the solve its last bits).
void build_wrench_terms(int nb, SimWorkspace& ws) {
  ws.wrench_terms.clear();
  const int n = static_cast<int>(ws.pair_terms.size());
  // Terms sorted by body pair, then index: runs of one pair, each in ascending term
  // order (no search over the pairs seen so far: a pile has thousands of terms).
  ws.term_order.resize(n);
  for (int t = 0; t < n; ++t) {
    const PairTerm& p = ws.pair_terms[t];
    ws.term_order[t] = {static_cast<long>(std::min(p.body_a, p.body_b)) * nb + std::max(p.body_a, p.body_b), t};
  }
  std::sort(ws.term_order.begin(), ws.term_order.end());
  ws.run_begin.clear();
  int most = 0;
  for (int i = 0; i < n; ++i) {
    if (i == 0 || ws.term_order[i].first != ws.term_order[i - 1].first) ws.run_begin.push_back(i);
    most = std::max(most, i + 1 - ws.run_begin.back());
  }
  ws.run_begin.push_back(n);
  const auto wrench_term = [](const PairTerm& t) {
    return WrenchTerm{t.body_a, t.body_b, point_wrench(t.point_a, -t.dir), point_wrench(t.point_b, t.dir), t.weight};
  };
  if (most <= kMaxTermsPerBodyPair) {
    for (const PairTerm& t : ws.pair_terms) ws.wrench_terms.push_back(wrench_term(t));
    return;
  }
  const int runs = static_cast<int>(ws.run_begin.size()) - 1;
  ws.run_order.resize(runs);
  for (int r = 0; r < runs; ++r) ws.run_order[r] = r;
  std::sort(ws.run_order.begin(), ws.run_order.end(),
            [&](int x, int y) { return ws.term_order[ws.run_begin[x]].second < ws.term_order[ws.run_begin[y]].second; });
  using Mat12 = Eigen::Matrix<double, 12, 12>;
  using Vec12 = Eigen::Matrix<double, 12, 1>;
  for (int r : ws.run_order) {
    const std::pair<long, int>* terms = ws.term_order.data() + ws.run_begin[r];
    const int count = ws.run_begin[r + 1] - ws.run_begin[r];
    if (count <= kMaxTermsPerBodyPair) {
      for (int i = 0; i < count; ++i) ws.wrench_terms.push_back(wrench_term(ws.pair_terms[terms[i].second]));
      continue;
    }
    const PairTerm& first = ws.pair_terms[terms[0].second];
    const int lo = std::min(first.body_a, first.body_b), hi = std::max(first.body_a, first.body_b);
    Mat12 sum = Mat12::Zero();
    for (int i = 0; i < count; ++i) {
      const PairTerm& t = ws.pair_terms[terms[i].second];
      const WrenchTerm w = wrench_term(t);
      Vec12 v;
      v << (t.body_a == lo ? w.wa : w.wb), (t.body_a == lo ? w.wb : w.wa);
      sum.selfadjointView<Eigen::Lower>().rankUpdate(v, t.weight);
    }
    const Eigen::LDLT<Mat12, Eigen::Lower> ldlt(sum.selfadjointView<Eigen::Lower>());
    const Mat12 l = ldlt.transpositionsP().transpose() * Mat12(ldlt.matrixL());
    const Vec12 d = ldlt.vectorD();
    const double dmax = d.maxCoeff();
    for (int i = 0; i < 12; ++i)
      if (d[i] > 1e-14 * dmax) ws.wrench_terms.push_back({lo, hi, l.col(i).head<6>(), l.col(i).tail<6>(), d[i]});
  }
}

// Solves the leading n x n block of c (overwritten) for rhs in place: Gaussian
// elimination with partial pivoting (the capacitance matrix is non-symmetric with the
// exact Hessian's blocks); no allocation.
void dense_solve(Eigen::MatrixXd& c, int n, VecX& rhs) {
  for (int j = 0; j < n; ++j) {
    int piv = j;
    for (int i = j + 1; i < n; ++i)
      if (std::abs(c(i, j)) > std::abs(c(piv, j))) piv = i;
    if (piv != j) {
      for (int l = 0; l < n; ++l) std::swap(c(j, l), c(piv, l));
      std::swap(rhs[j], rhs[piv]);
    }
    const double d = c(j, j);
    for (int i = j + 1; i < n; ++i) {
      const double f = c(i, j) / d;
      if (f == 0) continue;
      for (int l = j + 1; l < n; ++l) c(i, l) -= f * c(j, l);
      rhs[i] -= f * rhs[j];
    }
  }
  for (int j = n - 1; j >= 0; --j) {
    double v = rhs[j];
    for (int l = j + 1; l < n; ++l) v -= c(j, l) * rhs[l];
    rhs[j] = v / c(j, j);
  }
}

// Term t's trees into ws.term_trees[t] (one or two) and its column's nonzero rows,
// ascending over those trees' dofs (the order of a scan over all nv).
void term_rows(int t, SimWorkspace& ws) {
  const Forest& f = ws.forest;
  const WrenchTerm& w = ws.wrench_terms[t];
  std::array<int, 2>& trees = ws.term_trees[t];
  int count = 0;
  for (int b : {w.body_a, w.body_b})
    if (b > 0 && (count == 0 || trees[0] != f.body_tree[b])) trees[count++] = f.body_tree[b];
  if (count == 0) throw std::logic_error("lm_solve: a body-body contact term between two world geoms");
  ws.term_tree_count[t] = count;
  const double* u = ws.pair_u.col(t).data();
  const std::vector<int>& d0 = f.dofs[trees[0]];
  const std::vector<int>& d1 = count == 2 ? f.dofs[trees[1]] : d0;
  size_t i = 0, j = count == 2 ? 0 : d1.size();
  while (i < d0.size() || j < d1.size()) {
    const int d = (j == d1.size() || (i < d0.size() && d0[i] < d1[j])) ? d0[i++] : d1[j++];
    if (u[d] != 0) ws.pair_nz.push_back(d);
  }
  ws.pair_nz_begin.push_back(static_cast<int>(ws.pair_nz.size()));
}

int tree_root(std::vector<int>& link, int t) {
  while (link[t] != t) t = link[t] = link[link[t]];
  return t;
}

// Groups of terms coupled through shared trees, each ascending (ws.group_terms
// [group_begin[g] .. group_begin[g + 1])). Terms of different groups have a zero
// capacitance entry, so each group's block is solved on its own: the same elimination
// as on the whole matrix (partial pivoting never picks a zero of another group).
void term_groups_by_tree(int nt, SimWorkspace& ws) {
  const int ntree = static_cast<int>(ws.forest.bodies.size());
  ws.tree_link.resize(ntree);
  for (int t = 0; t < ntree; ++t) ws.tree_link[t] = t;
  for (int t = 0; t < nt; ++t)
    if (ws.term_tree_count[t] == 2)
      ws.tree_link[tree_root(ws.tree_link, ws.term_trees[t][0])] = tree_root(ws.tree_link, ws.term_trees[t][1]);
  // Group ids in order of each group's first term, terms counted per group.
  ws.term_group.assign(nt, -1);
  ws.tree_group.assign(ntree, -1);
  ws.group_begin.assign(1, 0);
  int groups = 0;
  for (int t = 0; t < nt; ++t) {
    int& g = ws.tree_group[tree_root(ws.tree_link, ws.term_trees[t][0])];
    if (g < 0) {
      g = groups++;
      ws.group_begin.push_back(0);
    }
    ws.term_group[t] = g;
    ++ws.group_begin[g + 1];
  }
  for (int g = 0; g < groups; ++g) ws.group_begin[g + 1] += ws.group_begin[g];
  ws.group_terms.resize(nt);
  ws.group_fill.assign(ws.group_begin.begin(), ws.group_begin.end() - 1);
  for (int t = 0; t < nt; ++t) ws.group_terms[ws.group_fill[ws.term_group[t]]++] = t;
}

}  // namespace

bool lm_solve(const Model& m, const std::vector<Mat6>& blocks, const VecX& rhs, VecX* x, SimWorkspace& ws,
              bool indefinite_fails) {
  const bool pd = tree_solve(m, ws.kin, blocks, ws.arm, rhs, x, &ws.tree);
  if (ws.pair_terms.empty() || (!pd && indefinite_fails)) return pd;
  if (ws.forest.body_tree.size() != m.bodies.size()) ws.forest = model_forest(m);
  const Forest& f = ws.forest;
  build_wrench_terms(static_cast<int>(m.bodies.size()), ws);
  const int nt = static_cast<int>(ws.wrench_terms.size());
  if (ws.pair_u.rows() != m.nv || ws.pair_u.cols() < nt) {  // capacity grows, never shrinks
    const int cap = std::max(nt, static_cast<int>(ws.pair_u.cols()) * 2);
    ws.pair_u.setZero(m.nv, cap);
    ws.pair_y.setZero(m.nv, cap);
    ws.col_trees.assign(cap, {-1, -1});
    ws.pair_alpha.resize(cap);
  }
  ws.term_trees.resize(nt);
  ws.term_tree_count.resize(nt);
  ws.tree_terms.resize(f.bodies.size());
  for (std::vector<int>& terms : ws.tree_terms) terms.clear();
  ws.pair_nz.clear();
  ws.pair_nz_begin.assign(1, 0);
  // Columns u and A^-1 u (A's elimination from the solve above) on the term's trees
  // only: A has no entries between trees, so A^-1 u is zero elsewhere (a pile of 100
  // free objects: two one-body trees per term instead of all 115 bodies). A column is
  // zero outside the trees it was last written at (ws.col_trees).
  for (int t = 0; t < nt; ++t) {
    for (int tree : ws.col_trees[t])
      if (tree >= 0)
        for (int d : f.dofs[tree]) ws.pair_u(d, t) = ws.pair_y(d, t) = 0;
    pair_column(m, ws.kin, ws.wrench_terms[t], ws.pair_u.col(t));
    term_rows(t, ws);
    ws.col_trees[t] = {ws.term_trees[t][0], ws.term_tree_count[t] == 2 ? ws.term_trees[t][1] : -1};
    for (int i = 0; i < ws.term_tree_count[t]; ++i) ws.tree_terms[ws.term_trees[t][i]].push_back(t);
    tree_resolve_in(m, ws.kin, f, ws.term_trees[t].data(), ws.term_tree_count[t], ws.pair_u.col(t),
                    ws.pair_y.col(t), &ws.tree);
  }
  // Per group, the capacitance u_i . A^-1 u_j over u_i's nonzero rows (12 for two free
  // bodies), only for terms j sharing a tree with i (the other entries are zero), and
  // its solve.
  term_groups_by_tree(nt, ws);
  ws.term_stamp.assign(nt, -1);
  ws.term_pos.resize(nt);
  for (size_t g = 0; g + 1 < ws.group_begin.size(); ++g) {
    const int* terms = ws.group_terms.data() + ws.group_begin[g];
    const int n = ws.group_begin[g + 1] - ws.group_begin[g];
    for (int r = 0; r < n; ++r) ws.term_pos[terms[r]] = r;
    if (ws.group_cap.rows() < n) {
      ws.group_cap.resize(n, n);
      ws.group_alpha.resize(n);
    }
    ws.group_cap.topLeftCorner(n, n).setZero();
    for (int r = 0; r < n; ++r) {
      const int i = terms[r];
      const int* nz = ws.pair_nz.data() + ws.pair_nz_begin[i];
      const int count = ws.pair_nz_begin[i + 1] - ws.pair_nz_begin[i];
      const double* u = ws.pair_u.col(i).data();
      for (int k = 0; k < ws.term_tree_count[i]; ++k)
        for (int j : ws.tree_terms[ws.term_trees[i][k]]) {
          if (ws.term_stamp[j] == i) continue;
          ws.term_stamp[j] = i;
          const double* y = ws.pair_y.col(j).data();
          double sum = 0;
          for (int l = 0; l < count; ++l) sum += u[nz[l]] * y[nz[l]];
          ws.group_cap(r, ws.term_pos[j]) = sum;
        }
      ws.group_cap(r, r) += 1 / ws.wrench_terms[i].weight;
      double alpha = 0;
      for (int l = 0; l < count; ++l) alpha += u[nz[l]] * (*x)[nz[l]];
      ws.group_alpha[r] = alpha;
    }
    dense_solve(ws.group_cap, n, ws.group_alpha);
    for (int r = 0; r < n; ++r) ws.pair_alpha[terms[r]] = ws.group_alpha[r];
  }
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < ws.term_tree_count[t]; ++k)
      for (int d : f.dofs[ws.term_trees[t][k]]) (*x)[d] -= ws.pair_alpha[t] * ws.pair_y(d, t);
  return pd && x->allFinite();
}

}  // namespace pliant::articulated
