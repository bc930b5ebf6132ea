// LM, L-BFGS and the hybrid (see optimizer.h).
#include "pliant/soft/optimizer.h"

#include <Eigen/Dense>
#include <LBFGSpp/Param.h>  // first: the line-search headers do not include it
#include <LBFGSpp/LineSearchBacktracking.h>
#include <LBFGSpp/LineSearchBracketing.h>
#include <LBFGSpp/LineSearchNocedalWright.h>
#include <cmath>
#include <deque>
#include <limits>
#include <stdexcept>

namespace pliant::soft {

const char* optimizer_name(OptimizerKind k) {
  switch (k) {
    case OptimizerKind::Hybrid: return "hybrid";
    case OptimizerKind::LM: return "lm";
    case OptimizerKind::LBFGS: return "lbfgs";
    case OptimizerKind::Spacetime: return "spacetime";
  }
  return "?";
}

const char* line_search_name(OptimizerSettings::LineSearch l) {
  switch (l) {
    case OptimizerSettings::LineSearch::Armijo: return "armijo";
    case OptimizerSettings::LineSearch::Wolfe: return "wolfe";
    case OptimizerSettings::LineSearch::StrongWolfe: return "strong_wolfe";
    case OptimizerSettings::LineSearch::Bracketing: return "bracketing";
    case OptimizerSettings::LineSearch::NocedalWright: return "nocedal_wright";
  }
  return "?";
}

OptimizerSettings::LineSearch parse_line_search(const std::string& name) {
  using L = OptimizerSettings::LineSearch;
  for (L l : {L::Armijo, L::Wolfe, L::StrongWolfe, L::Bracketing, L::NocedalWright})
    if (name == line_search_name(l)) return l;
  throw std::invalid_argument("unknown L-BFGS line search '" + name +
                              "' (armijo, wolfe, strong_wolfe, bracketing, nocedal_wright)");
}

Eigen::MatrixXd fd_jacobian(const ResidualFn& r, const Eigen::VectorXd& theta, const Eigen::VectorXd& r0,
                            double step) {
  const int n = int(theta.size());
  Eigen::MatrixXd J(r0.size(), n);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd t = theta;
    const double h = step * std::max(1.0, std::abs(theta[i]));
    t[i] += h;
    J.col(i) = (r(t) - r0) / h;
    // A failed rollout (NaN residuals) gives no derivative information along i.
    if (!J.col(i).allFinite()) J.col(i).setZero();
  }
  return J;
}

void broyden_update(Eigen::MatrixXd& J, const Eigen::VectorXd& d, const Eigen::VectorXd& dr) {
  const double dd = d.squaredNorm();
  if (!(dd > 0) || !dr.allFinite()) return;
  // Broyden's "good" rank-1 update (Broyden 1965; Madsen, Nielsen, Tingleff 2004,
  // eq. 3.32): the smallest change (Frobenius) with J_new d = dr.
  J.noalias() += ((dr - J * d) / dd) * d.transpose();
}

namespace {
// The Levenberg-Marquardt step: (J^T J + lambda diag(J^T J)) d = -g (Marquardt's scaling).
Eigen::VectorXd lm_step(const Eigen::MatrixXd& JtJ, const Eigen::VectorXd& g, double lambda) {
  Eigen::MatrixXd A = JtJ;
  A.diagonal() += lambda * (JtJ.diagonal().array() + 1e-9).matrix();
  return A.ldlt().solve(-g);
}

// Length of d in Marquardt's scaling, |diag(J^T J)^(1/2) d|: the trust region's norm.
double scaled_norm(const Eigen::MatrixXd& JtJ, const Eigen::VectorXd& d) {
  return std::sqrt((JtJ.diagonal().array() + 1e-9).matrix().dot(d.cwiseAbs2()));
}

// The LM step whose scaled length is about `radius` (Moré 1978: the damping is the
// trust region's multiplier): the undamped step (lambda 1e-9) if it is shorter,
// otherwise lambda by bisection in log lambda to within 10%; an n x n LDLT per probe
// (n = tens), nothing next to a rollout. lambda holds the damping used.
Eigen::VectorXd radius_step(const Eigen::MatrixXd& JtJ, const Eigen::VectorXd& g, double radius,
                            double& lambda) {
  double lo = 1e-9;
  Eigen::VectorXd d = lm_step(JtJ, g, lo);
  if (scaled_norm(JtJ, d) <= 1.1 * radius) {
    lambda = lo;
    return d;
  }
  // Bracket: the step at lo is too long, the one at hi (kept in d) is not.
  double hi = std::max(lambda, 1e-6);
  for (int k = 0; k < 60 && scaled_norm(JtJ, d = lm_step(JtJ, g, hi)) > 1.1 * radius; ++k) lo = hi, hi *= 4;
  for (int k = 0; k < 40 && scaled_norm(JtJ, d) < 0.9 * radius; ++k) {
    const double mid = std::sqrt(lo * hi);
    Eigen::VectorXd dm = lm_step(JtJ, g, mid);
    if (scaled_norm(JtJ, dm) > 1.1 * radius) {
      lo = mid;
    } else {
      hi = mid;
      d = std::move(dm);
    }
  }
  lambda = hi;
  return d;
}
// A restored memory must fit n parameters and its own residual count (the
// deserializer checks the same; this guards hand-made states).
bool memory_consistent(const OptimizerMemory& m, int n) {
  const Eigen::Index rows = m.r.size();
  auto fits = [&](const Eigen::MatrixXd& A) { return A.size() == 0 || (A.rows() == rows && A.cols() == n); };
  auto vec = [&](const Eigen::VectorXd& v) { return v.size() == 0 || v.size() == n; };
  if (!fits(m.J) || !fits(m.J_at) || !vec(m.g_prev) || !vec(m.theta_prev) || m.S.size() != m.Y.size()) return false;
  for (size_t i = 0; i < m.S.size(); ++i)
    if (m.S[i].size() != n || m.Y[i].size() != n) return false;
  return true;
}

// Iterations at the end of kinds[from..] that accepted nothing ("...-rejected").
int trailing_rejections(const std::vector<std::string>& kinds, size_t from) {
  int n = 0;
  for (size_t i = kinds.size(); i > from && kinds[i - 1].ends_with("-rejected"); --i) ++n;
  return n;
}
}  // namespace

void optimize(const ResidualFn& rf, const OptimizerSettings& settings, OptimizerState& st,
              const IterationFn& on_iteration, const JacobianFn& jacobian, const ResidualJacobianFn& fused) {
  const int n = int(st.theta.size());
  const bool fuse = settings.fused_trials && static_cast<bool>(fused);
  // Deferred sensitivities: a trial's rollout first, its Jacobian half only once the
  // trial is accepted (same bits as the one-pass J, so the same path).
  const bool defer = fuse && static_cast<bool>(fused.deferred);
  // Everything a later iteration reads lives in st.memory (optimizer.h), so the state
  // handed to on_iteration is complete: a checkpoint of it continues exactly.
  OptimizerMemory& mem = st.memory;
  const bool resumed = mem.theta.size() == n && mem.r.size() > 0 && mem.theta == st.theta;
  if (resumed && !memory_consistent(mem, n))
    throw std::invalid_argument("optimize: the state's memory does not fit its " + std::to_string(n) +
                                " parameters");
  if (!resumed) mem = OptimizerMemory();
  // Fused trials: the exact Jacobian at st.theta, from the evaluation that gave r
  // (empty when that evaluation's Jacobian was not finite).
  Eigen::MatrixXd& J_at = mem.J_at;
  // Jt: the trial's Jacobian, or (deferred) `later` gives it; jacobian_of takes it.
  auto evaluate = [&](const Eigen::VectorXd& t, Eigen::MatrixXd& Jt, DeferredJacobian& later) -> Eigen::VectorXd {
    ++st.evaluations;
    if (!fuse) return rf(t);
    Eigen::VectorXd rt;
    if (defer) later = fused.deferred(t, rt);
    else Jt = fused(t, rt);
    return rt;
  };
  auto jacobian_of = [](Eigen::MatrixXd& Jt, DeferredJacobian& later) -> Eigen::MatrixXd {
    if (later) Jt = later(), later = {};
    if (!Jt.allFinite()) Jt.resize(0, 0);
    return std::move(Jt);
  };
  Eigen::VectorXd& r = mem.r;
  if (!resumed) {
    DeferredJacobian later;
    r = evaluate(st.theta, J_at, later), mem.theta = st.theta;
    J_at = jacobian_of(J_at, later);
  }
  // The point J_at belongs to: reused only while it is st.theta.
  Eigen::VectorXd J_at_theta = st.theta;
  st.objective = 0.5 * r.squaredNorm();
  if (st.history.empty()) st.history.push_back(st.objective);
  const double f_initial = st.history.front();
  // L-BFGS memory.
  std::deque<Eigen::VectorXd>& S = mem.S;
  std::deque<Eigen::VectorXd>& Y = mem.Y;
  Eigen::VectorXd& g_prev = mem.g_prev;
  Eigen::VectorXd& theta_prev = mem.theta_prev;
  OptimizerSettings s = settings;
  if (s.kind == OptimizerKind::Spacetime) s.kind = OptimizerKind::Hybrid;  // see optimizer.h
  if (s.kind == OptimizerKind::Hybrid) s.lbfgs_line_search = s.hybrid_lbfgs_line_search;
  bool lbfgs = s.kind == OptimizerKind::LBFGS || (s.kind == OptimizerKind::Hybrid && st.in_lbfgs);
  int& lm_stalls = mem.lm_stalls;
  if (st.iteration == 0) st.lambda = s.lambda_initial;
  // LM's Jacobian carried to the next iteration (Broyden-updated after an accepted
  // step) and how many iterations in a row have used an updated one.
  Eigen::MatrixXd& J = mem.J;
  int& reused = mem.reused;
  // Length of the last accepted LM step: the hybrid's first L-BFGS step has it.
  double& last_lm_step = mem.last_lm_step;
  // Trust-region damping: the radius in Marquardt's scaling (< 0: not set yet, the
  // next LM step has lambda's length and sets it).
  double& radius = mem.radius;
  const bool trust = s.lm_damping == OptimizerSettings::Damping::TrustRegion;
  // Length of the last accepted L-BFGS step: a restart's first step has it.
  double& last_lbfgs_step = mem.last_lbfgs_step;
  // LBFGS++'s line searches evaluate f and the gradient together at every trial:
  // the fused pass when given, else a rollout and a Jacobian. The last evaluation is
  // kept so the accepted point's residuals and Jacobian need no second pass.
  Eigen::VectorXd ls_x, ls_r;
  Eigen::MatrixXd ls_J;
  // The search's start, direction, f0 and g.d (deferred sensitivities: see below).
  Eigen::VectorXd ls_xp, ls_d;
  double ls_f0 = 0, ls_dg = 0;
  const bool ls_backtracking = s.lbfgs_line_search == OptimizerSettings::LineSearch::Wolfe ||
                               s.lbfgs_line_search == OptimizerSettings::LineSearch::StrongWolfe;
  LBFGSpp::LBFGSParam<double> ls_param;
  ls_param.max_linesearch = 20;
  auto f_and_grad = [&](const Eigen::VectorXd& x, Eigen::VectorXd& grad) -> double {
    ++st.evaluations;
    if (defer && ls_backtracking) {
      // LBFGS++'s backtracking search reads the gradient only where Armijo's condition
      // f <= f0 + c1 step g.d holds; where it fails by a clear margin (half the asked
      // decrease, so the step recovered from x cannot flip the test) J is not formed.
      DeferredJacobian later = fused.deferred(x, ls_r);
      ls_x = x;
      const double fx = 0.5 * ls_r.squaredNorm();
      const double step = ls_d.squaredNorm() > 0 ? (x - ls_xp).dot(ls_d) / ls_d.squaredNorm() : 0;
      if (std::isfinite(fx) && fx > ls_f0 + 0.5 * step * ls_param.ftol * ls_dg) {
        ls_J.resize(0, 0);
        grad.setZero(n);
        return fx;
      }
      ls_J = later ? later() : Eigen::MatrixXd();
    } else if (fused) {
      ls_J = fused(x, ls_r);
    } else {
      ls_r = rf(x);
      ls_J = jacobian ? jacobian(x, ls_r) : Eigen::MatrixXd();
      if (ls_J.size()) {
        ++st.evaluations;
      } else if (ls_r.allFinite()) {
        ls_J = fd_jacobian(rf, x, ls_r, s.fd_step);
        st.evaluations += n;
      }
    }
    ls_x = x;
    const double fx = 0.5 * ls_r.squaredNorm();
    // A failed rollout: a huge finite value (not inf, which turns Nocedal-Wright's
    // interpolation into NaN) makes every LBFGS++ search shorten the step.
    if (!std::isfinite(fx) || ls_J.rows() != ls_r.size() || !ls_J.allFinite()) {
      grad.setZero(n);
      ls_J.resize(0, 0);
      return 1e100;
    }
    grad = ls_J.transpose() * ls_r;
    return fx;
  };
  // One line search along d from st.theta (objective f0, gradient g); on success moves
  // st.theta, r, st.objective, J_at. A search that throws (no Wolfe point in 20 trials,
  // step out of range) or ends without a decrease fails.
  auto wolfe_step = [&](const Eigen::VectorXd& d, const Eigen::VectorXd& g, double f0, Eigen::VectorXd& r) {
    LBFGSpp::LBFGSParam<double>& param = ls_param;
    param.linesearch = s.lbfgs_line_search == OptimizerSettings::LineSearch::Wolfe
                           ? LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE
                           : LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
    Eigen::VectorXd x = st.theta, grad = g;
    const Eigen::VectorXd xp = st.theta;
    double fx = f0, step = 1;
    ls_xp = xp, ls_d = d, ls_f0 = f0, ls_dg = g.dot(d);
    try {
      switch (s.lbfgs_line_search) {
        case OptimizerSettings::LineSearch::Bracketing:
          LBFGSpp::LineSearchBracketing<double>::LineSearch(f_and_grad, fx, x, grad, step, d, xp, param);
          break;
        case OptimizerSettings::LineSearch::NocedalWright:
          LBFGSpp::LineSearchNocedalWright<double>::LineSearch(f_and_grad, fx, x, grad, step, d, xp, param);
          break;
        default:
          LBFGSpp::LineSearchBacktracking<double>::LineSearch(f_and_grad, fx, x, grad, step, d, xp, param);
      }
    } catch (const std::exception&) {
      return false;
    }
    if (!(std::isfinite(fx) && fx < f0)) return false;
    if (ls_x.size() != n || ls_x != x) f_and_grad(x, grad);  // the search ended on an earlier trial
    if (!ls_J.size()) return false;
    st.theta = x, r = ls_r, st.objective = 0.5 * ls_r.squaredNorm();
    J_at = ls_J, J_at_theta = st.theta;
    return true;
  };
  // Rejections that end the run: pure LM and L-BFGS stop at a wholly rejected
  // iteration; the hybrid after three in a row, since the third began from a fresh LM
  // damping or an empty L-BFGS memory at the same theta, so every later iteration would
  // repeat one of the last two exactly (up to 12 or 20 rollouts each, for nothing).
  // Read from step_kinds, so a resumed run stops where the uninterrupted one does; a
  // run without exact memory (new, or its scene changed) counts only its own.
  const size_t kinds_from = resumed ? 0 : st.step_kinds.size();
  const int stop_rejections = s.kind == OptimizerKind::Hybrid ? 3 : 1;
  while (st.iteration < s.max_iterations) {
    if (st.objective <= s.tolerance * f_initial || (s.target >= 0 && st.objective <= s.target)) break;
    if (trailing_rejections(st.step_kinds, kinds_from) >= stop_rejections) break;
    const double f0 = st.objective;
    bool accepted = false;
    std::string kind;
    // Reuse step: one LM trial on the Broyden-updated Jacobian (one rollout instead
    // of n + 1). Taken when it decreases the objective and its gain is at least a
    // quarter of what the model predicts; otherwise the Jacobian is recomputed by
    // finite differences and the iteration proceeds as plain LM from there.
    if (!fuse && !lbfgs && J.size() && reused < s.broyden_reuse) {
      const Eigen::VectorXd d = lm_step(J.transpose() * J, J.transpose() * r, st.lambda);
      const Eigen::VectorXd t = st.theta + d;
      const Eigen::VectorXd rn = rf(t);
      ++st.evaluations;
      const double fn = 0.5 * rn.squaredNorm();
      const double predicted = f0 - 0.5 * (r + J * d).squaredNorm();
      if (std::isfinite(fn) && fn < f0 && (f0 - fn) >= 0.25 * predicted) {
        broyden_update(J, d, rn - r);
        last_lm_step = d.norm();
        st.theta = t, r = rn, st.objective = fn;
        st.lambda = std::max(st.lambda / 3, 1e-9);
        ++reused;
        accepted = true;
        kind = "lm-broyden";
      }
    }
    if (!accepted && J_at.size() && J_at_theta.size() == n && J_at_theta == st.theta) {
      reused = 0;
      J = J_at;  // paid for with the rollout that gave r
    } else if (!accepted) {
      reused = 0;
      if (jacobian) J = jacobian(st.theta, r);
      if (jacobian && J.size()) {
        st.evaluations += 1;
      } else {
        J = fd_jacobian(rf, st.theta, r, s.fd_step);
        st.evaluations += n;
      }
    }
    const Eigen::VectorXd g = accepted ? Eigen::VectorXd() : Eigen::VectorXd(J.transpose() * r);
    // After an accepted Broyden step nothing more happens this iteration.
    if (!accepted && !lbfgs) {
      kind = "lm";
      const Eigen::MatrixXd JtJ = J.transpose() * J;
      int rejected_tries = 0;
      for (int tries = 0; tries < 12 && !accepted; ++tries) {
        const Eigen::VectorXd d = trust && radius > 0 ? radius_step(JtJ, g, radius, st.lambda)
                                                      : lm_step(JtJ, g, st.lambda);
        const double len = scaled_norm(JtJ, d);
        if (trust && radius < 0) radius = len;
        const Eigen::VectorXd t = st.theta + d;
        Eigen::MatrixXd Jt;
        DeferredJacobian later;
        const Eigen::VectorXd rn = evaluate(t, Jt, later);
        const double fn = 0.5 * rn.squaredNorm();
        if (std::isfinite(fn) && fn < f0) {
          if (s.broyden_reuse > 0 && !fuse) broyden_update(J, d, rn - r);
          if (trust) {
            // Gain ratio (actual over the model's decrease f0 - |r + J d|^2 / 2) sets
            // the next radius (Moré 1978): < 1/4 halve, > 3/4 at least twice the step.
            const double rho = (f0 - fn) / std::max(f0 - 0.5 * (r + J * d).squaredNorm(), 1e-300);
            if (rho < 0.25) radius = 0.5 * len;
            else if (rho > 0.75) radius = std::max(radius, 2 * len);
          } else {
            st.lambda = std::max(st.lambda / 3, 1e-9);
          }
          last_lm_step = d.norm();
          st.theta = t, r = rn, st.objective = fn;
          J_at = jacobian_of(Jt, later), J_at_theta = st.theta;
          accepted = true;
        } else {
          // Trust region: half the failed step's length (its lambda grows as needed:
          // with few residuals, lambda x 4 barely shortened the step, e.g. the T-shape
          // high jump's 83.7 -> 78 over four rejected trials).
          if (trust) radius = 0.5 * len;
          else st.lambda *= 4;
          ++rejected_tries;
        }
      }
      if (!accepted) J.resize(0, 0);
      // LM stalls when its quadratic model fails (a try was rejected, lambda grew)
      // and the accepted step still gained little; two such steps in a row, or a
      // wholly rejected one, hand over to L-BFGS. Small gains on first tries are LM
      // still lowering its damping (the spider's first steps gain 2-5% each, then
      // 15-75%): leaving then made the hybrid stop at 12% where LM reaches 0.7%.
      const bool stalled = rejected_tries > 0 && (f0 - st.objective) < s.stall * f0;
      lm_stalls = !accepted ? 2 : stalled ? lm_stalls + 1 : 0;
      if (s.kind == OptimizerKind::Hybrid && lm_stalls >= 2) {
        lm_stalls = 0;
        lbfgs = true;  // next iteration(s) by L-BFGS
        S.clear(), Y.clear();
        J.resize(0, 0);
      }
      theta_prev.resize(0);
    } else if (!accepted) {
      kind = "lbfgs";
      if (theta_prev.size()) {
        const Eigen::VectorXd sv = st.theta - theta_prev, yv = g - g_prev;
        if (sv.dot(yv) > 1e-12 * sv.norm() * yv.norm()) {
          S.push_back(sv), Y.push_back(yv);
          if (int(S.size()) > std::max(1, s.lbfgs_memory)) S.pop_front(), Y.pop_front();
        }
      }
      theta_prev = st.theta, g_prev = g;
      // A restart (pure L-BFGS, after a failed line search) retries from here with
      // the curvature pairs dropped.
      for (bool restarted = false;; restarted = true) {
        // Two-loop recursion (Nocedal & Wright 2006, Alg. 7.4).
        Eigen::VectorXd q = g;
        std::vector<double> a(S.size());
        for (int i = int(S.size()) - 1; i >= 0; --i) {
          a[i] = S[i].dot(q) / Y[i].dot(S[i]);
          q -= a[i] * Y[i];
        }
        if (!S.empty())
          q *= S.back().dot(Y.back()) / Y.back().squaredNorm();
        else if (restarted && last_lbfgs_step > 0)
          q *= last_lbfgs_step / std::max(g.norm(), 1e-300);
        else if (last_lm_step > 0 || s.lbfgs_initial_step > 0)
          q *= (last_lm_step > 0 ? last_lm_step : s.lbfgs_initial_step) / std::max(g.norm(), 1e-300);
        for (size_t i = 0; i < S.size(); ++i) q += S[i] * (a[i] - Y[i].dot(q) / Y[i].dot(S[i]));
        Eigen::VectorXd d = -q;
        if (g.dot(d) >= 0) d = -g;
        if (s.lbfgs_line_search == OptimizerSettings::LineSearch::Armijo) {
          double alpha = 1;
          for (int ls = 0; ls < 20; ++ls) {
            const Eigen::VectorXd t = st.theta + alpha * d;
            Eigen::MatrixXd Jt;
            DeferredJacobian later;
            const Eigen::VectorXd rn = evaluate(t, Jt, later);
            const double fn = 0.5 * rn.squaredNorm();
            if (std::isfinite(fn) && fn <= f0 + 1e-4 * alpha * g.dot(d) && fn < f0) {
              st.theta = t, r = rn, st.objective = fn;
              J_at = jacobian_of(Jt, later), J_at_theta = st.theta;
              accepted = true;
              break;
            }
            alpha *= 0.5;
          }
        } else {
          accepted = wolfe_step(d, g, f0, r);
        }
        if (accepted) {
          last_lbfgs_step = (st.theta - theta_prev).norm();
          if (restarted) kind = "lbfgs-restart";
          break;
        }
        if (s.kind != OptimizerKind::LBFGS || S.empty() || st.lbfgs_restarts_used >= s.lbfgs_restarts) break;
        S.clear(), Y.clear();
        ++st.lbfgs_restarts_used;
      }
      if (s.kind == OptimizerKind::Hybrid && (!accepted || (f0 - st.objective) < s.stall * f0 * 0.2)) {
        lbfgs = false;  // back to LM with a fresh damping (and a fresh Jacobian)
        J.resize(0, 0);
        st.lambda = s.lambda_initial;
        radius = -1;
      }
    }
    st.in_lbfgs = lbfgs;
    // A Jacobian of an earlier point is never used again (accepted steps strictly
    // decrease the objective, so theta does not return to it): drop it, so the memory
    // holds only what belongs to st.theta.
    if (J_at.size() && J_at_theta != st.theta) J_at.resize(0, 0);
    // With fused trials the carried J is dead too: the next iteration takes J_at or a
    // fresh Jacobian before reading it (no Broyden reuse step).
    if (fuse && J.size()) J.resize(0, 0);
    mem.theta = st.theta;
    ++st.iteration;
    st.history.push_back(st.objective);
    st.step_kinds.push_back(accepted ? kind : kind + "-rejected");
    if (on_iteration && !on_iteration(st)) break;
  }
}

}  // namespace pliant::soft
