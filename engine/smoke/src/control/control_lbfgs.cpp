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
#include "control_trace.h"
#include "pliant/core/error.h"

namespace pliant::smoke {
namespace {

// Iterations the relative-decrease stop looks back (see control_solve_lbfgs).
constexpr int kStopPast = 3;

struct LbfgsObjective {
  LbfgsObjective(const ControlModel& m, control_detail::ForwardOps& ops, Progress& progress, int T, size_t nf)
      : m(m), ops(ops), progress(progress), T(T), nf(nf), f(size_t(T)), g(size_t(T)) {}
  const ControlModel& m;
  control_detail::ForwardOps& ops;
  Progress& progress;
  int T;
  size_t nf;
  // Frame pointers into x and the gradient: objective_d reads and writes them in place
  // (per-frame copies were 2 x T x faces doubles, 0.5 GB at 64^3 x 40, and two passes).
  std::vector<const double*> f;
  std::vector<double*> g;
  double best_f = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x;
  std::vector<double>* history = nullptr;
  control_detail::TraceClock* trace = nullptr;  // every evaluation (it keeps the new bests)
  long evaluations = 0;

  // No cache of the last evaluation: every chunk starts with a fresh one (resumed runs must
  // match) and LBFGS++'s line search never repeats a point, so it never hit; it cost two
  // T x faces copies per evaluation and 0.5 GB at 64^3 x 40.
  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    progress.check_cancelled();
    grad.resize(x.size());
    for (int i = 0; i < T; ++i) {
      f[size_t(i)] = x.data() + size_t(i) * nf;
      g[size_t(i)] = grad.data() + size_t(i) * nf;
    }
    const double E = control_detail::objective_d(m, ops, f.data(), g.data());
    ++evaluations;
    trace->add(E);
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
  control_detail::TraceClock trace(s, cb);
  LbfgsObjective obj(m, ops, progress, T, nf);
  obj.best_x = x;
  obj.history = &s.objective_history;
  obj.trace = &trace;
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
    // Relative-decrease stop over kStopPast iterations (LBFGS++: |f_{k-past} - f_k| <= delta
    // max(|f_k|, |f_{k-past}|, 1)). With past 1 a single step that barely moves the objective
    // ended the run: LBFGS++'s first step has unit length in force space, which from rest
    // toward a disjoint target changes E by ~1e-12 relative (round-off decided whether the
    // 16^2 x 6 toy stopped after 2 iterations at 32.08 or went on to 25.3). Its quasi-Newton
    // scaling makes the third step a real one (test ControlLbfgs.FirstTinyStepsDoNotStopTheRun).
    param.past = kStopPast;
    param.delta = m.tolerance;
    param.max_iterations = std::min(std::max(m.lbfgs_chunk, 1), m.max_iterations - s.iteration);
    double fx = 0;
    int k = 0;
    bool line_search_failed = false;
    // Each chunk starts afresh (no memory) so resumed runs match.
    obj.best_f = std::numeric_limits<double>::infinity();
    obj.best_x = x;
    const size_t history_before = s.objective_history.size();
    try {
      // The solver (its memory: 2 m + 4 vectors of T x faces doubles, 6 GB at 64^3 x 40)
      // lives only for the chunk's minimisation, not through the checkpoint below.
      LBFGSpp::LBFGSSolver<double> solver(param);
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
    trace.sync();
    // Checkpoint first, then report: whoever sees the progress event can rely on
    // the checkpoint being in the take.
    if (cb.on_iteration) cb.on_iteration(s);
    progress.report(std::min(s.iteration, m.max_iterations), fx);
  }
}

}  // namespace pliant::smoke
