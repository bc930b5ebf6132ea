// Converged comparison (converged_comparison.h). Clock: process CPU seconds (the bench
// runs with OMP_NUM_THREADS=1, so this is single-thread CPU time, immune to the load of a
// shared machine); the re-simulations that check an L-BFGS iterate are not charged.
#include "converged_comparison.h"

#include <LBFGS.h>
#include <sys/resource.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>
#include <algorithm>
#include <array>

#include "control_coarse_to_fine.h"
#include "control_forward_model.h"
#include "control_trace.h"

namespace pliant::smoke::bench {
namespace {

using control_detail::Vec;

double process_cpu_s() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}
double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
double load_average() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

// Thrown from the objective to end the L-BFGS run (LBFGS++ has no callback).
struct StopRun {
  const char* reason;
};

// Objective for LBFGS++ with the bench's bookkeeping: the charged CPU clock, the best
// point, its history, and the stop conditions (target reached, budget, deadline).
struct BudgetedObjective {
  const ControlModel& m;
  control_detail::ForwardOps ops;
  int T;
  size_t nf;
  std::vector<Vec> f, g;
  double c0 = 0, uncharged = 0, budget = 0, target = 0, deadline = 0;
  double best = std::numeric_limits<double>::infinity(), reached_s = -1, reached_check = 0;
  Eigen::VectorXd best_x;
  long evaluations = 0;
  nlohmann::json history = nlohmann::json::array();  // [cpu_s, E] at each new best
  double next_log = 0;

  BudgetedObjective(const ControlModel& m, double c0)
      : m(m), ops(m, control_detail::kControlPressureTolerance), T(m.sim.frames), nf(ops.faces()),
        f(T, Vec(nf)), c0(c0) {}
  double charged() const { return process_cpu_s() - c0 - uncharged; }

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    if (charged() > budget) throw StopRun{"budget"};
    if (deadline > 0 && unix_now() > deadline) throw StopRun{"deadline"};
    for (int i = 0; i < T; ++i) std::copy(x.data() + size_t(i) * nf, x.data() + size_t(i + 1) * nf, f[i].begin());
    const double E = control_detail::objective_d(m, ops, f, &g);
    grad.resize(x.size());
    for (int i = 0; i < T; ++i) std::copy(g[i].begin(), g[i].end(), grad.data() + size_t(i) * nf);
    ++evaluations;
    const double t = charged();
    if (E < best) {
      best = E;
      best_x = x;
      history.push_back({t, E});
      if (t >= next_log) {
        std::fprintf(stderr, "  lbfgs %.1f s cpu: E %.6g (target %.6g), %ld evaluations, load %.1f\n", t, E, target,
                     evaluations, load_average());
        next_log = t + 30;
      }
      if (E <= target) {
        // Re-simulate the forces as the take stores them (float) with the plain forward
        // model (not charged) before calling the target reached.
        const double u0 = process_cpu_s();
        reached_check = control_objective(m, control_detail::to_float(f), nullptr);
        uncharged += process_cpu_s() - u0;
        if (reached_check <= target * (1 + 1e-6)) {
          reached_s = t;
          throw StopRun{"reached"};
        }
      }
    }
    return E;
  }
};

struct LbfgsResult {
  bool reached = false;
  std::string stop_reason;
  double time_s = 0, best = 0, check = 0;
  long evaluations = 0;
  int restarts = 0;
  FaceSeries force;
  nlohmann::json history;
  std::vector<std::array<double, 2>> trace;  // the whole history, for the milestones
};

// One continuous L-BFGS run from `start` (memory 10, LBFGS++'s Armijo backtracking, as
// control_lbfgs.cpp) until E <= target, the CPU budget, or its own stop. A failed line
// search (a kink of the upwind flux) restarts from the best point with a fresh memory, as
// the production solver does; a restart that gains nothing ends the run.
LbfgsResult run_lbfgs(const ControlModel& m, const FaceSeries& start, double c0, double budget, double target,
                      double deadline) {
  BudgetedObjective obj(m, c0);
  obj.budget = budget;
  obj.target = target;
  obj.deadline = deadline;
  const size_t nf = obj.nf;
  Eigen::VectorXd x(Eigen::Index(size_t(obj.T) * nf));
  for (int i = 0; i < obj.T; ++i)
    for (size_t e = 0; e < nf; ++e) x[Eigen::Index(size_t(i) * nf + e)] = start[i][e];
  obj.best_x = x;
  LbfgsResult r;
  for (;;) {
    LBFGSpp::LBFGSParam<double> param;
    param.m = 10;
    param.epsilon = 1e-12;
    param.epsilon_rel = 1e-9;
    param.past = 3;  // the production stop's look-back (control_lbfgs.cpp kStopPast)
    param.delta = 1e-9;
    param.max_iterations = 0;  // unlimited: the budget ends the run
    LBFGSpp::LBFGSSolver<double> solver(param);
    const double before = obj.best;
    double fx = 0;
    try {
      solver.minimize(obj, x, fx);
      r.stop_reason = "converged";  // gradient or objective change below LBFGS++'s tolerances
      break;
    } catch (const StopRun& s) {
      r.stop_reason = s.reason;
      break;
    } catch (const std::exception&) {
      x = obj.best_x;
      if (!(obj.best < before * (1 - 1e-9))) {
        r.stop_reason = "line_search_failed";
        break;
      }
      ++r.restarts;
    }
  }
  r.reached = obj.reached_s >= 0;
  r.time_s = r.reached ? obj.reached_s : obj.charged();
  r.best = obj.best;
  r.check = obj.reached_check;
  r.evaluations = obj.evaluations;
  Eigen::VectorXd& b = obj.best_x;
  r.force.assign(obj.T, std::vector<float>(nf));
  for (int i = 0; i < obj.T; ++i)
    for (size_t e = 0; e < nf; ++e) r.force[i][e] = float(b[Eigen::Index(size_t(i) * nf + e)]);
  for (const auto& p : obj.history) r.trace.push_back({p[0].get<double>(), p[1].get<double>()});
  // Thin the history to at most ~60 points (keep the first and last).
  const auto& h = obj.history;
  const size_t stride = std::max<size_t>(1, h.size() / 60);
  r.history = nlohmann::json::array();
  for (size_t i = 0; i < h.size(); ++i)
    if (i % stride == 0 || i + 1 == h.size()) r.history.push_back(h[i]);
  return r;
}

nlohmann::json keyframes_json(const ControlMetrics& cm) {
  nlohmann::json k = nlohmann::json::array();
  for (const auto& x : cm.keyframes) k.push_back({{"frame", x.frame}, {"iou", x.iou}, {"relative_l2", x.relative_l2}});
  return k;
}

// CPU seconds at which a best-so-far trace first reaches E <= target; < 0: never.
double time_to(const std::vector<std::array<double, 2>>& trace, double target) {
  for (const auto& p : trace)
    if (p[1] <= target) return p[0];
  return -1;
}

// Time to shared milestones (intermediate objectives), Pliant's trace against the
// baseline's: the worse of the two final objectives (both reach it) and multiples of E*.
// speedup = L-BFGS time / Pliant's; null where a side never gets there.
nlohmann::json milestones_json(const std::vector<std::array<double, 2>>& pliant,
                               const std::vector<std::array<double, 2>>& lbfgs, double e_star, double lbfgs_best) {
  nlohmann::json out = nlohmann::json::array();
  if (pliant.empty()) return out;  // Pliant from an earlier run (--pliant-given): no trace
  const double worse = std::max(pliant.back()[1], lbfgs_best);
  const std::pair<const char*, double> ms[] = {{"worse_final", worse}, {"2.00 E*", 2.0 * e_star}, {"1.50 E*", 1.5 * e_star},
                                               {"1.25 E*", 1.25 * e_star}, {"1.10 E*", 1.1 * e_star}, {"1.01 E*", 1.01 * e_star}};
  for (const auto& [label, E] : ms) {
    const double tp = time_to(pliant, E), tl = time_to(lbfgs, E);
    auto num = [](double t) { return t >= 0 ? nlohmann::json(t) : nlohmann::json(); };
    out.push_back({{"milestone", label},
                   {"objective", E},
                   {"pliant_s", num(tp)},
                   {"lbfgs_s", num(tl)},
                   {"speedup", tp > 0 && tl >= 0 ? nlohmann::json(tl / tp) : nlohmann::json()}});
    std::fprintf(stderr, "  milestone %-11s E %-10.6g Pliant %7.1f s  L-BFGS %7.1f s  speedup %s\n", label, E, tp, tl,
                 tp > 0 && tl >= 0 ? std::to_string(tl / tp).c_str() : "-");
  }
  return out;
}

}  // namespace

void converged_comparison(const std::string& name, const ControlModel& m, const ConvergedOptions& o,
                          const std::function<void(const nlohmann::json&)>& emit) {
  // 1. Pliant as users run it: control_solve_admm with the scene's settings (coarse-to-fine
  //    when the scene asks for it, polish included), to its own end.
  Progress progress;
  ControlState s = control_init(m);
  nlohmann::json admm_history = nlohmann::json::array();
  const double c0 = process_cpu_s();
  const auto w0 = std::chrono::steady_clock::now();
  // Where Pliant's CPU time goes: per coarse-to-fine level (2 = quarter, 1 = half, 0 = the
  // scene's grid) and phase (ADMM outer iterations, L-BFGS polish); the time between two
  // checkpoints is charged to the later one's level and phase (prolongation and previews
  // to the next level's first iteration).
  struct Bucket {
    double cpu_s = 0;
    int iterations = 0;
    double objective = 0;
    int last_iteration = 0;
    bool seen = false;
    std::vector<double> admm_objectives;  // ADMM phase: E per outer iteration (the level's grid)
  };
  std::map<std::pair<int, int>, Bucket> buckets;
  double last_cpu = c0;
  ControlCallbacks cb;
  cb.clock = process_cpu_s;  // the objective trace in CPU seconds, as the baselines' histories
  cb.on_iteration = [&](const ControlState& st) {
    const double now = process_cpu_s();
    if (st.level == 0 && !st.objective_history.empty()) admm_history.push_back({now - c0, st.objective_history.back()});
    Bucket& b = buckets[{st.level, st.phase}];
    b.cpu_s += now - last_cpu;
    // The polish numbers its iterations after the ADMM's cap (its first checkpoint is the
    // switch): count from there.
    if (!b.seen && st.phase == 1) b.last_iteration = st.iteration;
    b.seen = true;
    b.iterations += st.iteration - b.last_iteration;
    b.last_iteration = st.iteration;
    if (!st.objective_history.empty()) b.objective = st.objective_history.back();
    if (st.phase == 0 && !st.objective_history.empty()) b.admm_objectives.push_back(st.objective_history.back());
    last_cpu = now;
  };
  const bool given = o.given_objective > 0;
  if (!given) {
    std::fprintf(stderr, "%s: Pliant (ADMM, scene settings) ...\n", name.c_str());
    control_solve_admm(m, s, progress, cb);
  }
  const double pliant_cpu = given ? o.given_pliant_s : process_cpu_s() - c0;
  nlohmann::json breakdown = nlohmann::json::array();
  for (const auto& [key, b] : buckets) {
    breakdown.push_back({{"level", key.first},
                         {"phase", key.second == 0 ? "admm" : "polish"},
                         {"cpu_s", b.cpu_s},
                         {"iterations", b.iterations},
                         {"objective", b.objective},
                         {"admm_objectives", b.admm_objectives}});
    std::fprintf(stderr, "  level %d %-6s %6.1f s cpu, %3d iterations, E %.6g\n", key.first,
                 key.second == 0 ? "admm" : "polish", b.cpu_s, b.iterations, b.objective);
  }
  if (!given) {
    breakdown.push_back({{"level", -1}, {"phase", "other"}, {"cpu_s", pliant_cpu - (last_cpu - c0)}});
    std::fprintf(stderr, "  after the last checkpoint %.1f s cpu\n", pliant_cpu - (last_cpu - c0));
  }
  const double pliant_wall =
      given ? -1.0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const double e_star = given ? o.given_objective : control_objective(m, s.force, nullptr);  // re-simulated
  ControlMetrics pm = given ? ControlMetrics{} : control_evaluate(m, s.force);
  if (given) pm.objective = e_star, pm.iou_min = o.given_iou_min;
  std::fprintf(stderr, "%s: Pliant E* %.6g IoU min %.3f in %.1f s cpu (%.1f s wall, load %.1f)\n", name.c_str(),
               e_star, pm.iou_min, pliant_cpu, pliant_wall, load_average());
  const double budget = o.budget_factor * pliant_cpu;
  const std::vector<std::array<double, 2>> pliant_trace = given ? std::vector<std::array<double, 2>>{} : s.objective_trace;

  auto row = [&](const char* label, const LbfgsResult& r, double coarse_s) {
    const ControlMetrics lm = control_evaluate(m, r.force);
    const nlohmann::json milestones = milestones_json(pliant_trace, r.trace, e_star, r.best);
    nlohmann::json j = {{"case", name + " converged " + label},
                        {"comparison", "converged"},
                        {"baseline", label},
                        {"time_basis", "cpu"},
                        {"grid", m.sim.n},
                        {"frames", m.sim.frames},
                        {"r", m.r},
                        {"pliant_s", pliant_cpu},
                        {"pliant_wall_s", pliant_wall},
                        {"pliant_objective", e_star},
                        {"pliant_keyframe_error", given ? nlohmann::json() : nlohmann::json(pm.objective - m.r * pm.control_energy)},
                        {"pliant_from_earlier_run", given},
                        {"iou_min", pm.iou_min},
                        {"keyframes", keyframes_json(pm)},
                        {"pliant_history", admm_history},
                        {"pliant_breakdown", breakdown},
                        {"lbfgs_chunk", m.lbfgs_chunk},
                        {"lbfgs_s", r.time_s},
                        {"lbfgs_coarse_s", coarse_s},
                        {"lbfgs_budget_s", budget},
                        {"budget_factor", o.budget_factor},
                        {"lbfgs_reached", r.reached},
                        {"lbfgs_stop_reason", r.stop_reason},
                        {"lbfgs_best_objective", r.best},
                        {"lbfgs_resimulated_objective", r.reached ? r.check : lm.objective},
                        {"lbfgs_iou_min", lm.iou_min},
                        {"lbfgs_evaluations", r.evaluations},
                        {"lbfgs_restarts", r.restarts},
                        {"lbfgs_history", r.history},
                        {"speedup", pliant_cpu > 0 ? r.time_s / pliant_cpu : 0.0},
                        {"speedup_is_lower_bound", !r.reached},
                        // Pliant's best-so-far trace on the scene's grid ([CPU s, E], <= 60
                        // points) and the time to shared intermediate objectives.
                        {"pliant_trace", control_detail::decimate_trace(pliant_trace, 60)},
                        {"milestones", milestones},
                        {"load_average_1min", load_average()},
                        {"peak_mb", [] {
                           rusage ru{};
                           getrusage(RUSAGE_SELF, &ru);
                           return ru.ru_maxrss / 1024.0;
                         }()}};
    emit(j);
  };

  if (!o.plain && !o.c2f) {  // Pliant only (schedule experiments): one row without a baseline
    LbfgsResult none;
    none.stop_reason = "not run";
    none.force = s.force;
    row("none", none, 0.0);
    return;
  }
  // 2. L-BFGS coarse-to-fine: the production L-BFGS on the quarter and half levels (as
  //    many iterations per level as Pliant's ADMM + polish there), then the budgeted
  //    continuous L-BFGS on the fine level; the coarse levels' time is charged.
  if (o.c2f && m.progressive_preview) {
    std::fprintf(stderr, "%s: L-BFGS coarse-to-fine, budget %.0f s cpu ...\n", name.c_str(), budget);
    const double l0 = process_cpu_s();
    ControlModel lm = m;
    lm.coarse_iterations = (m.coarse_iterations >= 0 ? m.coarse_iterations : m.max_iterations) +
                           (m.coarse_polish_iterations >= 0 ? m.coarse_polish_iterations : m.polish_iterations);
    lm.coarse_admm_levels = -1;  // every coarse level gets its L-BFGS iterations
    ControlState ls = control_init(lm);
    control_coarse_to_fine(lm, ls, kCoarseToFineLevels, {},
                           [&](const ControlModel& cm, ControlState& cs, const ControlCallbacks& lcb) {
                             control_solve_lbfgs(cm, cs, progress, lcb);
                           });
    const double coarse_s = process_cpu_s() - l0;
    const LbfgsResult r = run_lbfgs(m, ls.force, l0, budget, e_star, o.deadline_unix);
    row("lbfgs coarse-to-fine", r, coarse_s);
  }
  // 3. Plain L-BFGS from rest on the fine level: after coarse-to-fine, which ends far
  //    sooner, so a run stopped only by --deadline-unix still measures both.
  if (o.plain) {
    std::fprintf(stderr, "%s: plain L-BFGS, budget %.0f s cpu ...\n", name.c_str(), budget);
    const double l0 = process_cpu_s();
    const LbfgsResult r = run_lbfgs(m, control_init(m).force, l0, budget, e_star, o.deadline_unix);
    row("lbfgs", r, 0.0);
  }
}

}  // namespace pliant::smoke::bench
