// L-BFGS baseline (LBFGS++ 0.1.0) over all forces of all frames, with gradients from
// the discrete adjoint (Treuille et al. 2003, McNamara et al. 2004 style).
//
// LBFGS++ 0.1.0 has no per-iteration callback, so the solve runs in chunks of
// kChunk iterations: after each chunk the state is reported (checkpoint) and the
// next chunk starts a fresh L-BFGS memory from the current forces. A run resumed
// from a checkpoint therefore repeats exactly what an uninterrupted run does.
// Settings measured on circle-to-square 32^2 x 20, 200 iterations: memory 10,
// Armijo backtracking, chunks of 20 reach E = 11.5 (IoU 0.80); chunks of 10 stall
// at 13.9, Wolfe backtracking at 14.6, Nocedal-Wright fails at the first step.
#include <LBFGS.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "control_coarse_to_fine.h"
#include "control_forward_model.h"
#include "pliant/core/error.h"

namespace pliant::smoke {
namespace {

using control_detail::Vec;

struct LbfgsObjective {
  LbfgsObjective(const ControlModel& m, control_detail::ForwardOps& ops, Progress& progress, int T, size_t nf)
      : m(m), ops(ops), progress(progress), T(T), nf(nf), f(T, Vec(nf)) {}
  const ControlModel& m;
  control_detail::ForwardOps& ops;
  Progress& progress;
  int T;
  size_t nf;
  std::vector<Vec> f, g;
  // Cache of the last evaluation (each chunk re-evaluates its starting point).
  Eigen::VectorXd last_x, last_grad;
  double last_f = 0;
  bool has_last = false;
  double best_f = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x;
  std::vector<double>* history = nullptr;
  long evaluations = 0;

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    if (has_last && x.size() == last_x.size() && x == last_x) {
      grad = last_grad;
      return last_f;
    }
    progress.check_cancelled();
    has_last = false;  // the cache is rewritten below
    grad.resize(x.size());
    last_x.resize(x.size());
    last_grad.resize(x.size());
    // Per frame: x -> f and the cache copy (T * faces doubles each; serial copies were
    // a few % of a 48^3 evaluation's wall time on 2 threads).
    const bool parallel = nf >= control_detail::kControlParallelCells;
#pragma omp parallel for schedule(static) if (parallel)
    for (int i = 0; i < T; ++i) {
      const double* xi = x.data() + size_t(i) * nf;
      std::copy(xi, xi + nf, f[size_t(i)].begin());
      std::copy(xi, xi + nf, last_x.data() + size_t(i) * nf);
    }
    const double E = control_detail::objective_d(m, ops, f, &g);
#pragma omp parallel for schedule(static) if (parallel)
    for (int i = 0; i < T; ++i) {
      std::copy(g[size_t(i)].begin(), g[size_t(i)].end(), grad.data() + size_t(i) * nf);
      std::copy(g[size_t(i)].begin(), g[size_t(i)].end(), last_grad.data() + size_t(i) * nf);
    }
    ++evaluations;
    last_f = E;
    has_last = true;
    if (E < best_f) {
      best_f = E;
      best_x = x;
      history->push_back(E);
    }
    return E;
  }
};

}  // namespace

void control_solve_lbfgs(const ControlModel& m, ControlState& s, Progress& progress, const ControlCallbacks& cb) {
  control_detail::ForwardOps ops(m, control_detail::kControlPressureTolerance);
  const int T = m.sim.frames;
  const size_t nf = ops.faces();
  if (int(s.force.size()) != T) s = control_init(m);
  // Progressive preview: L-BFGS at a quarter and half resolution first, the fine solve
  // starts from the prolonged forces (control_coarse_to_fine.h).
  if (m.progressive_preview)
    control_coarse_to_fine(m, s, kCoarseToFineLevels, cb, [&](const ControlModel& cm, ControlState& cs, const ControlCallbacks& lcb) {
      control_solve_lbfgs(cm, cs, progress, lcb);
    });
  Eigen::VectorXd x(Eigen::Index(size_t(T) * nf));
  for (int i = 0; i < T; ++i) {
    if (s.force[i].size() != nf) throw std::invalid_argument("control_solve_lbfgs: state does not match the model");
    for (size_t e = 0; e < nf; ++e) x[Eigen::Index(size_t(i) * nf + e)] = s.force[i][e];
  }
  LbfgsObjective obj(m, ops, progress, T, nf);
  obj.best_x = x;
  obj.history = &s.objective_history;
  progress.stage(m.stage_label.empty() ? "lbfgs" : "lbfgs " + m.stage_label, m.max_iterations);

  while (s.iteration < m.max_iterations && !s.lbfgs_stopped) {
    // The objective at the end of the previous chunk (from the state, so a resumed
    // run makes the same stopping decision).
    const double previous =
        s.objective_history.empty() ? std::numeric_limits<double>::infinity() : s.objective_history.back();
    const auto t0 = std::chrono::steady_clock::now();
    LBFGSpp::LBFGSParam<double> param;
    param.m = 10;
    param.epsilon = 1e-12;
    param.epsilon_rel = 1e-9;
    param.past = 1;
    param.delta = m.tolerance;
    param.max_iterations = std::min(std::max(m.lbfgs_chunk, 1), m.max_iterations - s.iteration);
    LBFGSpp::LBFGSSolver<double> solver(param);
    double fx = 0;
    int k = 0;
    bool line_search_failed = false;
    // Each chunk starts afresh (no memory, no cache) so resumed runs match.
    obj.best_f = std::numeric_limits<double>::infinity();
    obj.best_x = x;
    obj.has_last = false;
    const size_t history_before = s.objective_history.size();
    try {
      k = solver.minimize(obj, x, fx);
    } catch (const CancelledError&) {
      throw;
    } catch (const std::exception&) {
      // The line search failed (a non-descent quasi-Newton direction at a kink of
      // the upwind flux, or round-off near the optimum): restart from the best point
      // with a fresh memory; stop when a whole chunk made no progress.
      line_search_failed = true;
      k = std::max(1, int(s.objective_history.size() - history_before) - 1);
    }
    if (obj.best_f < fx || line_search_failed) {
      x = obj.best_x;
      fx = obj.best_f;
    }
    const bool stalled = line_search_failed && s.objective_history.size() - history_before <= 1;
    s.iteration += std::max(k, 1);
    // The state holds floats; continue from exactly those values so a run resumed
    // from this checkpoint and an uninterrupted run take the same path.
    for (int i = 0; i < T; ++i)
      for (size_t e = 0; e < nf; ++e) {
        float& v = s.force[i][e];
        v = float(x[Eigen::Index(size_t(i) * nf + e)]);
        x[Eigen::Index(size_t(i) * nf + e)] = v;
      }
    s.wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bool converged = (!line_search_failed && k < param.max_iterations) ||
                           std::abs(previous - fx) <= m.tolerance * std::max(std::abs(fx), 1e-300);
    // In the state, so a run resumed from this checkpoint stops here too.
    s.lbfgs_stopped = stalled || converged;
    // Checkpoint first, then report: whoever sees the progress event can rely on
    // the checkpoint being in the take.
    if (cb.on_iteration) cb.on_iteration(s);
    progress.report(std::min(s.iteration, m.max_iterations), fx);
  }
}

}  // namespace pliant::smoke
