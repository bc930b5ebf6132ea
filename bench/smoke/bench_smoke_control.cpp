// ADMM vs L-BFGS on keyframe-control scenes (issue 3's benchmark). For each scene both
// solvers run max_iterations outer iterations; the target is the worse of the two best
// re-simulated objectives, and each solver's time is the wall time at which it first
// reached that target ("time to the same keyframe error"). Writes a JSON array with
// case, pliant_s, lbfgs_s, speedup, iou_min, peak_mb plus the ADMM profile (seconds
// per iteration by phase, FAS V-cycle factor).
//   bench_smoke_control [--quick] [--iterations N] [--out FILE] [scene.json ...]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "admm_solver.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/control.h"

using namespace pliant;
using namespace pliant::smoke;

namespace {

struct Run {
  std::vector<double> objective, wall;  // per outer iteration (cumulative seconds)
  FaceSeries force;
};

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
  ControlCallbacks cb;
  cb.on_iteration = [&](const ControlState& st) {
    r.objective.push_back(st.objective_history.empty() ? 0.0 : st.objective_history.back());
    r.wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  if (admm) admm_run(m, s, progress, cb, stats);
  else control_solve_lbfgs(m, s, progress, cb);
  r.force = s.force;
  if (r.objective.empty()) {  // a solver that stopped before its first iteration
    r.objective.push_back(control_objective(m, s.force, nullptr));
    r.wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return r;
}

double time_to(const Run& r, double target) {
  for (size_t i = 0; i < r.objective.size(); ++i)
    if (r.objective[i] <= target) return r.wall[i];
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int iterations = 0;
  std::string out = "bench/results/smoke.json";
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--iterations" && i + 1 < argc) iterations = std::stoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else scenes.push_back(a);
  }
  if (scenes.empty()) {
    scenes.push_back(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json");
    if (!quick) scenes.push_back(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_letter.json");
  }
  if (quick && iterations == 0) iterations = 10;
  nlohmann::json results = nlohmann::json::array();
  for (const auto& path : scenes) {
    ControlModel m = control_compile(load_scene(path));
    if (iterations > 0) m.max_iterations = iterations;
    m.progressive_preview = false;
    std::vector<AdmmIterationStats> st;
    const Run a = run(m, true, &st);
    const Run l = run(m, false, nullptr);
    const double best_a = *std::min_element(a.objective.begin(), a.objective.end());
    const double best_l = *std::min_element(l.objective.begin(), l.objective.end());
    const double target = std::max(best_a, best_l);
    const double ta = time_to(a, target), tl = time_to(l, target);
    const ControlMetrics cm = control_evaluate(m, a.force);
    double ao = 0, nso = 0, forces = 0, vc = 0;
    int nvc = 0;
    for (const auto& s : st) {
      ao += s.ao_s, nso += s.nso_s, forces += s.forces_s;
      for (double f : s.vcycle_factors) vc += f, ++nvc;
    }
    const double n = std::max<size_t>(1, st.size());
    nlohmann::json j = {{"case", path.substr(path.find_last_of('/') + 1)},
                        {"grid", m.sim.n},
                        {"frames", m.sim.frames},
                        {"iterations", m.max_iterations},
                        {"target_objective", target},
                        {"admm_best_objective", best_a},
                        {"lbfgs_best_objective", best_l},
                        {"pliant_s", ta},
                        {"lbfgs_s", tl},
                        {"speedup", (ta > 0 && tl > 0) ? tl / ta : 0.0},
                        // When one solver never reaches the other's best, the speedup above
                        // is at the weaker solver's level only; these say which way it went.
                        {"lbfgs_reaches_admm_best", best_l <= best_a},
                        {"admm_reaches_lbfgs_best", best_a <= best_l},
                        {"iou_min", cm.iou_min},
                        {"admm_s_per_iteration", (ao + nso + forces) / n},
                        {"admm_ao_s", ao / n},
                        {"admm_nso_s", nso / n},
                        {"admm_forces_s", forces / n},
                        {"fas_vcycle_factor", nvc ? vc / nvc : 0.0},
                        {"peak_mb", peak_mb()}};
    std::fprintf(stderr, "%s\n", j.dump().c_str());
    results.push_back(j);
  }
  std::ofstream(out) << results.dump(2) << "\n";
  return 0;
}
