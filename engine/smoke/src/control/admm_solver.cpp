#include "admm_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "../smoke_workspace.h"
#include "ao_solver.h"
#include "control_coarse_to_fine.h"
#include "control_forward_model.h"
#include "control_trace.h"
#include "nso_solver.h"
#include "spacetime_multigrid_transfer.h"

namespace pliant::smoke {

using control_detail::Vec;
using Series = std::vector<Vec>;

namespace {

// AO divergence penalty relative to beta (AoSolver::div_penalty). Off: measured at 12-30
// iterations, 100 beta halved the objective on circle_to_letter 64^2x40 (800 -> 400) but
// made circle_to_square 32^2x20 worse (14.8 -> 21.7); 10 or 1000 beta helped less.
constexpr double kAoDivPenalty = 0.0;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double norm(const Series& a) {
  double s = 0;
  for (const auto& v : a)
    for (double x : v) s += x * x;
  return std::sqrt(s);
}

double diff_norm(const Series& a, const Series& b) {
  double s = 0;
  for (size_t t = 0; t < a.size(); ++t)
    for (size_t e = 0; e < a[t].size(); ++e) s += (a[t][e] - b[t][e]) * (a[t][e] - b[t][e]);
  return std::sqrt(s);
}

Series to_d(const FaceSeries& f) { return control_detail::to_double(f); }
FaceSeries to_f(const Series& f) { return control_detail::to_float(f); }

// Forces that make the plain forward model follow z (see admm_solver.h).
Series forces_from_velocity(control_detail::ForwardOps& ops, const Series& z) {
  const size_t F = ops.faces();
  const double dt = ops.dt();
  Series f(z.size(), Vec(F, 0.0));
  Vec zr(F, 0.0), a(F, 0.0), next(F);
  for (size_t t = 0; t < z.size(); ++t) {
    ops.advect_velocity(zr, a);
    Vec& ft = f[t];
    for (size_t e = 0; e < F; ++e) ft[e] = z[t][e] - a[e];
    ops.project(ft);
    for (size_t e = 0; e < F; ++e) next[e] = a[e] + ft[e], ft[e] /= dt;
    ops.project(next);
    zr.swap(next);
  }
  return f;
}

}  // namespace

void admm_run(const ControlModel& m, ControlState& s, Progress& progress, const ControlCallbacks& cb,
              std::vector<AdmmIterationStats>* stats) {
  using clock = std::chrono::steady_clock;
  const int T = m.sim.frames;
  // No iteration to run (a level that only polishes, as the shipped scenes' fine level, or
  // a run resumed after its last one): allocate and simulate nothing, leave u, z, lambda
  // out of the state (nothing but ADMM reads them). At 64^3 x 40 that is the start-up
  // re-simulation, 0.4 GB of state (and of every checkpoint), 1.3 GB of series below and
  // the NSO's multigrid (2.6 GB, now built on first use anyway).
  if (s.iteration >= m.max_iterations) return;
  control_detail::TraceClock trace(s, cb);
  // Small grids on one thread (fork/join dominates there on a loaded machine).
  control_detail::SerialBelow serial(model_grid(m.sim).cells() * size_t(std::max(T, 1)), kSpacetimeOmpMinWork);
  control_detail::ForwardOps ops(m, control_detail::kControlPressureTolerance);
  const size_t F = ops.faces();
  // Penalty continuation (a deterministic schedule, so a resumed run knows the beta its
  // stored scaled dual belongs to): beta_k = penalty * min(1, c0 g^k). A small beta first
  // lets AO find a transport path that NSO then makes incompressible; growing beta
  // enforces u = z. The scaled dual lambda = y / beta is rescaled when beta changes.
  auto beta_at = [&](int k) { return admm_penalty_at(m, k); };
  auto sized = [&](const FaceSeries& x) { return int(x.size()) == T && (T == 0 || x[0].size() == F); };
  if (!sized(s.split) || !sized(s.velocity) || !sized(s.dual)) {
    // Start from the trajectory of the current forces (zero: rest).
    control_detail::TrajectoryD tr;
    Series f0 = sized(s.force) ? to_d(s.force) : Series(T, Vec(F, 0.0));
    control_detail::forward_d(m, ops, f0, tr);
    Series z(tr.u.begin() + 1, tr.u.end());
    s.split = to_f(z);
    s.velocity = s.split;
    s.dual.assign(T, std::vector<float>(F, 0.0f));
  }
  Series u = to_d(s.velocity), z = to_d(s.split), lam = to_d(s.dual), c(T, Vec(F)), d(T, Vec(F));
  // Over-relaxation (Boyd et al. 2011, Sec. 3.4.3): uh = alpha u + (1 - alpha) z_prev feeds
  // the NSO and the dual; alpha = 1 uses u itself (bit-identical to plain ADMM).
  const double alpha = m.admm_relaxation;
  Series uh(alpha == 1.0 ? 0 : T, Vec(alpha == 1.0 ? 0 : F));
  const bool balance = m.admm_balance_mu > 0;
  // Best re-simulated objective so far: the history's and the state's forces' (a start
  // from prolonged coarse forces may beat the first fine iterations). A function of the
  // state only, so a resumed run decides the same.
  double best = std::numeric_limits<double>::infinity();
  for (double e : s.objective_history) best = std::min(best, e);
  if (sized(s.force)) {
    control_detail::SerialBelow serial_e(0, 1);
    const double start = control_detail::objective_d(m, ops, to_d(s.force), nullptr);
    trace.add(start);  // the level's first point: its starting forces (rest or prolonged)
    best = std::min(best, start);
  }
  AoSolver ao(m, ops);
  NsoSolver nso(m, ops);
  nso.set_damping(s.nso_damping);
  nso.skip_gap = m.nso_skip_gap;
  progress.stage(m.stage_label.empty() ? "admm" : "admm " + m.stage_label, m.max_iterations);
  while (s.iteration < m.max_iterations) {
    // Stopping rule on the stored residuals, so a run resumed from the checkpoint
    // of the last iteration makes the same decision.
    if (s.iteration >= 2 && !s.primal_residual_history.empty() &&
        s.primal_residual_history.back() < m.tolerance && s.dual_residual_history.back() < m.tolerance)
      break;
    if (admm_stalled(s.objective_history)) break;
    if (admm_progress_below(s.objective_history, m.admm_switch_progress)) break;
    progress.check_cancelled();
    const auto t0 = clock::now();
    AdmmIterationStats it;
    // Residual balancing on top of the continuation: beta is state, the penalty the stored
    // scaled dual belongs to (s.admm_beta, balanced after the previous iteration), times the
    // schedule's growth from k-1 to k. A state without one (fresh, or a checkpoint older than
    // version 5) takes the schedule's beta_{k-1}.
    const double prev = s.iteration == 0 ? beta_at(0) : balance && s.admm_beta > 0 ? s.admm_beta : beta_at(s.iteration - 1);
    const double beta = !balance ? beta_at(s.iteration)
                                 : std::clamp(prev * (s.iteration == 0 ? 1.0 : beta_at(s.iteration) / beta_at(s.iteration - 1)),
                                              1e-3 * m.admm_penalty, 1e3 * m.admm_penalty);
    if (s.iteration > 0) {
      const double ratio = prev / beta;
      if (ratio != 1.0)
        for (auto& v : lam)
          for (double& x : v) x *= ratio;
    }
    for (int t = 0; t < T; ++t)
      for (size_t e = 0; e < F; ++e) c[t][e] = z[t][e] - lam[t][e];
    // AO and the force sweep run ForwardOps' fine-grained loops (one fork/join per
    // upwind sub-step): single-threaded they were 4-9x faster at 128^2 x 40 here.
    std::optional<control_detail::SerialBelow> serial_ao(std::in_place, 0, 1);
    ao.div_penalty = kAoDivPenalty * beta;  // NOLINT: 0 today, kept for experiments
    const AoStats as = ao.solve(u, c, beta, m.ao_iterations);
    serial_ao.reset();
    it.ao_keyframe_error = as.keyframe_error;
    it.ao_steps = as.steps;
    it.ao_s = seconds_since(t0);
    progress.check_cancelled();
    const auto t1 = clock::now();
    if (alpha != 1.0)
      for (int t = 0; t < T; ++t)
        for (size_t e = 0; e < F; ++e) uh[t][e] = alpha * u[t][e] + (1.0 - alpha) * z[t][e];
    const Series& ur = alpha == 1.0 ? u : uh;
    for (int t = 0; t < T; ++t)
      for (size_t e = 0; e < F; ++e) d[t][e] = ur[t][e] + lam[t][e];
    const Series z_prev = z;
    const NsoStats ns = nso.solve(z, d, beta, m.nso_vcycles);
    it.vcycle_factors = ns.vcycle_factors;
    it.nso_lm_steps = ns.lm_steps;
    it.nso_rejected = ns.rejected;
    it.nso_start_gap = ns.start_gap;
    it.nso_skipped = ns.skipped;
    it.nso_s = seconds_since(t1);
    for (int t = 0; t < T; ++t)
      for (size_t e = 0; e < F; ++e) lam[t][e] += ur[t][e] - z[t][e];
    it.primal = diff_norm(u, z) / std::max({norm(u), norm(z), 1e-30});
    it.dual = diff_norm(z, z_prev) / std::max(norm(lam), 1e-30);
    if (balance) {
      // Boyd et al. 2011, Eq. 3.13 on the relative residuals (primal / max(|u|, |z|), dual
      // beta |z - z_prev| / |y|): grow beta when the primal one is mu times the dual,
      // shrink it in the reverse case; the scaled dual y / beta follows. Pure balancing
      // (without the schedule's growth) held beta near 0.05-0.2 and lost to the schedule on
      // the 16^2 letter and square (README, ADMM options).
      const double mu = m.admm_balance_mu, tau = m.admm_balance_tau;
      double next = it.primal > mu * it.dual ? beta * tau : it.dual > mu * it.primal ? beta / tau : beta;
      next = std::clamp(next, 1e-3 * m.admm_penalty, 1e3 * m.admm_penalty);
      if (next != beta)
        for (auto& v : lam)
          for (double& x : v) x *= beta / next;
      s.admm_beta = next;
    }
    const auto t2 = clock::now();
    std::optional<control_detail::SerialBelow> serial_f(std::in_place, 0, 1);
    const Series f = forces_from_velocity(ops, z);
    it.objective = control_detail::objective_d(m, ops, f, nullptr);
    serial_f.reset();
    it.forces_s = seconds_since(t2);
    trace.add(it.objective);
    // The output forces are the best re-simulated ones so far (ADMM is not monotone in E).
    if (it.objective <= best || !sized(s.force)) s.force = to_f(f), best = std::min(best, it.objective);
    s.velocity = to_f(u);
    s.split = to_f(z);
    s.dual = to_f(lam);
    s.nso_damping = nso.damping();
    // Continue from exactly the float values of the checkpoint, so a resumed run and an
    // uninterrupted one take the same path.
    u = to_d(s.velocity), z = to_d(s.split), lam = to_d(s.dual);
    s.objective_history.push_back(it.objective);
    s.primal_residual_history.push_back(it.primal);
    s.dual_residual_history.push_back(it.dual);
    it.beta = beta;
    s.wall_s += seconds_since(t0);
    ++s.iteration;
    if (stats) stats->push_back(it);
    trace.sync();
    // Checkpoint first, then report: whoever sees the progress event can rely on the
    // checkpoint being in the take (as in control_lbfgs.cpp).
    if (cb.on_iteration) cb.on_iteration(s);
    progress.report(s.iteration, it.objective);
  }
}

bool admm_stalled(const std::vector<double>& h) {
  // The best re-simulated objective of the last kWindow iterations is not 0.1% below the
  // best before them. Measured on FLUID 128^2 x 40: iterations 8-10 of 10 left E at
  // 968.5 and cost a third of the run; the polish then does the rest.
  constexpr size_t kWindow = 3, kMinIterations = 6;
  if (h.size() < kMinIterations) return false;
  const double before = *std::min_element(h.begin(), h.end() - kWindow);
  const double recent = *std::min_element(h.end() - kWindow, h.end());
  return recent > before * (1.0 - 1e-3);
}

bool admm_progress_below(const std::vector<double>& h, double fraction) {
  constexpr size_t kMinIterations = 3;
  if (!(fraction > 0) || h.size() < kMinIterations) return false;
  const double before = *std::min_element(h.begin(), h.end() - 1);
  return std::min(before, h.back()) > before * (1.0 - fraction);
}

double admm_penalty_at(const ControlModel& m, int iteration) {
  const double c0 = 0.05, growth = 1.3;  // reaches the scene's penalty after 12 iterations
  return m.admm_penalty * std::min(1.0, c0 * std::pow(growth, iteration));
}

bool admm_coarsen_model(const ControlModel& m, ControlModel& coarse) {
  const MacGrid g = model_grid(m.sim);
  const SpacetimeGrid fine(g, 1);
  if (!fine.coarsenable()) return false;
  const SpacetimeGrid cg = fine.coarsened();
  coarse = m;
  for (int a = 0; a < g.dim; ++a) coarse.sim.n[a] = cg.g.n[a];
  coarse.sim.cell_size_m = 2 * m.sim.cell_size_m;
  auto restrict_density = [&](const std::vector<float>& x) {
    std::vector<double> xf(x.begin(), x.end()), xc(cg.cells());
    restrict_cells(fine, cg, xf.data(), xc.data());
    return std::vector<float>(xc.begin(), xc.end());
  };
  coarse.initial_density = restrict_density(m.initial_density);
  for (auto& k : coarse.keyframes) k.density = restrict_density(k.density);
  if (!m.solid.empty()) {
    std::vector<float> s(m.solid.begin(), m.solid.end());
    const auto sc = restrict_density(s);
    coarse.solid.assign(sc.size(), 0);
    for (size_t i = 0; i < sc.size(); ++i) coarse.solid[i] = sc[i] > 0.5f;
  }
  return true;
}

void control_solve_admm(const ControlModel& m, ControlState& s, Progress& progress, const ControlCallbacks& cb) {
  // Progressive preview: ADMM (and its polish) at a quarter and half resolution first;
  // the fine ADMM starts from the trajectory of the prolonged forces.
  // A coarse level's state (resumed from its checkpoint) continues there, whatever its phase.
  if (m.progressive_preview && (s.phase == 0 || s.level > 0))
    control_coarse_to_fine(m, s, kCoarseToFineLevels, cb, [&](const ControlModel& cm, ControlState& cs, const ControlCallbacks& lcb) {
      control_solve_admm(cm, cs, progress, lcb);
    });
  if (s.phase == 0) {
    admm_run(m, s, progress, cb, nullptr);
    if (m.polish_iterations <= 0) return;
    // Polish phase: numbered after the ADMM's iteration cap; the switch is checkpointed.
    s.phase = 1;
    s.iteration = m.max_iterations;
    if (cb.on_iteration) cb.on_iteration(s);
  }
  ControlModel pm = m;
  pm.max_iterations = m.max_iterations + m.polish_iterations;
  control_solve_lbfgs(pm, s, progress, cb);
}

}  // namespace pliant::smoke
