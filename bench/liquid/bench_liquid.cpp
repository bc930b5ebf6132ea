// bench_liquid [--quick] [--out FILE] [--sim-only | --planners-only | --feedback-only]
//   [--no-feedback] [--problems N] [--feedback-problems N] [--family zero|follow|both]
//   [--case NAME] [--sim-s S]: prints one
// JSON object per case and merges them into bench/results/liquid.json (rows of
// other cases are kept).
//   sim_<dim>d_<n>k_t<threads>: dam-break-style collapse, particle_steps_per_s
//   dam_break_3d: 0.5 m cube in a 1 m box (~60k particles), wall_per_sim_s
//   planner cases: see bench_planners.h (success_at_5, mean_transfer, plan_s), static
//   target ("planner_<mode>_2d") and TRANSFER+FOLLOW ("planner_<mode>_follow_2d").
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_planners.h"
#include "pliant/liquid/liquid.h"
#include "../bench_machine.h"

using namespace pliant::liquid;

namespace {


// A cube of liquid of side `side` (m) in the corner of a box of side 2*side,
// cells sized so the cube holds about `particles` particles (8 per cell in 3D,
// 4 in 2D).
LiquidModel collapse_model(int dim, double side, int particles) {
  LiquidModel m;
  m.dim = dim;
  const double per_cell = dim == 3 ? 8 : 4;
  const double cells_per_axis = std::pow(particles / per_cell, 1.0 / dim);
  m.cell_size_m = side / cells_per_axis;
  m.domain_min_m = {0, 0, 0};
  m.domain_max_m = {2 * side, 2 * side, dim == 3 ? 2 * side : 0};
  const int n = int(std::ceil(2 * side / m.cell_size_m - 1e-9));
  m.n = {n, n, dim == 3 ? n : 1};
  m.has_source = m.has_target = false;
  m.cfl = 2.0;
  m.liquid_boxes.push_back({{0, 0, 0}, {side, side, dim == 3 ? side : 0}});
  return m;
}

nlohmann::json run_sim(const std::string& name, const LiquidModel& m, int threads, double sim_s) {
  omp_set_num_threads(threads);
  LiquidState s = liquid_init(m);
  StepStats st;
  liquid_step(m, s);  // warm the workspace
  s = liquid_init(m);
  const int frames = std::max(1, int(sim_s / m.dt_s + 0.5));
  long long particle_steps = 0;
  const double t0 = omp_get_wtime();
  const std::clock_t c0 = std::clock();  // process CPU time, all threads
  for (int f = 0; f < frames; ++f) {
    const int before = st.substeps;
    liquid_step(m, s, &st);
    particle_steps += (long long)(st.substeps - before) * (long long)s.count();
  }
  const double wall = omp_get_wtime() - t0;
  const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  nlohmann::json j = {{"case", name},
                      {"dim", m.dim},
                      {"particles", s.count()},
                      {"cells", m.n[0] * m.n[1] * m.n[2]},
                      {"threads", threads},
                      {"simulated_s", frames * m.dt_s},
                      {"substeps", st.substeps},
                      {"wall_s", wall},
                      {"particle_steps_per_s", particle_steps / wall},
                      // Load-independent-ish: what the run cost in CPU seconds
                      // (on a shared machine wall time includes waiting for a core).
                      {"cpu_s", cpu},
                      {"particle_steps_per_cpu_s", particle_steps / std::max(1e-9, cpu)},
                      {"wall_per_sim_s", wall / (frames * m.dt_s)},
                      // CPU seconds per simulated second: on a quiet machine with
                      // one thread this is the wall time per simulated second.
                      {"cpu_per_sim_s", cpu / (frames * m.dt_s)},
                      {"pressure_iterations_per_substep", double(st.pressure_iterations) / st.substeps},
                      {"phase_s",
                       {{"solids", st.solids_s},
                        {"transfer", st.transfer_s},
                        {"pressure", st.pressure_s},
                        {"viscosity", st.viscosity_s},
                        {"advect", st.advect_s}}}};
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, sims = true, planners = true, feedback = true;
  int problems = 0, feedback_problems = 0;
  std::string out = PLIANT_BENCH_RESULTS, only;  // --case NAME: run just that simulator case
  std::string family = "both";
  double sim_override = 0;                       // --sim-s S: simulated seconds per case
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
    else if (!std::strcmp(argv[i], "--sim-only")) planners = false;
    else if (!std::strcmp(argv[i], "--planners-only")) sims = false;
    else if (!std::strcmp(argv[i], "--feedback-only")) sims = false, planners = false;
    else if (!std::strcmp(argv[i], "--no-feedback")) feedback = false;
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc) only = argv[++i], planners = feedback = false;
    else if (!std::strcmp(argv[i], "--sim-s") && i + 1 < argc) sim_override = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--problems") && i + 1 < argc) problems = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--feedback-problems") && i + 1 < argc) feedback_problems = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--family") && i + 1 < argc) family = argv[++i];  // planner cases
  }
  const bool zero = family != "follow", follow = family != "zero";
  const std::string mach = pliant::bench::machine_description();
  nlohmann::json all = nlohmann::json::array();
  auto emit = [&](nlohmann::json j) {
    j["machine"] = mach;
    // Other processes on a shared machine distort the figures: record the load.
    std::ifstream load("/proc/loadavg");
    double l1 = -1;
    load >> l1;
    j["load_average_1min"] = l1;
    // OMP_WAIT_POLICY=passive keeps idle OpenMP threads from spinning: on a
    // machine shared with other jobs it nearly halves 2-thread wall times.
    const char* wait = std::getenv("OMP_WAIT_POLICY");
    j["omp_wait_policy"] = wait ? wait : "default";
    j["mode"] = quick ? "quick" : "full";
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
    all.push_back(j);
  };
  const int maxt = std::max(1, int(std::thread::hardware_concurrency()));
  if (sims) {
    const double sim_s = sim_override > 0 ? sim_override : quick ? 0.1 : 0.4;
    auto run = [&](const std::string& name, const LiquidModel& m, int t, double seconds) {
      if (only.empty() || only == name) emit(run_sim(name, m, t, seconds));
    };
    const int t2 = std::min(2, maxt);
    for (int dim : {3, 2})
      for (int np : {8000, 60000})
        for (int t : {1, t2}) {
          run("sim_" + std::to_string(dim) + "d_" + std::to_string(np / 1000) + "k_t" + std::to_string(t),
              collapse_model(dim, 0.5, np), t, sim_s);
          if (t2 == 1) break;
        }
    // The dam break of the issue: 0.5 m cube in a 1 m box, ~60k particles, 2 threads
    // ("dam_break_3d") and 1 thread.
    const LiquidModel dam = collapse_model(3, 0.5, 60000);
    const double dam_s = sim_override > 0 ? sim_override : quick ? 0.2 : 1.0;
    run("dam_break_3d", dam, t2, dam_s);
    run("dam_break_3d_t1", dam, 1, dam_s);
  }
  if (planners && zero)
    for (auto& j : bench_planners(quick, problems)) emit(j);
  // TRANSFER+FOLLOW (moving target) held-out problems: *_follow_2d cases.
  if (planners && follow)
    for (auto& j : bench_planners(quick, problems, pliant::liquid::Family::Follow)) emit(j);
  const int fb_count = feedback_problems > 0 ? feedback_problems : quick ? 5 : 100;
  if (feedback && zero) emit(bench_feedback(fb_count));
  if (feedback && follow) emit(bench_feedback(fb_count, pliant::liquid::Family::Follow));
  // Merge into the results file: rows of the cases run now replace theirs, the
  // other rows (e.g. planner cases run separately) are kept, in their order.
  nlohmann::json merged = nlohmann::json::array();
  {
    std::ifstream in(out);
    nlohmann::json old;
    if (in) old = nlohmann::json::parse(in, nullptr, false);
    if (old.is_array()) merged = old;
  }
  for (const auto& row : all) {
    bool replaced = false;
    for (auto& o : merged)
      if (o.is_object() && o.value("case", "") == row["case"]) o = row, replaced = true;
    if (!replaced) merged.push_back(row);
  }
  std::ofstream f(out);
  f << merged.dump(2) << "\n";
  std::fprintf(stderr, "wrote %s\n", out.c_str());
  return 0;
}
