// ADMM vs L-BFGS on keyframe-control scenes (issue 3's benchmark). For each scene both
// solvers run in the same process: ADMM (the scene's max_iterations outer iterations, then
// its polish_iterations of L-BFGS from the best ADMM forces) and plain L-BFGS from rest.
// The target is ADMM's best re-simulated objective; pliant_s and lbfgs_s are the wall
// times at which each first reached it ("time to the same keyframe error"). When L-BFGS
// never reaches it (it stalls, or runs out of iterations), lbfgs_s is its whole run
// and speedup is a lower bound ("speedup_is_lower_bound": true; "lbfgs_stalled": true
// when L-BFGS stopped before its iteration budget, so it would never reach the target). Writes a JSON array with
// case, pliant_s, lbfgs_s, speedup, iou_min, peak_mb plus per-keyframe IoU, L-BFGS's own
// IoU, the ADMM profile (seconds per iteration by phase) and the FAS V-cycle factor.
//   bench_smoke_control [--quick] [--iterations N] [--lbfgs-iterations N] [--polish N]
//                       [--grid N] [--frames T] [--r R] [--coarse-to-fine] [--out FILE] [--merge]
//                       [--nso-vcycles N] [--ao-iterations N] [--balance-mu MU] [--relaxation ALPHA]
//                       [--switch-progress P] [--coarse-polish N] [scene.json ...]
//   bench_smoke_control --converged [--budget X] [--baseline plain|c2f|both] [--deadline-unix S]
//                       [--pliant-given E CPU_S IOU] [--grid N] [--merge] [--out FILE] scene.json ...
//   bench_smoke_control --evaluations N [--lbfgs-iterations K] [--grid N] [--frames T] scene.json ...
//     per-evaluation profile (objective + gradient of the polish; with K: also K L-BFGS
//     iterations from rest at that grid); prints JSON only.
// --converged: issue 3's converged comparison (converged_comparison.h): Pliant as users
// run it to its end, then L-BFGS with X (20) times Pliant's CPU time to reach its error.
// --merge keeps the output file's other rows (a row replaces the row of the same case).
// --nso-vcycles / --ao-iterations override the scenes' ADMM settings (A/B experiments), as do
// --balance-mu (residual balancing), --relaxation (over-relaxation alpha) and
// --switch-progress (adaptive switch to the polish), all ControlModel::admm_* fields.
// --grid / --frames rescale a scene (N cells per axis, same domain; T frames with the
// keyframes moved proportionally) for the time-per-iteration vs cells x frames rows.
// --coarse-to-fine runs BOTH solvers through their progressive preview (quarter and half
// resolution first, control_coarse_to_fine.h), as `pliant run` does; times then include
// the coarse levels and only fine-level objectives count towards the target; L-BFGS
// gets ADMM's iterations + polish on every coarse level. Scenes with max_iterations 0
// (fine level polish only, the shipped FLUID) always run this way.
// Times: with OMP_NUM_THREADS=1 pliant_s / lbfgs_s / speedup are process CPU seconds
// ("time_basis": "cpu": what a quiet machine's wall time would be, whatever else runs on
// the machine), otherwise wall seconds ("wall"); both are also printed as *_cpu_s and
// *_wall_s / speedup_cpu and speedup_wall.
#include <sys/resource.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "admm_solver.h"
#include "control_forward_model.h"
#include "converged_comparison.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/control.h"
#include "../bench_machine.h"

using namespace pliant;
using namespace pliant::smoke;

namespace {

struct Run {
  std::vector<double> objective, wall, cpu;  // per outer iteration (cumulative seconds)
  FaceSeries force;
  double total_s = 0, total_cpu_s = 0;
  int iterations = 0;  // the state's iteration count at the end
};

// Process CPU time (user + system): on a loaded shared machine the wall time of a
// single-threaded run is mostly waiting; its CPU time is what a quiet machine's wall
// time would be (OMP_NUM_THREADS=1).
double cpu_s() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

double load_average() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

double peak_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;
}

Run run(const ControlModel& m, bool admm, std::vector<AdmmIterationStats>* stats) {
  Run r;
  ControlState s = control_init(m);
  Progress progress;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_s();
  ControlCallbacks cb;
  cb.on_iteration = [&](const ControlState& st) {
    if (st.objective_history.empty() || st.level > 0) return;  // coarse levels: other objectives
    r.objective.push_back(st.objective_history.back());
    r.wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    r.cpu.push_back(cpu_s() - c0);
  };
  if (m.progressive_preview) {  // --coarse-to-fine: the solvers' own full path
    if (admm) control_solve_admm(m, s, progress, cb);
    else control_solve_lbfgs(m, s, progress, cb);
  } else if (admm) {
    // control_solve_admm without the progressive preview, with the per-iteration stats.
    admm_run(m, s, progress, cb, stats);
    if (m.polish_iterations > 0) {
      s.phase = 1;
      s.iteration = m.max_iterations;
      ControlModel pm = m;
      pm.max_iterations = m.max_iterations + m.polish_iterations;
      control_solve_lbfgs(pm, s, progress, cb);
    }
  } else {
    control_solve_lbfgs(m, s, progress, cb);
  }
  r.force = s.force;
  r.iterations = s.iteration;
  if (r.objective.empty()) {  // a solver that stopped before its first iteration
    r.objective.push_back(control_objective(m, s.force, nullptr));
    r.wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    r.cpu.push_back(cpu_s() - c0);
  }
  r.total_cpu_s = cpu_s() - c0;
  r.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

double time_to(const Run& r, double target, bool cpu = false) {
  for (size_t i = 0; i < r.objective.size(); ++i)
    if (r.objective[i] <= target) return cpu ? r.cpu[i] : r.wall[i];
  return -1;
}

// The scene rescaled to n cells per axis (same domain) and T frames (keyframes moved
// proportionally, at least frame 1).
void rescale_scene(Scene& scene, int n, int frames) {
  auto& doc = scene.doc;
  if (n > 0) {
    auto& res = doc["grid"]["resolution"];
    const double h = doc["grid"]["cell_size_m"].get<double>() * res[0].get<double>() / n;
    for (auto& x : res) x = n;
    doc["grid"]["cell_size_m"] = h;
  }
  if (frames > 0) {
    const int T0 = doc["time"]["frames"].get<int>();
    doc["time"]["frames"] = frames;
    for (auto& k : doc["control"]["keyframes"])
      k["frame"] = std::max(1, int(std::lround(k["frame"].get<double>() * frames / T0)));
  }
}


// --evaluations N: issue 3's per-evaluation profile. Wall and process CPU seconds of N
// objective + gradient evaluations (forward sweep + discrete adjoint: what one polish
// L-BFGS iteration costs) on one ForwardOps, as the polish does. Forces: a smooth
// descent direction f = -c dE/df(0) with max |dt f| = half a cell per frame (that
// gradient evaluation sizes the buffers; it is not timed). The first timed evaluation
// is reported apart; "bits" hashes E and the last gradient, to check that thread counts
// give the same bits.
nlohmann::json time_evaluations(const ControlModel& m, int n, int lbfgs_iterations) {
  using control_detail::Vec;
  control_detail::ForwardOps ops(m, control_detail::kControlPressureTolerance);
  const size_t nf = ops.faces();
  std::vector<Vec> f(m.sim.frames, Vec(nf, 0.0)), g;
  control_detail::objective_d(m, ops, f, &g);
  double gmax = 0;
  for (const Vec& gi : g)
    for (double x : gi) gmax = std::max(gmax, std::abs(x));
  const double c = gmax > 0 ? 0.5 * m.sim.cell_size_m / (m.sim.dt_s * m.sim.dt_s * gmax) : 0.0;
  for (int i = 0; i < m.sim.frames; ++i)
    for (size_t e = 0; e < nf; ++e) f[i][e] = -c * g[i][e];
  double first_s = 0, first_cpu = 0, rest_s = 0, rest_cpu = 0, E = 0;
  for (int k = 0; k < n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_s();
    E = control_detail::objective_d(m, ops, f, &g);
    const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_s() - c0;
    if (k == 0) first_s = w, first_cpu = cpu;
    else rest_s += w, rest_cpu += cpu;
  }
  uint64_t h = 1469598103934665603ull;  // FNV-1a over the bytes of E and the gradient
  auto mix = [&h](double x) {
    unsigned char b[sizeof x];
    std::memcpy(b, &x, sizeof x);
    for (unsigned char v : b) h = (h ^ v) * 1099511628211ull;
  };
  mix(E);
  for (const Vec& gi : g)
    for (double x : gi) mix(x);
  char bits[17];
  std::snprintf(bits, sizeof bits, "%016llx", static_cast<unsigned long long>(h));
  const int rest = std::max(1, n - 1);
  // --lbfgs-iterations K: K iterations of the L-BFGS polish itself at this level (no
  // coarse levels), from rest: evaluations plus LBFGS++'s serial vector work.
  double lbfgs_wall = 0, lbfgs_cpu = 0;
  int lbfgs_done = 0;
  if (lbfgs_iterations > 0) {
    ControlModel lm = m;
    lm.max_iterations = lbfgs_iterations;
    lm.lbfgs_chunk = lbfgs_iterations;
    lm.progressive_preview = false;
    ControlState st = control_init(lm);
    Progress progress;
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_s();
    control_solve_lbfgs(lm, st, progress, {});
    lbfgs_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    lbfgs_cpu = cpu_s() - c0;
    lbfgs_done = st.iteration;
  }
  return {{"mode", "evaluations"},
          {"lbfgs_iterations", lbfgs_done},
          {"lbfgs_wall_s", lbfgs_wall},
          {"lbfgs_cpu_s", lbfgs_cpu},
          {"omp_threads", omp_get_max_threads()},
          {"load_average_1min", load_average()},
          {"grid", m.sim.n},
          {"frames", m.sim.frames},
          {"evaluations", n},
          {"objective", E},
          {"bits", bits},
          {"first_evaluation_wall_s", first_s},
          {"first_evaluation_cpu_s", first_cpu},
          {"evaluation_wall_s", n > 1 ? rest_s / rest : first_s},
          {"evaluation_cpu_s", n > 1 ? rest_cpu / rest : first_cpu},
          {"pressure_iterations_per_projection", ops.projections ? double(ops.pressure_iterations) / ops.projections : 0.0},
          {"peak_mb", peak_mb()}};
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int iterations = 0, lbfgs_iterations = 0, polish = -1, grid = 0, frames = 0, evaluations = 0;
  bool coarse_to_fine = false, converged = false, merge = false;
  int nso_vcycles = -1, ao_iterations = 0;  // ADMM setting overrides (A/B experiments)
  double nso_skip_gap = -1;
  int coarse_polish = -2;  // -2: the scene's
  double balance_mu = -1, relaxation = -1, switch_progress = -1;  // -1: the scene's
  int lbfgs_chunk = 0, coarse_iterations = -2, coarse_admm_levels = -2;  // -2: the scene's
  pliant::smoke::bench::ConvergedOptions conv;
  double r_override = 0;
  std::string out = "bench/results/smoke.json";
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--iterations" && i + 1 < argc) iterations = std::stoi(argv[++i]);
    else if (a == "--lbfgs-iterations" && i + 1 < argc) lbfgs_iterations = std::stoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--polish" && i + 1 < argc) polish = std::stoi(argv[++i]);
    else if (a == "--grid" && i + 1 < argc) grid = std::stoi(argv[++i]);
    else if (a == "--frames" && i + 1 < argc) frames = std::stoi(argv[++i]);
    else if (a == "--coarse-to-fine") coarse_to_fine = true;
    else if (a == "--r" && i + 1 < argc) r_override = std::stod(argv[++i]);
    else if (a == "--converged") converged = true;
    else if (a == "--evaluations" && i + 1 < argc) evaluations = std::stoi(argv[++i]);
    else if (a == "--nso-vcycles" && i + 1 < argc) nso_vcycles = std::stoi(argv[++i]);
    else if (a == "--ao-iterations" && i + 1 < argc) ao_iterations = std::stoi(argv[++i]);
    else if (a == "--nso-skip-gap" && i + 1 < argc) nso_skip_gap = std::stod(argv[++i]);
    else if (a == "--lbfgs-chunk" && i + 1 < argc) lbfgs_chunk = std::stoi(argv[++i]);
    else if (a == "--coarse-polish" && i + 1 < argc) coarse_polish = std::stoi(argv[++i]);
    else if (a == "--balance-mu" && i + 1 < argc) balance_mu = std::stod(argv[++i]);
    else if (a == "--relaxation" && i + 1 < argc) relaxation = std::stod(argv[++i]);
    else if (a == "--switch-progress" && i + 1 < argc) switch_progress = std::stod(argv[++i]);
    else if (a == "--coarse-admm-levels" && i + 1 < argc) coarse_admm_levels = std::stoi(argv[++i]);
    else if (a == "--coarse-iterations" && i + 1 < argc) coarse_iterations = std::stoi(argv[++i]);
    else if (a == "--budget" && i + 1 < argc) conv.budget_factor = std::stod(argv[++i]);
    else if (a == "--deadline-unix" && i + 1 < argc) conv.deadline_unix = std::stod(argv[++i]);
    else if (a == "--baseline" && i + 1 < argc) {
      const std::string b = argv[++i];
      conv.plain = b == "plain" || b == "both";  // "none": Pliant only
      conv.c2f = b == "c2f" || b == "both";
    } else if (a == "--pliant-given" && i + 3 < argc) {  // E* CPU_S IOU_MIN of an earlier run
      conv.given_objective = std::stod(argv[++i]);
      conv.given_pliant_s = std::stod(argv[++i]);
      conv.given_iou_min = std::stod(argv[++i]);
    } else if (a == "--merge") merge = true;
    else scenes.push_back(a);
  }
  const std::string dir = std::string(PLIANT_ASSETS_DIR) + "/scenes/";
  if (scenes.empty()) {
    scenes.push_back(dir + "smoke_circle_to_square.json");
    if (!quick)
      for (const char* s : {"smoke_circle_to_letter.json", "smoke_fluid_letters.json"}) scenes.push_back(dir + s);
  }
  if (quick && iterations == 0) iterations = 10;
  nlohmann::json results = nlohmann::json::array();
  // --merge: keep the file's other rows; a row replaces the file's row of the same case.
  if (merge) {
    std::ifstream in(out);
    if (in) results = nlohmann::json::parse(in, nullptr, false);
    if (!results.is_array()) results = nlohmann::json::array();
  }
  auto emit = [&](const nlohmann::json& j) {
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
    bool replaced = false;
    for (auto& r : results)
      if (r.value("case", "") == j["case"]) r = j, replaced = true;
    if (!replaced) results.push_back(j);
    std::ofstream(out) << results.dump(2) << "\n";  // after every case: a long run keeps what it measured
  };
  for (const auto& path : scenes) {
    Scene scene = load_scene(path);
    rescale_scene(scene, grid, frames);
    ControlModel m = control_compile(scene);
    if (iterations > 0) m.max_iterations = iterations;
    if (quick) m.polish_iterations = std::min(m.polish_iterations, 20);
    if (polish >= 0) m.polish_iterations = polish;
    if (r_override > 0) m.r = r_override;
    if (nso_vcycles >= 0) m.nso_vcycles = nso_vcycles;
    if (ao_iterations > 0) m.ao_iterations = ao_iterations;
    if (nso_skip_gap >= 0) m.nso_skip_gap = nso_skip_gap;
    if (lbfgs_chunk > 0) m.lbfgs_chunk = lbfgs_chunk;
    if (balance_mu >= 0) m.admm_balance_mu = balance_mu;
    if (coarse_polish >= -1) m.coarse_polish_iterations = coarse_polish;
    if (relaxation > 0) m.admm_relaxation = relaxation;
    if (switch_progress >= 0) m.admm_switch_progress = switch_progress;
    if (coarse_admm_levels >= -1) m.coarse_admm_levels = coarse_admm_levels;
    if (coarse_iterations >= -1) m.coarse_iterations = coarse_iterations;
    if (evaluations > 0) {  // per-evaluation profile (no results file row unless --out)
      nlohmann::json j = time_evaluations(m, evaluations, lbfgs_iterations);
      std::string name = path.substr(path.find_last_of('/') + 1);
      name += " " + std::to_string(m.sim.n[0]) + "^" + std::to_string(m.sim.dim) + "x" + std::to_string(m.sim.frames);
      j["case"] = name + " evaluation omp" + std::to_string(omp_get_max_threads());
      j["machine"] = pliant::bench::machine_description();
      std::printf("%s\n", j.dump().c_str());
      std::fflush(stdout);
      continue;
    }
    if (converged) {  // issue 3's converged comparison (converged_comparison.h)
      std::string name = path.substr(path.find_last_of('/') + 1);
      if (grid > 0 || frames > 0)
        name += " " + std::to_string(m.sim.n[0]) + "^" + std::to_string(m.sim.dim) + "x" + std::to_string(m.sim.frames);
      // Overridden settings are part of the case name (so --merge keeps the shipped rows).
      if (iterations > 0) name += " iterations=" + std::to_string(iterations);
      if (coarse_iterations >= -1) name += " coarse_iterations=" + std::to_string(coarse_iterations);
      if (polish >= 0) name += " polish=" + std::to_string(polish);
      if (nso_skip_gap >= 0) name += " nso_skip_gap=" + nlohmann::json(nso_skip_gap).dump();
      if (ao_iterations > 0) name += " ao_iterations=" + std::to_string(ao_iterations);
      if (lbfgs_chunk > 0) name += " lbfgs_chunk=" + std::to_string(lbfgs_chunk);
      if (coarse_admm_levels >= -1) name += " coarse_admm_levels=" + std::to_string(coarse_admm_levels);
      if (balance_mu >= 0) name += " balance_mu=" + nlohmann::json(balance_mu).dump();
      if (relaxation > 0) name += " relaxation=" + nlohmann::json(relaxation).dump();
      if (switch_progress >= 0) name += " switch_progress=" + nlohmann::json(switch_progress).dump();
      if (coarse_polish >= -1) name += " coarse_polish=" + std::to_string(coarse_polish);
      pliant::smoke::bench::converged_comparison(name, m, conv, [&](nlohmann::json j) {
        j["machine"] = pliant::bench::machine_description();
        j["omp_threads"] = omp_get_max_threads();
        j["mode"] = "converged";
        emit(j);
      });
      continue;
    }
    // A scene whose fine level only polishes (max_iterations 0: the shipped FLUID) is
    // solved coarse-to-fine, as `pliant run` does it: both solvers then.
    const bool c2f = coarse_to_fine || m.max_iterations == 0;
    m.progressive_preview = c2f;
    ControlModel lm = m;  // the baseline gets as many iterations as ADMM and its polish together
    lm.max_iterations = lbfgs_iterations > 0 ? lbfgs_iterations : m.max_iterations + m.polish_iterations;
    // Coarse levels: L-BFGS gets ADMM's iterations plus its polish there too.
    lm.coarse_iterations = (m.coarse_iterations >= 0 ? m.coarse_iterations : m.max_iterations) +
                           (m.coarse_polish_iterations >= 0 ? m.coarse_polish_iterations : m.polish_iterations);
    lm.coarse_admm_levels = -1;
    std::vector<AdmmIterationStats> st;
    const Run a = run(m, true, &st);
    const Run l = run(lm, false, nullptr);
    const double best_a = *std::min_element(a.objective.begin(), a.objective.end());
    const double best_l = *std::min_element(l.objective.begin(), l.objective.end());
    const double target = best_a;
    const double ta = time_to(a, target), tl_reached = time_to(l, target);
    const bool lower_bound = tl_reached < 0;
    const double tl = lower_bound ? l.total_s : tl_reached;
    // Single-threaded runs report CPU seconds as pliant_s / lbfgs_s (a quiet machine's wall
    // time; immune to other jobs on a shared machine); threaded runs report wall time.
    const bool cpu_basis = omp_get_max_threads() == 1;
    const double ca = time_to(a, target, true), cl = lower_bound ? l.total_cpu_s : time_to(l, target, true);
    const ControlMetrics cm = control_evaluate(m, a.force);
    const ControlMetrics lmx = control_evaluate(m, l.force);
    double ao = 0, nso = 0, forces = 0, vc = 0;
    int nvc = 0, nso_skipped = 0;
    nlohmann::json gaps = nlohmann::json::array();
    for (const auto& s : st) {
      nso_skipped += s.nso_skipped;
      gaps.push_back(s.nso_start_gap);
      ao += s.ao_s, nso += s.nso_s, forces += s.forces_s;
      for (double f : s.vcycle_factors) vc += f, ++nvc;
    }
    const double n = std::max<size_t>(1, st.size());
    // CPU seconds per ADMM iteration from the callbacks' CPU clock (the first ADMM
    // iterations' entries; the first includes the start-up re-simulation).
    double admm_cpu_per_iteration = 0;
    if (st.size() >= 2 && a.cpu.size() >= st.size())
      admm_cpu_per_iteration = (a.cpu[st.size() - 1] - a.cpu[0]) / double(st.size() - 1);
    else if (st.size() == 1 && !a.cpu.empty())
      admm_cpu_per_iteration = a.cpu[0];
    // Per outer iteration: [CPU s, E, beta] (ADMM, then the polish's chunks without beta).
    nlohmann::json hist = nlohmann::json::array();
    for (size_t k = 0; k < a.objective.size() && k < a.cpu.size(); ++k)
      hist.push_back(k < st.size() ? nlohmann::json{a.cpu[k], a.objective[k], st[k].beta} : nlohmann::json{a.cpu[k], a.objective[k]});
    nlohmann::json ious = nlohmann::json::array();
    for (const auto& k : cm.keyframes) ious.push_back({{"frame", k.frame}, {"iou", k.iou}, {"relative_l2", k.relative_l2}});
    std::string name = path.substr(path.find_last_of('/') + 1);
    if (grid > 0 || frames > 0)
      name += " " + std::to_string(m.sim.n[0]) + "^" + std::to_string(m.sim.dim) + "x" + std::to_string(m.sim.frames);
    if (r_override > 0) name += " r=" + nlohmann::json(r_override).dump();
    if (nso_vcycles >= 0) name += " nso_vcycles=" + std::to_string(nso_vcycles);
    if (ao_iterations > 0) name += " ao_iterations=" + std::to_string(ao_iterations);
    if (nso_skip_gap >= 0) name += " nso_skip_gap=" + nlohmann::json(nso_skip_gap).dump();
    if (balance_mu >= 0) name += " balance_mu=" + nlohmann::json(balance_mu).dump();
    if (relaxation > 0) name += " relaxation=" + nlohmann::json(relaxation).dump();
    if (switch_progress >= 0) name += " switch_progress=" + nlohmann::json(switch_progress).dump();
    if (c2f) name += " coarse-to-fine";
    nlohmann::json j = {{"case", name},
                        {"coarse_to_fine", c2f},
                        {"omp_threads", omp_get_max_threads()},
                        {"load_average_1min", load_average()},
                        {"grid", m.sim.n},
                        {"frames", m.sim.frames},
                        {"r", m.r},
                        {"admm_iterations", st.size()},
                        {"polish_iterations", m.polish_iterations},
                        {"lbfgs_iterations", lm.max_iterations},
                        {"target_objective", target},
                        {"admm_best_objective", best_a},
                        {"lbfgs_best_objective", best_l},
                        {"time_basis", cpu_basis ? "cpu" : "wall"},
                        {"pliant_s", cpu_basis ? ca : ta},
                        {"lbfgs_s", cpu_basis ? cl : tl},
                        {"speedup", cpu_basis ? ((ca > 0 && cl > 0) ? cl / ca : 0.0) : ((ta > 0 && tl > 0) ? tl / ta : 0.0)},
                        {"pliant_wall_s", ta},
                        {"lbfgs_wall_s", tl},
                        {"speedup_wall", (ta > 0 && tl > 0) ? tl / ta : 0.0},
                        {"speedup_is_lower_bound", lower_bound},
                        {"pliant_cpu_s", ca},
                        {"lbfgs_cpu_s", cl},
                        {"speedup_cpu", (ca > 0 && cl > 0) ? cl / ca : 0.0},
                        // L-BFGS stopped early (converged or line search failed) above the
                        // target: it never gets there, whatever the time.
                        {"lbfgs_stalled", lower_bound && l.iterations < lm.max_iterations},
                        {"admm_total_s", a.total_s},
                        {"admm_total_cpu_s", a.total_cpu_s},
                        {"lbfgs_total_cpu_s", l.total_cpu_s},
                        {"lbfgs_total_s", l.total_s},
                        {"iou_min", cm.iou_min},
                        {"keyframes", ious},
                        {"lbfgs_iou_min", lmx.iou_min},
                        {"control_energy", cm.control_energy},
                        {"max_divergence", cm.max_divergence},
                        {"admm_s_per_iteration", (ao + nso + forces) / n},
                        {"admm_cpu_s_per_iteration", admm_cpu_per_iteration},
                        {"admm_ao_s", ao / n},
                        {"admm_nso_s", nso / n},
                        {"admm_forces_s", forces / n},
                        {"fas_vcycle_factor", nvc ? vc / nvc : 0.0},
                        {"nso_skip_gap", m.nso_skip_gap},
                        {"nso_skipped", nso_skipped},
                        {"nso_start_gaps", gaps},
                        {"admm_history", hist},
                        {"peak_mb", peak_mb()},
                        {"machine", pliant::bench::machine_description()},
                        {"mode", quick ? "quick" : "full"}};
    emit(j);
  }
  return 0;
}
