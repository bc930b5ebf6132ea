// bench_smoke_sim: cell-steps per second of the forward smoke simulation (128^2 and
// 64^3, 1 and 2 threads, with a per-phase profile) and the pressure solve, MGPCG
// against Jacobi-PCG on the same right-hand side in the same run.
//   bench_smoke_sim [--quick] [--max-threads N] [--out bench/results/smoke_sim.json]
// Prints one JSON object per case and writes all of them (with machine info) to --out.
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "advection.h"
#include "forces.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/smoke.h"
#include "pressure_projection.h"
#include "smoke_workspace.h"

using namespace pliant;
using namespace pliant::smoke;
using json = nlohmann::json;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The 1, 5 and 15 minute load averages: the machines here are shared, so a result
// is only comparable with others taken at a similar load.
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

json machine_info() {
  std::string cpu = "unknown";
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  return {{"nproc", sysconf(_SC_NPROCESSORS_ONLN)},
          {"cpu", cpu},
          {"omp_max_threads", omp_get_max_threads()},
          // libgomp spins at barriers by default; on an oversubscribed machine that
          // makes 2-thread runs many times slower than 1 thread (see the results).
          {"omp_wait_policy", std::getenv("OMP_WAIT_POLICY") ? std::getenv("OMP_WAIT_POLICY") : "default"},
          {"load_average_at_start", load_average()}};
}

// The rising-plume scene of assets/scenes at benchmark resolutions (cubic domain
// of 1.28 m, buoyancy 2, a sphere source with upward velocity, a vortex).
SmokeModel plume(int dim, int n, Advection adv) {
  const double side = 1.28;
  const std::string res = dim == 2 ? "[" + std::to_string(n) + "," + std::to_string(n) + "]"
                                   : "[" + std::to_string(n) + "," + std::to_string(n) + "," + std::to_string(n) + "]";
  const std::string c = dim == 2 ? "[0.64, 0.2]" : "[0.64, 0.2, 0.64]";
  const std::string vc = dim == 2 ? "[0.64, 0.8]" : "[0.64, 0.8, 0.64]";
  const std::string up = dim == 2 ? "[0, 0.5]" : "[0, 0.5, 0]";
  const std::string text = R"({"pliant":1,"kind":"smoke","grid":{"resolution":)" + res +
                           R"(,"cell_size_m":)" + std::to_string(side / n) +
                           R"(},"time":{"dt_s":0.02},"advection":")" +
                           (adv == Advection::Upwind ? "upwind" : "semi_lagrangian") +
                           R"(","buoyancy_m_per_s2":2,"pressure":{"solver":"mgpcg","tolerance":1e-6,"max_iterations":200},
      "sources":[{"shape":"sphere","center_m":)" + c +
                           R"(,"radius_m":0.1,"density_per_s":4,"velocity_m_per_s":)" + up +
                           R"(}],"forces":[{"type":"vortex","center_m":)" + vc +
                           R"(,"radius_m":0.3,"strength_per_s":1.5}]})";
  return smoke_compile(parse_scene(text, "bench_plume"));
}

std::vector<json> results;
void emit(json j) {
  j["bench"] = "smoke_sim";
  std::cout << j.dump() << std::endl;
  results.push_back(std::move(j));
}

// Forward simulation throughput: `warm` frames untimed (fills the plume, first-call
// allocation), then `frames` timed frames (median and mean; phases are totals).
json forward_case(const std::string& name, const SmokeModel& m, int threads, int warm, int frames) {
  omp_set_num_threads(threads);
  SmokeState s = smoke_init(m);
  for (int f = 0; f < warm; ++f) smoke_step(m, s);
  SmokeWorkspace& ws = smoke_workspace(model_grid(m));
  ws.timings = {};
  long long iters = 0;
  StepStats st;
  std::vector<double> frame_s(frames);
  const double t0 = now_s();
  for (int f = 0; f < frames; ++f) {
    const double tf = now_s();
    smoke_step(m, s, &st);
    frame_s[f] = now_s() - tf;
    iters += st.pressure_iterations;
  }
  const double wall = now_s() - t0;
  // The median frame is the headline figure: on a shared machine a few frames that
  // lost their core to another process would otherwise dominate the mean.
  std::sort(frame_s.begin(), frame_s.end());
  const double median = frame_s[frames / 2];
  const double cells = double(model_grid(m).cells());
  const StepTimings& tm = ws.timings;
  return {{"case", name},
          {"threads", threads},
          {"cells", cells},
          {"frames", frames},
          {"wall_s", wall},
          {"cell_steps_per_s", cells * m.substeps / median},
          {"cell_steps_per_s_mean", cells * frames * m.substeps / wall},
          {"ms_per_step", 1e3 * median / m.substeps},
          {"ms_per_step_mean", 1e3 * wall / (frames * m.substeps)},
          {"mean_pressure_iterations", double(iters) / (frames * m.substeps)},
          {"max_divergence_per_s", st.max_divergence},
          {"total_density", st.total_density},
          {"phase_s",
           {{"forces", tm.forces_s},
            {"advect_velocity", tm.advect_velocity_s},
            {"project", tm.project_s},
            {"advect_density", tm.advect_density_s}}}};
}

// Pressure solve on the right-hand side of a real step: a plume is simulated for
// `warm` frames, then buoyancy and self-advection are applied and the divergence of
// that (unprojected) velocity is the rhs both solvers get, from a zero initial guess.
void pressure_case(const std::string& name, const SmokeModel& m, int threads, int warm, int repeats) {
  omp_set_num_threads(threads);
  const MacGrid g = model_grid(m);
  SmokeState s = smoke_init(m);
  for (int f = 0; f < warm; ++f) smoke_step(m, s);
  std::vector<float> u = s.u, v = s.v, w = s.w;
  FaceVelocityMut vel{u.data(), v.data(), g.dim == 3 ? w.data() : nullptr};
  add_buoyancy(g, m.buoyancy_m_per_s2, s.density.data(), m.dt_s, vel);
  FaceVelocityMut src{s.u.data(), s.v.data(), g.dim == 3 ? s.w.data() : nullptr};
  std::copy(u.begin(), u.end(), s.u.begin());
  std::copy(v.begin(), v.end(), s.v.begin());
  std::copy(w.begin(), w.end(), s.w.begin());
  advect_semi_lagrangian_velocity(g, src, m.dt_s, vel);
  std::vector<double> rhs0(g.cells()), rhs(g.cells()), x(g.cells());
  divergence(g, vel, rhs0.data());
  for (double& r : rhs0) r *= -g.h * g.h;
  PoissonSolver solver(g);
  json out{{"case", name}, {"threads", threads}, {"cells", g.cells()}, {"levels", solver.levels()},
           {"tolerance", m.pressure_tolerance}};
  double t_mg = 0, t_j = 0;
  for (PoissonMethod method : {PoissonMethod::MultigridPCG, PoissonMethod::JacobiPCG}) {
    const char* key = method == PoissonMethod::MultigridPCG ? "mgpcg" : "jacobi_pcg";
    PoissonStats st;
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
      rhs = rhs0;
      std::fill(x.begin(), x.end(), 0.0);
      const double t0 = now_s();
      st = solver.solve(method, rhs.data(), x.data(), m.pressure_tolerance, 100000);
      best = std::min(best, now_s() - t0);
    }
    out[key] = {{"iterations", st.iterations}, {"relative_residual", st.relative_residual}, {"time_s", best},
                {"ms_per_iteration", 1e3 * best / std::max(1, st.iterations)}};
    (method == PoissonMethod::MultigridPCG ? t_mg : t_j) = best;
  }
  out["iteration_ratio_jacobi_over_mgpcg"] =
      double(out["jacobi_pcg"]["iterations"].get<int>()) / std::max(1, out["mgpcg"]["iterations"].get<int>());
  out["time_ratio_jacobi_over_mgpcg"] = t_j / t_mg;
  emit(out);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out_path = "bench/results/smoke_sim.json";
  int max_threads = std::min(2, omp_get_num_procs());
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--max-threads" && i + 1 < argc) {
      max_threads = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--out" && i + 1 < argc) {
      out_path = argv[++i];
    } else {
      std::cerr << "usage: bench_smoke_sim [--quick] [--max-threads N] [--out PATH]\n";
      return 2;
    }
  }
  const json machine = machine_info();
  std::cout << json{{"bench", "smoke_sim"}, {"case", "machine"}, {"machine", machine}}.dump() << std::endl;
  const double t_start = now_s();

  // Forward simulation, 1 and 2 threads (speed-up is the ratio of the two rows).
  struct Fwd {
    std::string name;
    int dim, n;
    Advection adv;
    int warm, frames;
  };
  std::vector<Fwd> fwd = {
      {"forward_2d_128_semi_lagrangian", 2, 128, Advection::SemiLagrangian, quick ? 10 : 40, quick ? 10 : 100},
      {"forward_2d_128_upwind", 2, 128, Advection::Upwind, quick ? 10 : 40, quick ? 10 : 100},
      {"forward_3d_64_semi_lagrangian", 3, 64, Advection::SemiLagrangian, quick ? 2 : 10, quick ? 3 : 20},
  };
  for (const Fwd& f : fwd) {
    const SmokeModel m = plume(f.dim, f.n, f.adv);
    json per_thread;
    for (int t = 1; t <= max_threads; ++t) {
      json j = forward_case(f.name, m, t, f.warm, f.frames);
      per_thread[std::to_string(t)] = j["cell_steps_per_s"];
      emit(j);
    }
    if (max_threads > 1)
      emit({{"case", f.name + "_thread_scaling"},
            {"speedup_2_over_1", per_thread["2"].get<double>() / per_thread["1"].get<double>()}});
  }

  // Pressure solver: MGPCG vs Jacobi-PCG, same rhs, same thread count, same tolerance.
  // (--quick: 1 thread only, to stay under a minute on a loaded 2-core machine.)
  for (int t = 1; t <= (quick ? 1 : max_threads); ++t) {
    pressure_case("pressure_2d_128", plume(2, 128, Advection::SemiLagrangian), t, quick ? 20 : 40, quick ? 1 : 3);
    pressure_case("pressure_3d_64", plume(3, 64, Advection::SemiLagrangian), t, quick ? 3 : 10, quick ? 1 : 2);
  }
  if (!quick) pressure_case("pressure_2d_256", plume(2, 256, Advection::SemiLagrangian), max_threads, 40, 1);

  json doc{{"bench", "smoke_sim"}, {"mode", quick ? "quick" : "full"},
           {"machine", machine}, {"load_average_at_end", load_average()},
           {"total_wall_s", now_s() - t_start}, {"cases", results}};
  std::error_code ec;
  const std::filesystem::path p(out_path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  std::ofstream f(out_path);
  if (!f) {
    std::cerr << "bench_smoke_sim: cannot write " << out_path << "\n";
    return 1;
  }
  f << doc.dump(2) << "\n";
  return 0;
}
