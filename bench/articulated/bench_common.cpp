// bench_articulated's shared pieces: emitted rows, thread CPU clock, load, the chain row, timed rollouts.
#include "bench_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

namespace art_bench {

nlohmann::json g_results = nlohmann::json::array();
std::string g_machine;

void emit(nlohmann::json j) {
  j["machine"] = g_machine;
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  g_results.push_back(std::move(j));
}

double thread_cpu_s() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double load_average() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1;
}

nlohmann::json row(const std::string& c, const std::string& method, int links, double dt, const Outcome& o) {
  nlohmann::json j = {{"case", c},
                      {"method", method},
                      {"links", links},
                      {"dt", dt},
                      {"energy_drift", std::isfinite(o.drift) ? nlohmann::json(o.drift) : nlohmann::json("inf")},
                      {"stable", o.stable},
                      {"wall_per_sim_s", o.sim_time > 0 ? o.wall / o.sim_time : 0.0},  // thread CPU time
                      {"wall_per_step_us", o.steps > 0 ? 1e6 * o.wall / o.steps : 0.0},
                      {"simulated_s", o.sim_time}};
  if (method.rfind("pbad", 0) == 0) j["lm_iterations_per_step"] = o.iterations;
  return j;
}

TimedRollout timed_rollout(const Model& m, const SimOptions& o, const State& initial, int steps, int reps) {
  TimedRollout t;
  for (int rep = 0; rep < reps; ++rep) {
    State s = initial;
    SimWorkspace ws;
    double cpu = 0;
    t.iterations = t.max_iterations = t.contacts = t.pair_contacts = t.max_pair_depth = 0;
    for (int i = 0; i < steps; ++i) {
      StepInfo info;
      const double t0 = thread_cpu_s();
      sim_step(m, o, s, ws, &info);
      cpu += thread_cpu_s() - t0;
      t.iterations += info.iterations;
      t.max_iterations = std::max<double>(t.max_iterations, info.iterations);
      t.contacts += ws.contacts.size();
      t.pair_contacts += ws.pair_contacts.size();
      for (const PairContact& c : ws.pair_contacts) t.max_pair_depth = std::max(t.max_pair_depth, c.depth);
    }
    t.cpu_s = std::min(t.cpu_s, cpu);
    t.final = s;
  }
  return t;
}

}  // namespace art_bench
