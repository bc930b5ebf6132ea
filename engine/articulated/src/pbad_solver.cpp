// PBAD's per-step minimiser (sim.h): Levenberg-Marquardt on the exact or Gauss-Newton
// Hessian through tree_solve, with the accuracy-aware stop, or L-BFGS preconditioned
// by the Gauss-Newton solve. One iteration per pbad_iterate call.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "sim_internal.h"

namespace pliant::articulated {
namespace {

// Joint-space diagonal of the LM matrix: damping lambda * diag(Gauss-Newton), the
// joints' viscous damping (dissipation potential / dt), their armature (2 c a, c the
// stencil's weight / dt^2, as the bodies' 2 c M), dry friction's iteratively
// reweighted curvature F / sqrt(dq^2 + eps^2) (a majoriser of F |dq|, as sliding
// friction's mu fn / r; ws.dq is at the current iterate) and active range penalties.
void lm_armature(const Model& m, const SimOptions& o, const PbadStep& p, double lambda, SimWorkspace& ws) {
  ws.arm = lambda * ws.diag;
  if (p.any_damping || p.any_armature || p.any_frictionloss)
    for (const Joint& j : m.joints)
      for (int i = 0; i < joint_nv(j.type); ++i) {
        const int v = j.vadr + i;
        ws.arm[v] += j.damping / o.dt + 2 * p.weight / (o.dt * o.dt) * j.armature;
        if (j.frictionloss > 0) {
          const double eps = frictionloss_eps(o, j, i);
          ws.arm[v] += j.frictionloss / std::sqrt(ws.dq[v] * ws.dq[v] + eps * eps);
        }
      }
  if (p.any_limits) ws.arm += ws.limit_h;
}

// L-BFGS iteration preconditioned by the Gauss-Newton matrix: the two-loop recursion
// with H0^-1 applied by tree_solve, so the curvature the Gauss-Newton model misses
// (gravity, the stencil residual times the second derivative of X) is learnt from
// the last gradient differences; O(N) per iteration; Armijo backtracking on E.
bool lbfgs_iterate(const Model& m, const SimOptions& o, const State& s, PbadStep& p, SimWorkspace& ws) {
  const int hist = static_cast<int>(p.s_hist.size());
  VecX q = ws.grad;
  std::vector<double> alpha(hist);
  for (int i = hist - 1; i >= 0; --i) {
    alpha[i] = p.s_hist[i].dot(q) / p.y_hist[i].dot(p.s_hist[i]);
    q -= alpha[i] * p.y_hist[i];
  }
  tree_diagonal(m, ws.kin, ws.h, &ws.diag, &ws.tree);
  lm_armature(m, o, p, 1e-9, ws);
  lm_solve(m, ws.h, q, &ws.step, ws);
  for (int i = 0; i < hist; ++i) {
    const double beta = p.y_hist[i].dot(ws.step) / p.y_hist[i].dot(p.s_hist[i]);
    ws.step += p.s_hist[i] * (alpha[i] - beta);
  }
  ws.step = -ws.step;
  double slope = ws.grad.dot(ws.step);
  if (!(slope < 0)) {  // not a descent direction: restart from the preconditioner alone
    p.s_hist.clear();
    p.y_hist.clear();
    lm_solve(m, ws.h, ws.grad, &ws.step, ws);
    ws.step = -ws.step;
    slope = ws.grad.dot(ws.step);
    if (!(slope < 0)) return true;
  }
  const VecX g_old = ws.grad;
  double t = 1;
  for (int tries = 0; tries < 20; ++tries, t *= 0.5) {
    ws.q_trial = p.q;
    qpos_integrate(m, ws.q_trial, ws.step, t);
    if (!ws.q_trial.allFinite()) continue;
    const double e_trial = pbad_energy(m, o, s, p, ws.q_trial, ws, false);
    const double step_max = t * ws.step.lpNorm<Eigen::Infinity>();
    const bool tiny = step_max < o.lm_tolerance;
    if (tiny || e_trial <= p.energy + 1e-4 * t * slope) {
      const bool stalled = p.energy - e_trial < 1e-14 * (std::abs(p.energy) + 1e-300);
      p.q = ws.q_trial;
      p.energy = pbad_energy(m, o, s, p, p.q, ws, true);
      VecX sv = t * ws.step, yv = ws.grad - g_old;
      if (sv.dot(yv) > 1e-12 * sv.norm() * yv.norm()) {
        if (p.s_hist.size() >= 6) {
          p.s_hist.erase(p.s_hist.begin());
          p.y_hist.erase(p.y_hist.begin());
        }
        p.s_hist.push_back(std::move(sv));
        p.y_hist.push_back(std::move(yv));
      }
      return tiny || stalled || ws.grad.lpNorm<Eigen::Infinity>() < p.grad_tol;
    }
  }
  return true;  // no decrease along a descent direction: at a minimum to round-off
}

// Accuracy-aware stop: solves for the next step at the new iterate (the solve the
// next iteration would start with). If it is below lm_relative_tolerance times the
// step's correction to the quadratic predictor (a measure of the step's truncation
// error, Milne's device), it is applied without the energy test and the step ends:
// the solver error stays a small fraction of the discretisation error instead of
// being driven to round-off. Otherwise the solve is kept for the next iteration.
bool final_correction(const Model& m, const SimOptions& o, PbadStep& p, SimWorkspace& ws) {
  // Only an (almost) undamped Newton step measures the remaining error: a step shrunk
  // by LM damping (indefinite model in a whipping chain) is small without being close.
  if (p.lambda > 1e-4) return false;
  tree_diagonal(m, ws.kin, ws.h, &ws.diag, &ws.tree);
  ws.rhs = -ws.grad;
  lm_armature(m, o, p, p.lambda, ws);
  if (!lm_solve(m, o.exact_hessian ? ws.h_exact : ws.h, ws.rhs, &ws.step, ws))
    return false;  // the next iteration damps and solves again
  const double correction = qpos_difference(m, p.q, p.q_pred).lpNorm<Eigen::Infinity>();
  if (ws.step.lpNorm<Eigen::Infinity>() > o.lm_relative_tolerance * correction) {
    p.step_ready = true;
    return false;
  }
  qpos_integrate(m, p.q, ws.step, 1.0);
  ws.kin_at.resize(0);  // ws.kin is no longer at p.q
  return true;
}

// Generalized force of wrench wb on body b and wa on body a (their ancestors' dofs
// only; world-frame motion subspaces).
void pair_column(const Model& m, const Kinematics& k, const WrenchTerm& t, Eigen::Ref<VecX> u) {
  u.setZero();
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
void build_wrench_terms(SimWorkspace& ws) {
  ws.wrench_terms.clear();
  ws.term_groups.clear();
  const auto in_group = [](const PairTerm& t, const std::array<int, 3>& g) {
    return std::min(t.body_a, t.body_b) == g[0] && std::max(t.body_a, t.body_b) == g[1];
  };
  int most = 0;
  for (const PairTerm& t : ws.pair_terms) {
    auto g = std::find_if(ws.term_groups.begin(), ws.term_groups.end(),
                          [&](const std::array<int, 3>& x) { return in_group(t, x); });
    if (g == ws.term_groups.end())
      g = ws.term_groups.insert(ws.term_groups.end(), {std::min(t.body_a, t.body_b), std::max(t.body_a, t.body_b), 0});
    most = std::max(most, ++(*g)[2]);
  }
  const auto wrench_term = [](const PairTerm& t) {
    return WrenchTerm{t.body_a, t.body_b, point_wrench(t.point_a, -t.dir), point_wrench(t.point_b, t.dir), t.weight};
  };
  if (most <= kMaxTermsPerBodyPair) {
    for (const PairTerm& t : ws.pair_terms) ws.wrench_terms.push_back(wrench_term(t));
    return;
  }
  using Mat12 = Eigen::Matrix<double, 12, 12>;
  using Vec12 = Eigen::Matrix<double, 12, 1>;
  for (const std::array<int, 3>& g : ws.term_groups) {
    if (g[2] <= kMaxTermsPerBodyPair) {
      for (const PairTerm& t : ws.pair_terms)
        if (in_group(t, g)) ws.wrench_terms.push_back(wrench_term(t));
      continue;
    }
    Mat12 sum = Mat12::Zero();
    for (const PairTerm& t : ws.pair_terms) {
      if (!in_group(t, g)) continue;
      const WrenchTerm w = wrench_term(t);
      Vec12 v;
      v << (t.body_a == g[0] ? w.wa : w.wb), (t.body_a == g[0] ? w.wb : w.wa);
      sum.selfadjointView<Eigen::Lower>().rankUpdate(v, t.weight);
    }
    const Eigen::LDLT<Mat12, Eigen::Lower> ldlt(sum.selfadjointView<Eigen::Lower>());
    const Mat12 l = ldlt.transpositionsP().transpose() * Mat12(ldlt.matrixL());
    const Vec12 d = ldlt.vectorD();
    const double dmax = d.maxCoeff();
    for (int i = 0; i < 12; ++i)
      if (d[i] > 1e-14 * dmax) ws.wrench_terms.push_back({g[0], g[1], l.col(i).head<6>(), l.col(i).tail<6>(), d[i]});
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

}  // namespace

bool lm_solve(const Model& m, const std::vector<Mat6>& blocks, const VecX& rhs, VecX* x, SimWorkspace& ws) {
  const bool pd = tree_solve(m, ws.kin, blocks, ws.arm, rhs, x, &ws.tree);
  if (ws.pair_terms.empty()) return pd;
  build_wrench_terms(ws);
  const int nt = static_cast<int>(ws.wrench_terms.size());
  if (ws.pair_u.rows() != m.nv || ws.pair_u.cols() < nt) {  // capacity grows, never shrinks
    const int cap = std::max(nt, static_cast<int>(ws.pair_u.cols()) * 2);
    ws.pair_u.resize(m.nv, cap);
    ws.pair_y.resize(m.nv, cap);
    ws.pair_cap.resize(cap, cap);
    ws.pair_alpha.resize(cap);
  }
  ws.pair_nz.clear();
  ws.pair_nz_begin.assign(1, 0);
  for (int t = 0; t < nt; ++t) {  // A^-1 u with A's elimination from the solve above
    pair_column(m, ws.kin, ws.wrench_terms[t], ws.pair_u.col(t));
    ws.pair_col = ws.pair_u.col(t);
    for (int d = 0; d < m.nv; ++d)
      if (ws.pair_col[d] != 0) ws.pair_nz.push_back(d);
    ws.pair_nz_begin.push_back(static_cast<int>(ws.pair_nz.size()));
    tree_resolve(m, ws.kin, ws.pair_col, &ws.pair_sol, &ws.tree);
    ws.pair_y.col(t) = ws.pair_sol;
  }
  // u_i touches only its two bodies' ancestors' dofs (12 for two free bodies): the
  // capacitance u_i . A^-1 u_j over those rows, not all nv (a pile of 100 free objects:
  // hundreds of terms, nv 627; the full dot products were 2/3 of its step).
  for (int i = 0; i < nt; ++i) {
    const int* nz = ws.pair_nz.data() + ws.pair_nz_begin[i];
    const int count = ws.pair_nz_begin[i + 1] - ws.pair_nz_begin[i];
    const double* u = ws.pair_u.col(i).data();
    for (int j = 0; j < nt; ++j) {
      const double* y = ws.pair_y.col(j).data();
      double sum = 0;
      for (int k = 0; k < count; ++k) sum += u[nz[k]] * y[nz[k]];
      ws.pair_cap(i, j) = sum;
    }
    ws.pair_cap(i, i) += 1 / ws.wrench_terms[i].weight;
    double alpha = 0;
    for (int k = 0; k < count; ++k) alpha += u[nz[k]] * (*x)[nz[k]];
    ws.pair_alpha[i] = alpha;
  }
  dense_solve(ws.pair_cap, nt, ws.pair_alpha);
  for (int t = 0; t < nt; ++t) *x -= ws.pair_alpha[t] * ws.pair_y.col(t);
  return pd && x->allFinite();
}

bool pbad_iterate(const Model& m, const SimOptions& o, const State& s, PbadStep& p, SimWorkspace& ws) {
  if (p.done) return true;
  ++p.iterations;
  if (o.solver == Solver::Lbfgs) {
    p.done = lbfgs_iterate(m, o, s, p, ws) || p.iterations >= o.lm_max_iterations;
    if (p.done) pbad_energy(m, o, s, p, p.q, ws, true);
    return p.done;
  }
  const std::vector<Mat6>& blocks = o.exact_hessian ? ws.h_exact : ws.h;
  if (!p.step_ready) {
    tree_diagonal(m, ws.kin, ws.h, &ws.diag, &ws.tree);
    ws.rhs = -ws.grad;
  }
  for (int tries = 0; tries < 12; ++tries) {
    if (!(p.step_ready && tries == 0)) {
      lm_armature(m, o, p, p.lambda, ws);
      // An indefinite Newton model (compressed links in a whip, contact) could lead to
      // a saddle: take the Gauss-Newton step (positive definite) at the same damping
      // instead. Raising lambda until the Newton model was definite (1e-6 -> 1e-2 in the
      // whip) left it above the final correction's 1e-4 for several accepted steps:
      // 100-link whip at dt 0.05, 3.57 -> 2.49 iterations per step, same drift, every
      // whip of the sweep bounded with pbad3 and pbad4 (judged with the body-point
      // velocity; with the old joint-space velocity this looked unsafe).
      if (!lm_solve(m, blocks, ws.rhs, &ws.step, ws) &&
          (&blocks == &ws.h || !lm_solve(m, ws.h, ws.rhs, &ws.step, ws))) {
        p.lambda *= 10;
        continue;
      }
    }
    p.step_ready = false;
    const double step_max = ws.step.lpNorm<Eigen::Infinity>();
    ws.q_trial = p.q;
    qpos_integrate(m, ws.q_trial, ws.step, 1.0);
    if (!ws.q_trial.allFinite()) {
      p.lambda *= 10;
      continue;
    }
    const bool tiny = step_max < o.lm_tolerance;
    // The trial is evaluated with derivatives: Newton steps are nearly always
    // accepted, and a rejected one re-evaluates the current point.
    const double e_trial = pbad_energy(m, o, s, p, ws.q_trial, ws, true);
    if (tiny || e_trial <= p.energy) {
      // Decrease at the round-off floor of E (E ~ m/dt^2 |X - Y|^2 + V): converged.
      const bool stalled = p.energy - e_trial < 1e-14 * (std::abs(p.energy) + 1e-300);
      std::swap(p.q, ws.q_trial);
      p.energy = e_trial;
      // Marquardt's original factor 10 both ways: after the whip's indefinite models
      // raised lambda, 0.3 needed ~4 accepted steps to get back below the final
      // correction's 1e-4 (100-link whip at dt 0.05: 4.8 -> 3.6 iterations per step,
      // same trajectory; smooth swings unchanged).
      p.lambda = std::max(p.lambda * 0.1, 1e-12);
      if (tiny || stalled || p.iterations >= o.lm_max_iterations || ws.grad.lpNorm<Eigen::Infinity>() < p.grad_tol)
        p.done = true;
      else if (o.lm_relative_tolerance > 0)
        p.done = final_correction(m, o, p, ws);
      return p.done;
    }
    pbad_energy(m, o, s, p, p.q, ws, true);
    // A rejected step already within 10x the length tolerance: the minimum sits at a
    // kink (a contact's deepest point switching faces), where the gradient never
    // vanishes; shrinking the step further only spends iterations (pile: box_mid flat).
    if (step_max < 10 * o.lm_tolerance) {
      p.done = true;
      return true;
    }
    p.lambda *= 10;
  }
  // No decrease possible: at a minimum to round-off.
  p.done = true;
  return true;
}

}  // namespace pliant::articulated
