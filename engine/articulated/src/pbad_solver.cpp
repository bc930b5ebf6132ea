// PBAD's per-step minimiser (sim.h): Levenberg-Marquardt on the exact or Gauss-Newton
// Hessian through tree_solve, with the accuracy-aware stop, or L-BFGS preconditioned
// by the Gauss-Newton solve. One iteration per pbad_iterate call.
#include <algorithm>
#include <cmath>
#include <stdexcept>
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

// LM's step ws.step for ws.rhs at the current damping: the Newton model's (with the
// exact Hessian) where it is positive definite, else the Gauss-Newton model's at the
// same damping. False if neither is (the caller raises lambda). An indefinite model's
// solve stops after the tree elimination (lm_solve's indefinite_fails).
bool lm_step(const Model& m, const SimOptions& o, SimWorkspace& ws) {
  if (o.exact_hessian && lm_solve(m, ws.h_exact, ws.rhs, &ws.step, ws, true)) return true;
  return lm_solve(m, ws.h, ws.rhs, &ws.step, ws, true);
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
  // Only a positive definite Newton model measures the remaining error here. Taking
  // the Gauss-Newton step where it is indefinite (the step the next iteration would
  // take) cut humanoid100's LM iterations 12.8 -> 9.86 per step, but let a pbad4 whip
  // (40 links, dt 0.03) grow to 3x its energy: not done.
  if (!lm_solve(m, o.exact_hessian ? ws.h_exact : ws.h, ws.rhs, &ws.step, ws, true))
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

}  // namespace

bool pbad_iterate(const Model& m, const SimOptions& o, const State& s, PbadStep& p, SimWorkspace& ws) {
  if (p.done) return true;
  ++p.iterations;
  if (o.solver == Solver::Lbfgs) {
    p.done = lbfgs_iterate(m, o, s, p, ws) || p.iterations >= o.lm_max_iterations;
    if (p.done) pbad_energy(m, o, s, p, p.q, ws, true);
    return p.done;
  }
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
      if (!lm_step(m, o, ws)) {
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
