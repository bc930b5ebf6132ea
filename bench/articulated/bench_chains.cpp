// Contact-free chains: the dt sweep of PBAD, Euler/RK4 and MuJoCo's integrators (energy drift), cost per step, batched rollouts.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "bench_common.h"

namespace art_bench {

double chain_range(const Model& m, int links, double len) {
  double mass = 0;
  for (const Body& b : m.bodies) mass += b.mass;
  return mass / links * 9.81 * len * links * links / 2.0;
}

State chain_initial(const Model& m, bool tilt) {
  State s = state_init(m);
  if (tilt) s.qpos[0] = 1.3;  // hinge y of the root: 30 degrees from vertical
  s.qvel[1] = tilt ? 0.3 : 0.5;
  return s;
}

SimOptions contact_free_options(Integrator integ, double dt) {
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  o.contact.enabled = false;
  return o;
}

Outcome run_ours(const Model& m, Integrator integ, double dt, double duration, const State& init,
                 double range) {
  const SimOptions o = contact_free_options(integ, dt);
  State s = init;
  SimWorkspace ws;
  Outcome out;
  const double e0 = state_energy(m, o, s, ws).total;
  const int n = static_cast<int>(std::llround(duration / dt));
  for (int i = 0; i < n; ++i) {
    const double t0 = thread_cpu_s();
    StepInfo info;
    const bool ok = sim_step(m, o, s, ws, &info);
    out.wall += thread_cpu_s() - t0;
    out.iterations += info.iterations;
    ++out.steps;
    const double e = ok ? state_energy(m, o, s, ws).total : NAN;
    const double d = std::abs(e - e0) / range;
    if (!std::isfinite(d) || d > 2) {
      out.stable = false;
      out.drift = std::isfinite(d) ? d : INFINITY;
      break;
    }
    out.drift = std::max(out.drift, d);
  }
  out.sim_time = out.steps * dt;
  out.iterations /= std::max(1, out.steps);
  return out;
}

// Stepping only (the matched re-timing): duration / dt steps from init.
Timing time_ours(const Model& m, Integrator integ, double dt, double duration, const State& init) {
  const SimOptions o = contact_free_options(integ, dt);
  State s = init;
  SimWorkspace ws;
  const int n = static_cast<int>(std::llround(duration / dt));
  const double c0 = thread_cpu_s();
  const auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) sim_step(m, o, s, ws);
  return {thread_cpu_s() - c0, std::chrono::duration<double>(Clock::now() - t0).count()};
}

#ifdef PLIANT_HAVE_MUJOCO
mjModel* mujoco_load(const std::string& xml, std::string* error) {
  const auto path = std::filesystem::temp_directory_path() / ("bench_art_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << xml;
  char err[1000] = "";
  mjModel* mm = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  std::filesystem::remove(path);
  if (!mm) *error = err;
  return mm;
}

Outcome run_mujoco(mjModel* mm, const Model& m, int integrator, double dt, double duration,
                   const State& init, double range) {
  mm->opt.integrator = integrator;
  mm->opt.timestep = dt;
  mjData* d = mj_makeData(mm);
  for (int i = 0; i < m.nq; ++i) d->qpos[i] = init.qpos[i];
  for (int i = 0; i < m.nv; ++i) d->qvel[i] = init.qvel[i];
  SimOptions o;
  o.contact.enabled = false;
  SimWorkspace ws;
  State s = init;
  Outcome out;
  const double e0 = state_energy(m, o, s, ws).total;
  const int n = static_cast<int>(std::llround(duration / dt));
  for (int i = 0; i < n; ++i) {
    const double t0 = thread_cpu_s();
    mj_step(mm, d);
    out.wall += thread_cpu_s() - t0;
    ++out.steps;
    for (int k = 0; k < m.nq; ++k) s.qpos[k] = d->qpos[k];
    for (int k = 0; k < m.nv; ++k) s.qvel[k] = d->qvel[k];
    const double e = s.qpos.allFinite() && s.qvel.allFinite() ? state_energy(m, o, s, ws).total : NAN;
    const double dd = std::abs(e - e0) / range;
    if (!std::isfinite(dd) || dd > 2 || d->warning[mjWARN_BADQACC].number > 0) {
      out.stable = false;
      out.drift = std::isfinite(dd) ? dd : INFINITY;
      break;
    }
    out.drift = std::max(out.drift, dd);
  }
  out.sim_time = out.steps * dt;
  mj_deleteData(d);
  return out;
}
#endif

void chain_cases(double duration, const std::vector<int>& link_counts, const std::vector<double>& dts,
                 const std::string& only_case, const std::string& only_methods) {
  // Matched accuracy bookkeeping: best wall per simulated second at drift <= 1%.
  for (const char* chain_case : {"chain_swing", "chain_tilt"}) {
    const bool tilt = std::string(chain_case) == "chain_tilt";
    if (!only_case.empty() && only_case != chain_case) continue;
    for (int links : link_counts) {
      const std::string xml = chain_mjcf(links);
      const Model m = model_from_mjcf(xml, "chain.xml");
      const double range = chain_range(m, links, 0.1);
      const State init = chain_initial(m, tilt);
      // Every run within the drift bound is a candidate for the matched comparison.
      std::vector<std::pair<std::string, double>> candidates;
      auto note = [&](const std::string& method, double dt, const Outcome& o) {
        if (o.stable && o.drift <= 0.01) candidates.emplace_back(method, dt);
      };
      for (double dt : dts) {
        for (Integrator integ :
             {Integrator::Pbad2, Integrator::Pbad3, Integrator::Pbad4, Integrator::Euler, Integrator::Rk4}) {
          if (!only_methods.empty() && only_methods.find(integrator_name(integ)) == std::string::npos) continue;
          const Outcome o = run_ours(m, integ, dt, duration, init, range);
          emit(row(chain_case, integrator_name(integ), links, dt, o));
          note(integrator_name(integ), dt, o);
        }
#ifdef PLIANT_HAVE_MUJOCO
        std::string err;
        mjModel* mm = mujoco_load(xml, &err);
        for (auto [name, integ] : {std::pair{"mujoco_euler", (int)mjINT_EULER}, std::pair{"mujoco_rk4", (int)mjINT_RK4},
                                   std::pair{"mujoco_implicit", (int)mjINT_IMPLICIT}}) {
          if (!only_methods.empty() && only_methods.find("mujoco") == std::string::npos) continue;
          if (!mm) {
            emit({{"case", chain_case}, {"method", name}, {"links", links}, {"dt", dt}, {"refused", true},
                  {"stable", false}, {"error", err}});
            continue;
          }
          const Outcome o = run_mujoco(mm, m, integ, dt, duration, init, range);
          emit(row(chain_case, name, links, dt, o));
          note(name, dt, o);
        }
        if (mm) mj_deleteModel(mm);
#endif
      }
      matched_case(chain_case, links, xml, m, init, duration, candidates);
    }
  }
}

void batched_case(bool quick) {
  const Model m = model_from_mjcf(chain_mjcf(40), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.enabled = false;
  const int trajectories = 100, steps = 10;
  std::vector<double> walls;
  for (int threads : {1, omp_get_num_procs()}) {
    double best = 1e300;
    int passes = 0;
    for (int rep = 0; rep < (quick ? 1 : 3); ++rep) {
      std::vector<State> states(trajectories);
      for (int t = 0; t < trajectories; ++t) {
        states[t] = chain_initial(m, true);
        states[t].qvel[1] = 0.3 + 0.01 * t;  // every trajectory different
      }
      const auto t0 = Clock::now();
      passes = batch_rollout(m, o, states, steps, threads);
      best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    walls.push_back(best);
    emit({{"case", "batched_rollouts"}, {"method", "pbad3"}, {"links", 40}, {"dt", o.dt},
          {"trajectories", trajectories}, {"steps", steps}, {"threads", threads}, {"wall_s", best},
          {"passes", passes}, {"trajectory_steps_per_s", trajectories * steps / best},
          {"speedup_vs_1_thread", walls.front() / best}});
  }
}

// Cost per step from 10 to 100 links at dt 0.05 (issue 6: within 1.5x of linear):
// thread CPU time of 10 s of stepping, fastest of 3 repeats.
void cost_per_step_case() {
  // pbad4 only on the smooth swing: it does not survive the 40/100-link whip (README).
  for (auto [chain_case, integ] : {std::pair{"chain_tilt", Integrator::Pbad3}, std::pair{"chain_swing", Integrator::Pbad3},
                                   std::pair{"chain_tilt", Integrator::Pbad4}}) {
    const bool tilt = std::string(chain_case) == "chain_tilt";
    double per_step[2] = {0, 0}, iterations[2] = {0, 0};
    const int links[2] = {10, 100};
    for (int k = 0; k < 2; ++k) {
      const Model m = model_from_mjcf(chain_mjcf(links[k]), "chain.xml");
      const State init = chain_initial(m, tilt);
      double best = 1e300;
      for (int rep = 0; rep < 3; ++rep) best = std::min(best, time_ours(m, integ, 0.05, 10.0, init).cpu);
      per_step[k] = best / 200;
      iterations[k] = run_ours(m, integ, 0.05, 10.0, init, chain_range(m, links[k], 0.1)).iterations;
    }
    emit({{"case", "cost_per_step"}, {"chain", chain_case}, {"method", integrator_name(integ)}, {"dt", 0.05},
          {"us_per_step_10", 1e6 * per_step[0]}, {"us_per_step_100", 1e6 * per_step[1]},
          {"lm_iterations_10", iterations[0]}, {"lm_iterations_100", iterations[1]},
          {"ratio_vs_linear", per_step[1] / per_step[0] / 10}, {"load_average", load_average()},
          {"timing", "thread CPU time, fastest of 3 runs of 200 steps"}});
  }
}

}  // namespace art_bench
